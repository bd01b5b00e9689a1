/* The shared shadow-map layer (DESIGN.md §5): the light's frustum, and the
 * products techniques sample, keyed by product, not by technique (STYLE.md
 * item 5). Each product is rendered once per light pose and shared by every
 * technique of a run. */
#ifndef SB_SHADOWMAP_H
#define SB_SHADOWMAP_H

#include "gl/gl.h"
#include "gl/scene_mesh.h"
#include "scene/light_frustum.h"
#include "scene/scene.h"
#include "technique.h"

#include <stdbool.h>

/* std140 mirror of `uniform ShadowMapBlock` in shaders/shadow_block.glsl.
 * Keep in sync with it. */
struct shadowmap_block {
    float light_view_proj[16];
    float light_view[16];
    float light_pos_world[4];     /* xyz: light centre */
    float light_dir_world[4];     /* xyz: emit direction (the light's -Z) */
    float light_size_uv[2];       /* at the near plane */
    float texel_size_uv[2];       /* 1 / map size */
    float near_window_world[2];   /* r - l, t - b */
    float near_world, far_world;  /* planar depth range */
    float map_size_texels;
    int sat_format;               /* enum sat_format of the current SAT */
    float sat_scale;              /* SAT_INT32: fixed-point units per 1.0 of depth */
    float sat_max_box_texels;     /* SAT_INT32: widest box whose sums fit in 32 bits */
};
/* std140: scalars pack at 4 bytes, the block ends on a 16-byte boundary. */
_Static_assert(sizeof(struct shadowmap_block) == 208, "std140 layout of ShadowMapBlock");
_Static_assert(offsetof(struct shadowmap_block, light_size_uv) == 160, "std140 layout");
_Static_assert(offsetof(struct shadowmap_block, near_world) == 184, "std140 layout");

/* Zero means default (sokol style); shadowmap_create fills the defaults. */
struct shadowmap_desc {
    int size_texels;  /* square map, default 1024, [16, 8192] */
};

#define SHADOWMAP_DEFAULT_SIZE 1024
#define SHADOWMAP_MAX_BLUR_RADIUS 32  /* BLUR_MAX_RADIUS in shaders/moments_blur.frag */

struct shadowmap {
    struct shadowmap_desc desc;       /* filled */
    struct light_frustum frustum;
    struct shadowmap_block block;     /* as last uploaded to ubo */
    unsigned current;                 /* SM_* products valid for this light pose ... */
    struct shadowmap_request made;    /* ... rendered with these options */
    GLuint ubo;
    GLuint depth_texture, depth_fbo, depth_program, compare_sampler;
    GLuint moments, moments_temp;     /* RG32F; `moments` is filtered and mipmapped */
    GLuint moments_fbo, temp_fbo;     /* rendering into level 0 of each */
    GLuint fullscreen_vao;            /* empty: the full-screen passes need none */
    GLuint blur_rows_program, blur_columns_program;
    GLuint sat_rows_program, sat_columns_program;
    GLuint sat_buffer;                /* (N+1)^2 uvec2 */
};

/* Fits the frustum to s and creates the depth product's GL objects.
 * Returns 0 or -1 (logged). */
int shadowmap_create(struct shadowmap *sm, const struct scene *s, const struct shadowmap_desc *desc);

/* Creates what the products of r need (textures, buffers, programs), so
 * rendering them later does no set-up work. Returns 0 or -1 (logged). */
int shadowmap_prepare(struct shadowmap *sm, const struct shadowmap_request *r);

/* Renders one product of r unconditionally (the harness times this call);
 * SM_MOMENTS and SM_MOMENTS_SAT read the current depth product. */
void shadowmap_render_product(struct shadowmap *sm, const struct scene_mesh *mesh,
                              enum shadowmap_product product, const struct shadowmap_request *r);

/* Do requests a and b ask for the same product p (same options)? */
bool shadowmap_same_product(enum shadowmap_product p, const struct shadowmap_request *a,
                            const struct shadowmap_request *b);

/* Makes every product of r current with r's options, rendering only what
 * is missing or was made with other options. Needs shadowmap_prepare(r). */
void shadowmap_require(struct shadowmap *sm, const struct scene_mesh *mesh,
                       const struct shadowmap_request *r);

/* Binds the uniform block (binding 0), the product textures and the SAT
 * buffer to the units shaders/shadow_common.glsl and sat.glsl declare. */
void shadowmap_bind(const struct shadowmap *sm);

/* The SAT_INT32 fixed-point scale (units per 1.0 of depth) and the widest
 * box side in texels it allows, for a request on an n x n map. The scale is
 * 2^k with k = 30 - floor(log2(largest box area the reader forms)), so
 * every box sum stays below 2^31. */
void shadowmap_sat_int32_scale(const struct shadowmap_request *r, int n, float *scale,
                               float *max_box_texels);

/* Accepts a half-built map. */
void shadowmap_destroy(struct shadowmap *sm);

#endif
