/* Writes shadowbench scenes as glTF 2.0 with an embedded buffer: the
 * triangles as one node named "geometry", or one named node per part, a
 * perspective camera and an area light or the sun, each placed by a look-at. Used by tools/make_scenes.c (the shipped scenes) and by the tests
 * (scenes generated on the fly, e.g. the closed-form parallel planes). */
#ifndef SB_GLTF_WRITER_H
#define SB_GLTF_WRITER_H

#include "scene/scene.h"

#include <stddef.h>
#include <stdint.h>

#define MESH_MAX_PARTS 8

struct mesh_builder {
    float *positions;
    uint32_t *indices;
    size_t vertex_count, index_count;
    /* Named parts, each a node of its own (what a caster motion moves):
     * part i is what was added from its mesh_begin_part to the next. */
    int part_count;
    struct mesh_part {
        const char *name;  /* not copied */
        size_t first_vertex, first_index;
    } parts[MESH_MAX_PARTS];
};

/* Starts a part: what is added from now on is the node `name`. Before the
 * first call (or without one) everything is the node "geometry". */
void mesh_begin_part(struct mesh_builder *m, const char *name);

/* Returns the new vertex's index. */
uint32_t mesh_add_vertex(struct mesh_builder *m, struct vec3 p);
void mesh_add_index(struct mesh_builder *m, uint32_t i);
void mesh_add_triangle(struct mesh_builder *m, struct vec3 a, struct vec3 b, struct vec3 c);
/* Parallelogram corner, corner + u, corner + u + v, corner + v. */
void mesh_add_quad(struct mesh_builder *m, struct vec3 corner, struct vec3 u, struct vec3 v);
void mesh_add_box(struct mesh_builder *m, struct vec3 lo, struct vec3 hi);
void mesh_add_sphere(struct mesh_builder *m, struct vec3 centre, float radius, int segments);
/* A torus around the +y axis through centre: major radius to the tube's
 * centre, minor radius of the tube. */
void mesh_add_torus(struct mesh_builder *m, struct vec3 centre, float major, float minor,
                    int major_segments, int minor_segments);
void mesh_free(struct mesh_builder *m);

struct gltf_scene_desc {
    const char *description, *shows;
    struct vec3 camera_pos, camera_target;
    float camera_yfov_rad, camera_znear;
    struct vec3 light_pos, light_target;  /* the light faces its target */
    int light_disk;                       /* 0: rect width x height, 1: disk of radius */
    float light_width, light_height, light_radius;
    double sun_angular_diameter_deg;      /* > 0: the light is this sun (KHR_lights_punctual), shining
                                             from light_pos towards light_target; size and shape unused */
    const char *const *motions;           /* extras.shadowbench.motions, NULL-terminated, or NULL */
};

/* Returns 0 or -1 (logged). */
int gltf_write(const char *path, const struct mesh_builder *m, const struct gltf_scene_desc *d);

#endif
