/* The light's frustum (docs/design.md §5): the perspective projection of the
 * shadow map, fitted to the scene. Pure math, no GL: the ground truth uses it
 * for its mask, the shadow-map layer for its projection, techniques for the
 * sizes they derive from the light. */
#ifndef SB_LIGHT_FRUSTUM_H
#define SB_LIGHT_FRUSTUM_H

#include "scene.h"

#include <stdbool.h>
#include <stddef.h>

/* Widest half-angle of the light frustum: geometry beyond it is outside the
 * map (and unscored), as an engine's fixed-FOV spot shadow would be. */
#define LIGHT_FRUSTUM_MAX_HALF_ANGLE_DEG 75.0

/* An area light's: the perspective frustum from the light centre along the
 * light's -Z, fitted to the scene geometry in front of the light. The
 * sun's (sun true): an orthographic box along the sun, fitted to what the
 * camera can see and every caster between it and the sun. */
struct light_frustum {
    struct mat4 view;             /* world -> light space */
    struct mat4 view_proj;        /* world -> clip, reversed Z in [0, 1] */
    float near_world, far_world;  /* planar depth range of the geometry */
    float l, r, b, t;             /* window at the near plane (the sun's: at every depth), light space */
    float light_size_uv[2];       /* light size in shadow-map UV at the near plane; the sun's:
                                     its cone's width in UV per world unit of depth, 2 tan(alpha) / window */
    int sun;                      /* 1: orthographic (an int: the struct is hashed, no padding) */
};
_Static_assert(sizeof(struct light_frustum) == 2 * sizeof(struct mat4) + 8 * sizeof(float) + sizeof(int),
               "light_frustum is hashed as bytes: no padding");

/* Fits f to s, whose images are aspect = width / height (the sun's map
 * covers the camera's view). Returns 0, or -1 after logging when nothing is
 * in front of the light (the camera, for the sun). */
int light_frustum_fit(const struct scene *s, float aspect, struct light_frustum *f);

/* Fits near and far to s, and keeps window's angular window (its l/near,
 * r/near, b/near, t/near): the map's texel grid attached to the light, as a
 * spot light's shadow map moves with it, rather than refitted to the
 * scene's bounds (which holds the grid still on the scene). The sun's
 * window is kept as it is, in its own frame's world units. Returns 0 or
 * -1 (logged). */
int light_frustum_fit_window(const struct scene *s, float aspect, const struct light_frustum *window,
                             struct light_frustum *f);

/* Pulls the near plane towards the light: near / k (k >= 1), far kept, the
 * same cone (the window scales with near); the sun's, its depth range k
 * times as deep towards it, the window kept. What an engine with a fixed,
 * too-small near plane does: the scene's depths then fill less of [near,
 * far] (`shadowbench stability --vary depth_range`). */
void light_frustum_widen(struct light_frustum *f, const struct scene *s, float k);

/* The side in texels of an n x n map of the widest PCSS blocker-search box
 * (shaders/pcss_geometry.glsl) for the light scaled by light_size_scale:
 * a receiver's on the far plane, light_size_uv * (1 - near/far) (the sun's:
 * light_size_uv * (far - near)). A
 * summed-area table's int32 scale is set by it. */
float light_frustum_search_box_texels(const struct light_frustum *f, float light_size_scale, int n);

/* The world size of one texel of an n x n map at planar depth d. */
float light_frustum_texel_world(const struct light_frustum *f, int n, float d);

/* Is the world point inside the frustum (and so covered by the map)? */
bool light_frustum_inside(const struct light_frustum *f, struct vec3 p);

#endif
