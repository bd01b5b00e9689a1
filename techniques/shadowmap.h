/* The shared shadow-map layer (docs/design.md §5): the products techniques sample,
 * keyed by product, not by technique (STYLE.md item 5). A product is a row
 * of the table in shadowmap.c (its texture format or buffer, its binding,
 * its passes, its GLSL sampler) plus its shaders; the layer renders each
 * requested product once per light pose and set of options for the cells
 * that score it, and afresh for every timed frame.
 *
 * Edge policy, one for every product and every read (docs/design.md §5):
 * clamp-to-edge, i.e. past the map's edge the map continues as its edge
 * texels. The light frustum is fitted to all the geometry with a 1% margin
 * (scene/light_frustum.c), so where everything fits the edge texels are
 * empty (far) and a read past them is lit, which is right; where geometry
 * crosses the edge (the frustum's half-angle is capped at 75 degrees, as in
 * scenes/map_border), the edge texels carry on what crosses it, the best
 * guess the map alone gives. And it is one definition that the texture
 * unit gives texture() reads (GL_CLAMP_TO_EDGE), that a texelFetch gets by
 * clamping its coordinate to [0, size - 1], and that SAT boxes reproduce
 * exactly (shaders/sat.glsl). tests/test_edge_policy.c checks it. */
#ifndef SB_SHADOWMAP_H
#define SB_SHADOWMAP_H

#include "technique.h"
#include "base/util.h"
#include "gl/gl.h"
#include "gl/scene_mesh.h"
#include "scene/light_frustum.h"
#include "scene/scene.h"

#include <stdbool.h>

/* The summed-area tables' fields of the block, one slot per SAT product in
 * the order of the product table (SM_SAT_SLOT_<ID> in GLSL), so that two
 * tables coexist in one request; the layer refuses to start when the table
 * holds another number of them. std140 mirror of `struct SmSatTable` in
 * shaders/shadow_block.glsl. */
#define SM_SAT_TABLES 2
struct shadowmap_sat_block {
    int format;            /* enum sat_format */
    float scale;           /* SAT_INT32: fixed-point units per 1.0 of depth */
    float max_box_texels;  /* SAT_INT32: widest box whose sums fit in 32 bits */
    float pad_;            /* std140: a struct in an array takes 16 bytes */
};

/* std140 mirror of `uniform ShadowMapBlock` in shaders/shadow_block.glsl.
 * Keep in sync with it. */
struct shadowmap_block {
    float light_view_proj[16];
    float light_view[16];
    float light_pos_world[4];     /* w 1: xyz the light centre; w 0: xyz the direction to the sun */
    float light_dir_world[4];     /* xyz: emit direction (the light's -Z) */
    float light_size_uv[2];       /* at the near plane */
    float texel_size_uv[2];       /* 1 / map size */
    float near_window_world[2];   /* r - l, t - b */
    float near_world, far_world;  /* planar depth range */
    float map_size_texels;
    float pad_[3];                /* std140: the array below starts on 16 bytes */
    struct shadowmap_sat_block sat[SM_SAT_TABLES];
};
/* std140: scalars pack at 4 bytes, a struct array starts on a 16-byte boundary. */
_Static_assert(sizeof(struct shadowmap_block) == 240, "std140 layout of ShadowMapBlock");
_Static_assert(offsetof(struct shadowmap_block, light_size_uv) == 160, "std140 layout");
_Static_assert(offsetof(struct shadowmap_block, near_world) == 184, "std140 layout");
_Static_assert(offsetof(struct shadowmap_block, sat) == 208, "std140 layout");
_Static_assert(sizeof(struct shadowmap_sat_block) == 16, "std140 layout of SmSatTable");

#define SHADOWMAP_DEFAULT_SIZE 1024
#define SHADOWMAP_MIN_SIZE 16
#define SHADOWMAP_MAX_SIZE 8192

/* Zero means default (sokol style); shadowmap_create fills the defaults. */
struct shadowmap_desc {
    int size_texels;   /* square map, [SHADOWMAP_MIN_SIZE, SHADOWMAP_MAX_SIZE] */
    float near_scale;  /* >= 1: the fitted near plane pulled in to near / near_scale
                          (light_frustum_widen); default 1 */
    float aspect;      /* width / height of the images it serves (the sun's map is fitted to the
                          camera's view); default 1 */
    const struct light_frustum *frustum;  /* NULL: fitted to the scene (light_frustum_fit); else this
                                             one (a cascade's), copied */
    int depth_clamp;   /* the depth pass clamps what is in front of the near plane onto it (GL_DEPTH_CLAMP:
                          pancaking) */
};

/* One product's GL objects: the product itself (a texture or a storage
 * buffer) and what its passes need. shadowmap_destroy deletes what is set. */
struct shadowmap_product {
    GLuint texture;                 /* the product, when a texture */
    GLuint buffer;                  /* the product, when a storage buffer */
    GLuint temp_texture;            /* an intermediate, e.g. a separable filter's first pass */
    GLuint framebuffers[2];
    GLuint programs[2];
    bool created;                   /* the objects above exist (shadowmap_prepare) */
    bool current;                   /* holds this pose's product for the options of `made` */
    struct shadowmap_request made;  /* the request it was last rendered for */
};

struct shadowmap {
    struct shadowmap_desc desc;    /* filled */
    struct light_frustum frustum;
    struct shadowmap_block block;  /* as last uploaded to ubo */
    GLuint ubo;
    GLuint compare_sampler;        /* hardware comparison (sampler2DShadow) of depth products */
    GLuint fullscreen_vao;         /* empty: the full-screen passes need none */
    GLuint blue_noise;             /* RG32F, TAP_BLUE_NOISE_SIDE^2: rotation=blue_noise's tiles */
    struct shadowmap_product products[SM_PRODUCT_COUNT];  /* by SM_PRODUCT_* */
};

/* Fits the frustum to s and creates what every product shares (the uniform
 * block, the comparison sampler, the blue-noise texture). Returns 0 or -1
 * (logged). */
int shadowmap_create(struct shadowmap *sm, const struct scene *s, const struct shadowmap_desc *desc);

/* Sets the frustum to f (a cascade refitted to s in another pose) and
 * uploads the uniform block; the products are rendered afresh by the next
 * frame. */
void shadowmap_set_frustum(struct shadowmap *sm, const struct scene *s, const struct light_frustum *f);

/* Appends the #defines that the layer's shaders and the receiver pass share
 * with C, all from the product table and the enums: the products'
 * indices (SM_PRODUCT_<ID>), bindings (SM_BINDING_<ID>, _BLOCK,
 * _PASS_SOURCE), samplers (SM_PRODUCT_SAMPLERS, the declarations of every
 * texture product's) and SAT slots (SM_SAT_SLOT_<ID>, SM_SAT_TABLES), the
 * vertex attributes (SM_ATTRIB_*), the light shapes (SM_LIGHT_<SHAPE>), the
 * SAT formats (SM_SAT_<FORMAT>), SM_MAX_BLUR_RADIUS and the tap loops
 * SM_UNROLL_<n> for n in TAP_COUNTS and 0. */
void shadowmap_shader_defines(struct strbuf *out);

/* Texels read and written per frame by the passes that build product p
 * (not the depth pass, 0) for request r: the blurs, the SAT scans, the
 * mip chains, counted from the passes' shaders (docs/metrics.md:
 * prep_texels). */
double shadowmap_prep_texels(const struct shadowmap *sm, int p, const struct shadowmap_request *r);

/* The texture unit a full-screen pass reads its input from (GLSL:
 * SM_BINDING_PASS_SOURCE; a second input the unit after it). */
enum { SHADOWMAP_PASS_SOURCE_UNIT = 0 };

/* The first texture unit past the products' and the blue-noise texture's
 * (GLSL: SM_BINDING_SCREEN): where a receiver pass finds a screen-space
 * stage's input (the penumbra mask). */
int shadowmap_screen_binding(void);

/* The texture of rotation=blue_noise (GLSL: SM_BINDING_BLUE_NOISE,
 * sm_blue_noise): shaders/blue_noise.png's two tiles (tools/blue_noise.c)
 * as the R and G of a RG32F texture, texel value (rank + 0.5) / 4096.
 * Returns it, or 0 (logged) if the file is missing or malformed. */
GLuint shadowmap_blue_noise_create(void);

/* Its texture unit, the first past the products' (SM_BINDING_BLUE_NOISE). */
int shadowmap_blue_noise_binding(void);

/* Creates what the products of r need (textures, buffers, programs), so
 * rendering them later does no set-up work, and checks r's options.
 * Returns 0 or -1 (logged). */
int shadowmap_prepare(struct shadowmap *sm, const struct shadowmap_request *r);

/* Renders product p (SM_PRODUCT_*) with r's options (NULL: the defaults,
 * for a product that has none), unconditionally (the
 * harness times this call: a timed frame renders its products afresh);
 * the products past depth read the current depth. */
void shadowmap_render_product(struct shadowmap *sm, const struct scene_mesh *mesh, int p,
                              const struct shadowmap_request *r);

/* Renders product p for r unless it holds it already: rendered in this
 * pose for a request that its row says gives the same product (an untimed
 * frame, for scoring: the cells of a pose share their products). Returns
 * whether it rendered. */
bool shadowmap_ensure_product(struct shadowmap *sm, const struct scene_mesh *mesh, int p,
                              const struct shadowmap_request *r);

/* The pose changed (the geometry moved): no product is current.
 * shadowmap_set_frustum calls it; so must a caller that moves the mesh
 * without refitting. */
void shadowmap_invalidate(struct shadowmap *sm);

/* The block's fields of summed-area table product p (SM_PRODUCT_MOMENTS_SAT,
 * SM_PRODUCT_MSM_SAT): its slot; NULL for a product that is no table. */
struct shadowmap_sat_block *shadowmap_sat_fields(struct shadowmap *sm, int p);

/* Binds the uniform block and every product to the bindings the shaders
 * name (SM_BINDING_*). */
void shadowmap_bind(const struct shadowmap *sm);

/* Accepts a half-built map. */
void shadowmap_destroy(struct shadowmap *sm);

#endif
