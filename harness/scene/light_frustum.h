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

/* Cascaded shadow maps for the sun (docs/cascades.md): the camera's view
 * cut by view depth into slices, each covered by its own orthographic map.
 * The split schemes: X(ID, name). */
#define CASCADES_MAX 8
#define CASCADE_SPLITS(X)                                                                    \
    X(PRACTICAL, "practical") /* lambda log + (1 - lambda) uniform (Zhang et al. 2006, PSSM) */ \
    X(UNIFORM, "uniform")     /* equal steps of view depth */                                 \
    X(LOG, "log")             /* equal ratios from the camera's near plane */                 \
    X(FRACTIONS, "fractions") /* given: each split's depth as a fraction of the distance */

enum cascade_split {
#define X(id, name) CASCADE_SPLIT_##id,
    CASCADE_SPLITS(X)
#undef X
};
extern const char *const cascade_split_names[];  /* by enum value, NULL-terminated */

enum cascade_fit { CASCADE_FIT_BOX, CASCADE_FIT_SPHERE };
enum cascade_width { CASCADE_WIDTH_WORLD, CASCADE_WIDTH_TEXEL };

/* The shared layer's cascade settings (the run's, recorded with every
 * cell). Zero is one map over the whole view, fitted to what the camera
 * sees: Filament's default (one cascade, shadowFar 0 = the view's far
 * end, no stable fit). */
struct cascade_settings {
    int count;                          /* 1..CASCADES_MAX; 0: 1 */
    enum cascade_split split;
    float lambda;                       /* PRACTICAL: the log scheme's share, [0, 1] */
    float fractions[CASCADES_MAX - 1];  /* FRACTIONS: the count - 1 splits, increasing in (0, 1) */
    float shadow_distance;              /* world units: the last slice's far end; 0: the farthest
                                           point the camera sees. Past it is unshadowed and unscored */
    enum cascade_fit fit;               /* BOX: each map fitted to the geometry its slice sees
                                           (Filament); SPHERE: to its slice's bounding sphere, a size
                                           that turning the camera does not change (Unity's stable fit) */
    int snap;                           /* the window moved in whole texels (Godot, Unity) */
    float blend;                        /* the band at a slice's far end where the next fades in, as a
                                           fraction of the slice, [0, 0.5] (Unity HDRP's border) */
    int depth_clamp;                    /* near plane at the slice's receivers, casters in front of it
                                           clamped onto it (pancaking, Unity) */
    enum cascade_width width;           /* WORLD: the PCSS family's sizes from the sun's angle in each
                                           map's own world units (HDRP); TEXEL: cascade 0's ratio on
                                           each map's normalised depth (most engines) */
};

/* The slices' view depths z[0..n] (n = the count): z[0] the camera's near
 * plane, z[n] the shadow distance (s's farthest visible depth when 0; with
 * one slice and no distance, INFINITY: the whole view, as
 * light_frustum_fit). Returns n, or -1 after logging when the camera sees
 * nothing or the splits do not increase. */
int light_frustum_splits(const struct scene *s, float aspect, const struct cascade_settings *cs, float *z);

/* The width of the band at the far end of slice c, where slice c + 1
 * fades in (view depth units; 0 for the last). */
float light_frustum_band(const struct cascade_settings *cs, const float *z, int c);

/* Fits cascade c of an n x n map to s: its slice of view depth, from
 * z[c] (less the band of slice c - 1, which it also covers) to z[c + 1].
 * With zero settings and c 0 the same as light_frustum_fit. Returns 0 or -1
 * (logged). */
int light_frustum_fit_cascade(const struct scene *s, float aspect, const struct cascade_settings *cs,
                              const float *z, int c, int n, struct light_frustum *f);

/* After a fit of f (near and far fitted anew), keeps window's angular
 * window (its l/near, r/near, b/near, t/near): the map's texel grid
 * attached to the light, as a spot light's shadow map moves with it,
 * rather than refitted to the scene's bounds (which holds the grid still
 * on the scene). The sun's window is kept as it is, in its own frame's
 * world units. */
void light_frustum_set_window(struct light_frustum *f, const struct scene *s, const struct light_frustum *window);

/* `--cascade-width texel`: f's light size in uv set so that a depth
 * difference, in f's normalised depth, gives the penumbra it gives in
 * first's (cascade 0's): light_size_uv = first's * first's depth range /
 * f's. What an engine gets that takes the PCSS ratio on each cascade's
 * normalised depth with one constant. */
void light_frustum_texel_ratio(struct light_frustum *f, const struct light_frustum *first);

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

/* The tangent of the half-angle of the smallest cone about an area
 * light's axis (its -z) that holds every point of s inside f's window in
 * front of its near plane: the cone an engine's symmetric spot frustum
 * needs to cover what shadowbench's fitted one covers (docs/engines.md). */
float light_frustum_cone_tan(const struct scene *s, const struct light_frustum *f);

/* The farthest view depth at which the camera sees s's geometry, for
 * images of the given aspect (the sun's fit's reach); -1 when it sees
 * none. */
float light_frustum_view_far(const struct scene *s, float aspect);

#endif
