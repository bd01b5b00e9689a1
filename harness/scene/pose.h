/* A scene in another pose: its light moved, turned or scaled, its camera
 * moved, one of its nodes moved (`shadowbench stability`: motions and
 * sensitivities). A posed scene shares the base scene's arrays, except
 * positions when a node moved: free it with scene_unpose, never scene_free. */
#ifndef SB_POSE_H
#define SB_POSE_H

#include "scene.h"

/* Zero is the base pose. */
struct scene_pose {
    float light_shift;     /* the light moved along its own x axis, world units */
    float light_turn_rad;  /* the light turned about its own y axis, through its centre */
    float camera_shift;    /* the camera moved along its own x axis, world units */
    float light_scale;     /* the light's size times this (0: 1): width, height, radius, the sun's angle */
    int caster;            /* 1 + the index in nodes of a node moved (0: none) */
    float caster_shift;    /* that node moved along the light's x axis, world units */
    float camera_yaw_rad;  /* the camera turned about its own y axis */
};

/* The viewer's pose (`shadowbench view`), relative to the scene's. Zero is
 * the scene's own pose, bit for bit. */
struct scene_orbit {
    float light_dx, light_dy;  /* the light along its own x and y, world units (the sun: turned
                                  towards that point a scene's extent along it) */
    float yaw, pitch, dolly;   /* the camera's orbit (radians) and log distance */
};

/* base with its light moved in its plane and its camera orbiting the point
 * of its axis nearest the scene's centre (yaw about the world's up, then
 * pitch) and dollied towards or away from it; extent: the scene's size.
 * Shares base's arrays. */
struct scene scene_orbited(const struct scene *base, const struct scene_orbit *o, float extent);

/* base in pose p: the light and camera moved, the geometry shared (or its
 * positions copied and a node moved: p->caster), and a hash of its own
 * (the ground-truth cache key). */
void scene_posed(const struct scene *base, const struct scene_pose *p, struct scene *out);

/* Frees what scene_posed gave posed of its own (moved positions). */
void scene_unpose(struct scene *posed, const struct scene *base);

/* The index in s->nodes of the node named name, or -1 (none, or more than
 * one of that name: *count, when given, says how many). */
int pose_find_node(const struct scene *s, const char *name, int *count);

/* The planar depth from the light of the centre of node's bounds. */
float pose_light_depth_of_node(const struct scene *s, int node);

/* The planar depth from the light of the centre of s's bounds. */
float pose_light_depth_of_centre(const struct scene *s);

/* The world size of one pixel of an image height pixels high at the depth
 * of the centre of s's bounds from the camera. */
float pose_pixel_world(const struct scene *s, int height);

#endif
