#include "shadowmap.h"
#include "base/log.h"
#include "gl/shader.h"
#include "base/image.h"
#include "base/util.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The uniform block's binding (GLSL: SM_BINDING_BLOCK). */
enum { BLOCK_BINDING = 0, PASS_SOURCE_BINDING = SHADOWMAP_PASS_SOURCE_UNIT };

/* One product: how it is stored, where shaders find it, how it is made.
 * Its name is SM_PRODUCTS'; its binding follows from its place in the
 * table (binding_of). */
struct product_kind {
    GLenum format;         /* a texture product's internal format; 0: a storage buffer */
    bool mipmapped;        /* texture: a full mip chain, sampled trilinearly */
    const char *sampler;   /* texture: its GLSL sampler2D (SM_PRODUCT_SAMPLERS declares it) */
    const char *compare_sampler;  /* texture: also a sampler2DShadow through the comparison sampler
                                     (SM_BINDING_<ID>_COMPARE), or NULL */
    int sat_channels;      /* a summed-area table by sat_build.comp: its SAT_CHANNELS (2 or 4); its
                              fields in the block: sm.sat[sat_slot_of] */
    /* What the passes need beyond a texture product's texture (framebuffers,
     * programs; a buffer product's buffer): called once. Returns 0 or -1
     * (logged); what it made before failing is deleted with the rest. */
    int (*create)(struct shadowmap *sm, struct shadowmap_product *p);
    void (*render)(struct shadowmap *sm, struct shadowmap_product *p, const struct scene_mesh *mesh,
                   const struct shadowmap_request *r);
    /* Optional: 0, or -1 (logged) when r's options are beyond the product. */
    int (*check)(const struct shadowmap_request *r);
    /* Optional: whether requests a and b give the same product (their
     * options agree); without it every request does (no options). */
    bool (*same)(const struct shadowmap_request *a, const struct shadowmap_request *b);
};

static const struct product_kind kinds[SM_PRODUCT_COUNT];

/* Product p's binding: texture products take texture units in table order
 * (a comparison sampler the unit after its texture's), storage-buffer
 * products storage bindings in table order. */
static int binding_of(int p)
{
    int unit = 0, buffer = 0;
    for (int i = 0; i < p; i++)
        if (kinds[i].format)
            unit += kinds[i].compare_sampler ? 2 : 1;
        else
            buffer++;
    return kinds[p].format ? unit : buffer;
}

/* Summed-area table p's slot of the block: the SAT products in table order. */
static int sat_slot_of(int p)
{
    int slot = 0;
    for (int i = 0; i < p; i++)
        slot += kinds[i].sat_channels > 0;
    return slot;
}

static const char *const product_ids[] = {
#define X(id, name) #id,
    SM_PRODUCTS(X)
#undef X
};

static const char *const product_names[] = {
#define X(id, name) name,
    SM_PRODUCTS(X)
#undef X
};

/* "shadow map: <product>": the label of a product's own GL object. */
static void label_product(GLenum type, GLuint object, int p)
{
    char *label = util_printf("shadow map: %s", product_names[p]);
    gl_label(type, object, label);
    free(label);
}

/* ---- helpers ------------------------------------------------------------ */

static void fill_block(struct shadowmap *sm, const struct scene *s)
{
    const struct light_frustum *f = &sm->frustum;
    struct shadowmap_block *b = &sm->block;
    memset(b, 0, sizeof *b);
    memcpy(b->light_view_proj, f->view_proj.m, sizeof b->light_view_proj);
    memcpy(b->light_view, f->view.m, sizeof b->light_view);
    /* homogeneous: the area light's centre (w 1), the sun's direction (w 0) */
    const bool sun = s->light.shape == LIGHT_SUN;
    memcpy(b->light_pos_world, sun ? &s->light.z : &s->light.pos, sizeof(struct vec3));
    b->light_pos_world[3] = sun ? 0.0f : 1.0f;
    struct vec3 dir = v3_scale(s->light.z, -1.0f);
    memcpy(b->light_dir_world, &dir, sizeof dir);
    memcpy(b->light_size_uv, f->light_size_uv, sizeof b->light_size_uv);
    b->texel_size_uv[0] = b->texel_size_uv[1] = 1.0f / (float)sm->desc.size_texels;
    b->near_window_world[0] = f->r - f->l;
    b->near_window_world[1] = f->t - f->b;
    b->near_world = f->near_world;
    b->far_world = f->far_world;
    b->map_size_texels = (float)sm->desc.size_texels;
}

static GLuint map_texture(GLenum format, int levels, int n)
{
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexStorage2D(GL_TEXTURE_2D, levels, format, n, n);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, levels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, levels > 1 ? GL_LINEAR : GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);  /* edge policy, shadowmap.h */
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return t;
}

static int mip_levels(int n)
{
    int levels = 1;
    while ((n >> levels) > 0)
        levels++;
    return levels;
}

/* A program of a product's pass: the layer's shared defines, then its own.
 * A single stage is a compute pass; two are vertex and fragment. */
static GLuint pass_program(const char *label, const char *defines, const char *first,
                           const char *fragment)
{
    struct strbuf d = {0};
    shadowmap_shader_defines(&d);
    strbuf_printf(&d, "%s", defines);
    const struct shader_stage stages[2] = {
        {fragment ? GL_VERTEX_SHADER : GL_COMPUTE_SHADER, {first}},
        {GL_FRAGMENT_SHADER, {fragment}},
    };
    GLuint p = shader_program(label, d.data, stages, fragment ? 2 : 1);
    strbuf_free(&d);
    return p;
}

/* One full-screen pass of `program` into fbo, reading `source` (at
 * SM_BINDING_PASS_SOURCE). */
static void image_pass(struct shadowmap *sm, GLuint fbo, GLuint program, GLuint source)
{
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, sm->desc.size_texels, sm->desc.size_texels);
    glUseProgram(program);
    glBindBufferBase(GL_UNIFORM_BUFFER, BLOCK_BINDING, sm->ubo);
    glBindTextureUnit(PASS_SOURCE_BINDING, source);
    glBindSampler(PASS_SOURCE_BINDING, 0);
    glBindVertexArray(sm->fullscreen_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

/* ---- depth: the scene from the light ------------------------------------ */

static int depth_create(struct shadowmap *sm, struct shadowmap_product *p)
{
    (void)sm;
    p->framebuffers[0] = gl_framebuffer(NULL, 0, p->texture, "shadow map: depth pass");
    p->programs[0] = pass_program("shadow map depth pass", "", "shadowmap_depth.vert",
                                  "shadowmap_depth.frag");
    return p->framebuffers[0] && p->programs[0] ? 0 : -1;
}

static void depth_render(struct shadowmap *sm, struct shadowmap_product *p,
                         const struct scene_mesh *mesh, const struct shadowmap_request *r)
{
    (void)r;
    glBindFramebuffer(GL_FRAMEBUFFER, p->framebuffers[0]);
    glViewport(0, 0, sm->desc.size_texels, sm->desc.size_texels);
    glClearBufferfv(GL_DEPTH, 0, (const float[]){0.0f}); /* reversed Z: far */
    glUseProgram(p->programs[0]);
    glBindBufferBase(GL_UNIFORM_BUFFER, BLOCK_BINDING, sm->ubo);
    if (sm->desc.depth_clamp)
        glEnable(GL_DEPTH_CLAMP);
    scene_mesh_draw(mesh);
    glDisable(GL_DEPTH_CLAMP);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

/* ---- moments (d, d²), evsm (warped moments), msm (four moments): separable
 * Gaussian, mipmaps */

/* The passes of a product made from the depth map by moments_blur.frag
 * (moments, evsm, msm): its rows pass converts (BLUR_FROM_DEPTH), its
 * columns pass filters; its MOMENTS_KIND is the product's own
 * SM_PRODUCT_<ID>. */
static int blurred_create(struct shadowmap *sm, struct shadowmap_product *p)
{
    const int product = (int)(p - sm->products);
    char *temp = util_printf("shadow map: %s blur temporary", product_names[product]);
    p->temp_texture = map_texture(kinds[product].format, 1, sm->desc.size_texels);
    gl_label(GL_TEXTURE, p->temp_texture, temp);
    free(temp);
    p->framebuffers[0] = gl_framebuffer(&p->texture, 1, 0, product_names[product]);
    p->framebuffers[1] = gl_framebuffer(&p->temp_texture, 1, 0, "blur, rows");
    for (int pass = 0; pass < 2; pass++) {
        char *label = util_printf("%s blur, %s", product_names[product], pass ? "columns" : "rows");
        char *defines = util_printf("#define BLUR_FROM_DEPTH %d\n#define MOMENTS_KIND SM_PRODUCT_%s\n", !pass,
                                    product_ids[product]);
        p->programs[pass] = pass_program(label, defines, "fullscreen.vert", "moments_blur.frag");
        free(label), free(defines);
    }
    return p->framebuffers[0] && p->framebuffers[1] && p->programs[0] && p->programs[1] ? 0 : -1;
}

static int check_radius(const char *product, int radius)
{
    if (radius >= 0 && radius <= SM_MAX_BLUR_RADIUS_TEXELS)
        return 0;
    log_error("%s product: blur radius %d is beyond [0, %d]", product, radius, SM_MAX_BLUR_RADIUS_TEXELS);
    return -1;
}

static int moments_check(const struct shadowmap_request *r)
{
    return check_radius("moments", r->moments.blur_radius_texels);
}

static int evsm_check(const struct shadowmap_request *r)
{
    const float c[2] = {r->evsm.positive, r->evsm.negative};
    for (int i = 0; i < 2; i++)
        if (!(c[i] > 0 && c[i] <= SM_EVSM_MAX_EXPONENT)) {
            log_error("evsm product: exponent %g is beyond (0, %g], what fp32 holds of e^{2c} at depth 1", c[i],
                      (double)SM_EVSM_MAX_EXPONENT);
            return -1;
        }
    return check_radius("evsm", r->evsm.blur_radius_texels);
}

static int msm_check(const struct shadowmap_request *r)
{
    return check_radius("msm", r->msm.blur_radius_texels);
}

static int msm_sat_check(const struct shadowmap_request *r)
{
    if (r->msm_sat.format == SAT_FP32_CENTERED) {
        log_error("msm_sat product: format fp32_centered does not apply (w = 2d - 1 is centred already)");
        return -1;
    }
    return 0;
}

static bool moments_same(const struct shadowmap_request *a, const struct shadowmap_request *b)
{
    return a->moments.blur_radius_texels == b->moments.blur_radius_texels;
}

static bool evsm_same(const struct shadowmap_request *a, const struct shadowmap_request *b)
{
    return a->evsm.positive == b->evsm.positive && a->evsm.negative == b->evsm.negative &&
           a->evsm.blur_radius_texels == b->evsm.blur_radius_texels;
}

static bool msm_same(const struct shadowmap_request *a, const struct shadowmap_request *b)
{
    return a->msm.blur_radius_texels == b->msm.blur_radius_texels;
}

static void blur_pass(struct shadowmap *sm, GLuint fbo, GLuint program, GLuint source,
                      int dx, int dy, int radius, const float *weights)
{
    glUseProgram(program);
    glUniform1i(glGetUniformLocation(program, "u_radius"), radius);
    glUniform1fv(glGetUniformLocation(program, "u_weights"), radius + 1, weights);
    glUniform2i(glGetUniformLocation(program, "u_direction"), dx, dy);
    image_pass(sm, fbo, program, source);
}

/* The product made from the depth map, filtered by a Gaussian of radius;
 * exponents: evsm's warps (NULL: the moments, msm). */
static void blurred_render(struct shadowmap *sm, struct shadowmap_product *p, int radius, const float *exponents)
{
    /* Normalised Gaussian weights, sigma = radius / 2, by |offset|. Radius
     * 0 is the rows pass alone with weight 1: depth converted to moments. */
    float w[SM_MAX_BLUR_RADIUS_TEXELS + 1], sum = 0;
    for (int k = 0; k <= radius; k++) {
        w[k] = expf(-2.0f * (float)(k * k) / (float)(radius * radius > 0 ? radius * radius : 1));
        sum += k ? 2 * w[k] : w[k];
    }
    for (int k = 0; k <= radius; k++)
        w[k] /= sum;
    GLuint depth = sm->products[SM_PRODUCT_DEPTH].texture;
    if (exponents) {
        glUseProgram(p->programs[0]);
        glUniform2fv(glGetUniformLocation(p->programs[0], "u_exponents"), 1, exponents);
    }
    if (radius > 0) {
        blur_pass(sm, p->framebuffers[1], p->programs[0], depth, 1, 0, radius, w);
        blur_pass(sm, p->framebuffers[0], p->programs[1], p->temp_texture, 0, 1, radius, w);
    } else {
        blur_pass(sm, p->framebuffers[0], p->programs[0], depth, 1, 0, 0, w);
    }
    glBindTexture(GL_TEXTURE_2D, p->texture);
    glGenerateMipmap(GL_TEXTURE_2D);
}

static void moments_render(struct shadowmap *sm, struct shadowmap_product *p,
                           const struct scene_mesh *mesh, const struct shadowmap_request *r)
{
    (void)mesh;
    blurred_render(sm, p, r->moments.blur_radius_texels, NULL);
}

static void evsm_render(struct shadowmap *sm, struct shadowmap_product *p,
                        const struct scene_mesh *mesh, const struct shadowmap_request *r)
{
    (void)mesh;
    blurred_render(sm, p, r->evsm.blur_radius_texels, (const float[]){r->evsm.positive, r->evsm.negative});
}

static void msm_render(struct shadowmap *sm, struct shadowmap_product *p,
                       const struct scene_mesh *mesh, const struct shadowmap_request *r)
{
    (void)mesh;
    blurred_render(sm, p, r->msm.blur_radius_texels, NULL);
}

/* ---- moments_sat, msm_sat: summed-area tables of (d, d²), (w, w², w³, w⁴) */

static int sat_create(struct shadowmap *sm, struct shadowmap_product *p)
{
    const int i = (int)(p - sm->products), channels = kinds[i].sat_channels;
    /* Zeroed once: the first row stays zero (the passes never write it). */
    size_t n = (size_t)sm->desc.size_texels, bytes = sizeof(uint32_t) * (size_t)channels * (n + 1) * (n + 1);
    void *zero = xcalloc(1, bytes);
    glGenBuffers(1, &p->buffer);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, p->buffer);
    glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)bytes, zero, GL_DYNAMIC_COPY);
    free(zero);
    label_product(GL_BUFFER, p->buffer, i);
    for (int pass = 0; pass < 2; pass++) {
        char *label = util_printf("%s %s", product_names[i], pass ? "columns" : "rows");
        char *defines = util_printf("#define SAT_PASS_ROWS %d\n#define SAT_CHANNELS %d\n", !pass, channels);
        p->programs[pass] = pass_program(label, defines, "sat_build.comp", NULL);
        free(label), free(defines);
    }
    return p->programs[0] && p->programs[1] ? 0 : -1;
}

/* The request's block for SAT product i. */
static const struct sat_request *sat_request_of(const struct shadowmap_request *r, int i)
{
    return i == SM_PRODUCT_MSM_SAT ? &r->msm_sat : &r->moments_sat;
}

/* The SAT_INT32 fixed-point scale (units per 1.0 of depth) and the widest
 * box side in texels it allows, for a request on an n x n map. The scale is
 * 2^k with k = 30 - floor(log2(largest box area the reader forms)), so
 * every box sum stays below 2^31. */
static void sat_int32_scale(const struct sat_request *r, int n, float *scale, float *max_box_texels)
{
    /* A box of side s has edges in at most ceil(s) + 1 texels per axis, and
     * the 16-value read forms boxes one texel wider: (ceil(s) + 2)^2 texels,
     * each at most 1.0 = 2^k units. */
    double side = r->max_box_texels > 0 ? fmin(r->max_box_texels, (double)n) : (double)n;
    double area = (ceil(side) + 2.0) * (ceil(side) + 2.0);
    int k = 30 - (int)floor(log2(area));
    k = k > 24 ? 24 : k;  /* float d has 24 significant bits */
    *scale = ldexpf(1.0f, k);
    *max_box_texels = (float)side;
}

static bool sat_same(const struct shadowmap_request *a, const struct shadowmap_request *b, int i)
{
    const struct sat_request *x = sat_request_of(a, i), *y = sat_request_of(b, i);
    return x->format == y->format && (x->format != SAT_INT32 || x->max_box_texels == y->max_box_texels);
}

static bool moments_sat_same(const struct shadowmap_request *a, const struct shadowmap_request *b)
{
    return sat_same(a, b, SM_PRODUCT_MOMENTS_SAT);
}

static bool msm_sat_same(const struct shadowmap_request *a, const struct shadowmap_request *b)
{
    return sat_same(a, b, SM_PRODUCT_MSM_SAT);
}

static void sat_render(struct shadowmap *sm, struct shadowmap_product *p,
                       const struct scene_mesh *mesh, const struct shadowmap_request *r)
{
    (void)mesh;
    const int i = (int)(p - sm->products), n = sm->desc.size_texels;
    const struct sat_request *sr = sat_request_of(r, i);
    struct shadowmap_sat_block *b = &sm->block.sat[sat_slot_of(i)];
    b->format = (int)sr->format;
    if (sr->format == SAT_INT32) {
        sat_int32_scale(sr, n, &b->scale, &b->max_box_texels);
    } else {
        b->scale = 1.0f;
        b->max_box_texels = (float)n;
    }
    glBindBuffer(GL_UNIFORM_BUFFER, sm->ubo);
    glBufferSubData(GL_UNIFORM_BUFFER, 0, sizeof sm->block, &sm->block);

    glBindBufferBase(GL_UNIFORM_BUFFER, BLOCK_BINDING, sm->ubo);
    glBindTextureUnit(binding_of(SM_PRODUCT_DEPTH), sm->products[SM_PRODUCT_DEPTH].texture);
    glBindSampler(binding_of(SM_PRODUCT_DEPTH), 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding_of(i), p->buffer);
    glUseProgram(p->programs[0]);
    glDispatchCompute((GLuint)(n + 63) / 64, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glUseProgram(p->programs[1]);
    glDispatchCompute((GLuint)(n + 63) / 64, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

/* ---- the table ------------------------------------------------------------ */

/* No row chooses what a read past the map returns: the edge policy
 * (shadowmap.h) is every product's. */
static const struct product_kind kinds[SM_PRODUCT_COUNT] = {
    [SM_PRODUCT_DEPTH] = {
        .format = GL_DEPTH_COMPONENT32F, .sampler = "sm_depth", .compare_sampler = "sm_depth_compare",
        .create = depth_create, .render = depth_render,
    },
    [SM_PRODUCT_MOMENTS] = {
        .format = GL_RG32F, .mipmapped = true, .sampler = "sm_moments",
        .create = blurred_create, .render = moments_render, .check = moments_check, .same = moments_same,
    },
    [SM_PRODUCT_MOMENTS_SAT] = {
        .sat_channels = 2,
        .create = sat_create, .render = sat_render, .same = moments_sat_same,
    },
    [SM_PRODUCT_EVSM] = {
        .format = GL_RGBA32F, .mipmapped = true, .sampler = "sm_evsm",
        .create = blurred_create, .render = evsm_render, .check = evsm_check, .same = evsm_same,
    },
    [SM_PRODUCT_MSM] = {
        .format = GL_RGBA32F, .mipmapped = true, .sampler = "sm_msm",
        .create = blurred_create, .render = msm_render, .check = msm_check, .same = msm_same,
    },
    [SM_PRODUCT_MSM_SAT] = {
        .sat_channels = 4,
        .create = sat_create, .render = sat_render, .check = msm_sat_check, .same = msm_sat_same,
    },
};

/* ---- the layer ------------------------------------------------------------ */

int shadowmap_blue_noise_binding(void)
{
    int units = 0;
    for (int p = 0; p < SM_PRODUCT_COUNT; p++)
        units += kinds[p].format ? (kinds[p].compare_sampler ? 2 : 1) : 0;
    return units;
}

int shadowmap_screen_binding(void) { return shadowmap_blue_noise_binding() + 1; }

GLuint shadowmap_blue_noise_create(void)
{
    enum { SIDE = TAP_BLUE_NOISE_SIDE, TILE = SIDE * SIDE };
    static float *texels;  /* read once: every map uploads the same */
    if (!texels) {
        char *path = shader_path("blue_noise.png");
        uint16_t *pixels;
        int err = image_read_png16(path, SIDE, 2 * SIDE, &pixels);
        if (err == -ENOENT)
            log_error("%s: no such file (the blue-noise texture; build/blue_noise writes it)", path);
        free(path);
        if (err)
            return 0;
        texels = xmalloc(2 * TILE * sizeof *texels);
        for (int i = 0; i < TILE; i++)
            for (int c = 0; c < 2; c++)  /* 16 rank + 8: (rank + 0.5) / 4096 */
                texels[2 * i + c] = (float)pixels[c * TILE + i] / 65536.0f;
        free(pixels);
    }
    GLuint t = gl_texture_2d(GL_RG32F, SIDE, SIDE, "blue noise");
    glTextureSubImage2D(t, 0, 0, 0, SIDE, SIDE, GL_RG, GL_FLOAT, texels);
    return t;
}

void shadowmap_shader_defines(struct strbuf *out)
{
    strbuf_printf(out, "#define SM_BINDING_BLOCK %d\n#define SM_BINDING_PASS_SOURCE %d\n",
                  BLOCK_BINDING, PASS_SOURCE_BINDING);
    strbuf_printf(out, "#define SM_ATTRIB_POSITION %d\n#define SM_ATTRIB_NORMAL %d\n",
                  SCENE_MESH_POSITION, SCENE_MESH_NORMAL);
    strbuf_printf(out, "#define SM_SAT_TABLES %d\n#define SM_PRODUCT_SAMPLERS", SM_SAT_TABLES);
    for (int p = 0; p < SM_PRODUCT_COUNT; p++) {  /* the samplers, one line */
        if (kinds[p].sampler)
            strbuf_printf(out, " layout(binding = %d) uniform sampler2D %s;", binding_of(p), kinds[p].sampler);
        if (kinds[p].compare_sampler)
            strbuf_printf(out, " layout(binding = %d) uniform sampler2DShadow %s;", binding_of(p) + 1,
                          kinds[p].compare_sampler);
    }
    strbuf_printf(out, "\n");
    /* the texture units past the products', for the screen-space stages' inputs */
    strbuf_printf(out, "#define SM_BINDING_SCREEN %d\n", shadowmap_screen_binding());
    strbuf_printf(out, "#define SM_BINDING_BLUE_NOISE %d\n#define SM_BLUE_NOISE_SIDE %d\n",
                  shadowmap_blue_noise_binding(), TAP_BLUE_NOISE_SIDE);
    for (int p = 0; p < SM_PRODUCT_COUNT; p++) {
        strbuf_printf(out, "#define SM_PRODUCT_%s %d\n#define SM_BINDING_%s %d\n", product_ids[p], p, product_ids[p],
                      binding_of(p));
        if (kinds[p].compare_sampler)
            strbuf_printf(out, "#define SM_BINDING_%s_COMPARE %d\n", product_ids[p], binding_of(p) + 1);
        if (kinds[p].sat_channels)
            strbuf_printf(out, "#define SM_SAT_SLOT_%s %d\n", product_ids[p], sat_slot_of(p));
    }
#define X(id, name) strbuf_printf(out, "#define SM_LIGHT_" #id " %d\n", LIGHT_##id);
    LIGHT_SHAPES(X)
#undef X
#define X(id, name) strbuf_printf(out, "#define SM_SAT_" #id " %d\n", SAT_##id);
    SAT_FORMATS(X)
#undef X
#define X(id, name) strbuf_printf(out, "#define SM_PATTERN_" #id " %d\n", TAP_PATTERN_##id);
    TAP_PATTERNS(X)
#undef X
#define X(id, name) strbuf_printf(out, "#define SM_ROTATION_" #id " %d\n", TAP_ROTATION_##id);
    TAP_ROTATIONS(X)
#undef X
    strbuf_printf(out, "#define SM_MAX_BLUR_RADIUS %d\n#define SM_MSM_QUANTISATION_FACTOR %s\n",
                  SM_MAX_BLUR_RADIUS_TEXELS, UTIL_STR(SM_MSM_QUANTISATION_FACTOR));
    /* SM_UNROLL_n(F): F(0) ... F(n-1) in blocks of 32, 16, 4 and 1 (the
     * SM_T* macros of shadow_taps.glsl). */
    for (int i = -1; i < TAP_COUNT_KINDS; i++) {  /* -1: SM_UNROLL_0, no taps */
        int n = i < 0 ? 0 : tap_counts[i], at = 0;
        strbuf_printf(out, "#define SM_UNROLL_%d(F)", n);
        for (; n - at >= 32; at += 32)
            strbuf_printf(out, " SM_T32(F, %d)", at);
        for (; n - at >= 16; at += 16)
            strbuf_printf(out, " SM_T16(F, %d)", at);
        for (; n - at >= 4; at += 4)
            strbuf_printf(out, " SM_T4(F, %d)", at);
        for (; at < n; at++)
            strbuf_printf(out, " F(%d)", at);
        strbuf_printf(out, "\n");
    }
}

static int fit(struct shadowmap *sm, const struct scene *s)
{
    if (light_frustum_fit(s, sm->desc.aspect, &sm->frustum) != 0)
        return -1;
    if (sm->desc.near_scale > 1)
        light_frustum_widen(&sm->frustum, s, sm->desc.near_scale);
    fill_block(sm, s);
    return 0;
}

void shadowmap_invalidate(struct shadowmap *sm)
{
    for (int i = 0; i < SM_PRODUCT_COUNT; i++)
        sm->products[i].current = false;
}

void shadowmap_set_frustum(struct shadowmap *sm, const struct scene *s, const struct light_frustum *f)
{
    shadowmap_invalidate(sm);
    sm->frustum = *f;
    fill_block(sm, s);
    glBindBuffer(GL_UNIFORM_BUFFER, sm->ubo);
    glBufferSubData(GL_UNIFORM_BUFFER, 0, sizeof sm->block, &sm->block);
}

int shadowmap_create(struct shadowmap *sm, const struct scene *s, const struct shadowmap_desc *desc)
{
    memset(sm, 0, sizeof *sm);
    for (int i = 0; i < SM_PRODUCT_COUNT; i++)
        if (!kinds[i].create || !kinds[i].render) {  /* an X() in SM_PRODUCTS without its row */
            log_error("shadow map: product '%s' has no row in the layer's table", product_names[i]);
            return -1;
        }
    if (sat_slot_of(SM_PRODUCT_COUNT) != SM_SAT_TABLES) {  /* the block holds a slot per table */
        log_error("shadow map: %d summed-area tables in the layer's table, SM_SAT_TABLES says %d",
                  sat_slot_of(SM_PRODUCT_COUNT), SM_SAT_TABLES);
        return -1;
    }
    sm->desc = *desc;
    if (!sm->desc.size_texels)
        sm->desc.size_texels = SHADOWMAP_DEFAULT_SIZE;
    if (!(sm->desc.near_scale >= 1))
        sm->desc.near_scale = 1;
    if (desc->frustum) {
        sm->frustum = *desc->frustum;
        sm->desc.frustum = NULL;  /* copied: the caller's may go */
        fill_block(sm, s);
    } else if (fit(sm, s) != 0) {
        return -1;
    }
    glGenBuffers(1, &sm->ubo);
    glBindBuffer(GL_UNIFORM_BUFFER, sm->ubo);
    glBufferData(GL_UNIFORM_BUFFER, sizeof sm->block, &sm->block, GL_DYNAMIC_DRAW);
    gl_label(GL_BUFFER, sm->ubo, "ShadowMapBlock");

    /* Depth products through a comparison sampler: hardware 2x2 PCF. */
    glGenSamplers(1, &sm->compare_sampler);
    glSamplerParameteri(sm->compare_sampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glSamplerParameteri(sm->compare_sampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glSamplerParameteri(sm->compare_sampler, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);  /* edge policy */
    glSamplerParameteri(sm->compare_sampler, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(sm->compare_sampler, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glSamplerParameteri(sm->compare_sampler, GL_TEXTURE_COMPARE_FUNC, GL_GEQUAL); /* reversed Z: lit */
    gl_label(GL_SAMPLER, sm->compare_sampler, "shadow map: depth comparison sampler");
    glGenVertexArrays(1, &sm->fullscreen_vao);
    sm->blue_noise = shadowmap_blue_noise_create();
    return sm->blue_noise ? 0 : -1;
}

int shadowmap_prepare(struct shadowmap *sm, const struct shadowmap_request *r)
{
    for (int i = 0; i < SM_PRODUCT_COUNT; i++) {
        const struct product_kind *k = &kinds[i];
        struct shadowmap_product *p = &sm->products[i];
        if (!(r->products & (1u << i)))
            continue;
        if (k->check && k->check(r) != 0)
            return -1;
        if (p->created)
            continue;
        p->created = true;  /* even if create fails: shadowmap_destroy deletes what it made */
        if (k->format) {
            int n = sm->desc.size_texels;
            p->texture = map_texture(k->format, k->mipmapped ? mip_levels(n) : 1, n);
            label_product(GL_TEXTURE, p->texture, i);
        }
        if (k->create(sm, p) != 0)
            return -1;
    }
    return 0;
}

void shadowmap_render_product(struct shadowmap *sm, const struct scene_mesh *mesh, int p,
                              const struct shadowmap_request *r)
{
    struct shadowmap_product *product = &sm->products[p];
    kinds[p].render(sm, product, mesh, r);
    product->current = true;
    product->made = r ? *r : (struct shadowmap_request){0};
}

bool shadowmap_ensure_product(struct shadowmap *sm, const struct scene_mesh *mesh, int p,
                              const struct shadowmap_request *r)
{
    const struct shadowmap_product *product = &sm->products[p];
    if (product->current && (!kinds[p].same || kinds[p].same(&product->made, r)))
        return false;
    shadowmap_render_product(sm, mesh, p, r);
    return true;
}

/* The Gaussian radius r asks of blurred product p. */
static int blur_radius_of(int p, const struct shadowmap_request *r)
{
    return p == SM_PRODUCT_MOMENTS ? r->moments.blur_radius_texels
           : p == SM_PRODUCT_EVSM  ? r->evsm.blur_radius_texels
                                   : r->msm.blur_radius_texels;
}

double shadowmap_prep_texels(const struct shadowmap *sm, int p, const struct shadowmap_request *r)
{
    const double n = sm->desc.size_texels, texels = n * n;
    if (p == SM_PRODUCT_DEPTH)
        return 0;
    if (kinds[p].sat_channels)  /* rows: a depth texel read, an element written (and the zero column);
                                   columns: each element read and written (sat_build.comp) */
        return 2 * texels + n + 2 * texels;
    /* moments_blur.frag: 2r + 1 reads and a write a texel, rows then
     * columns (radius 0: the rows pass alone, one read); then the mip
     * chain, each texel of a level 4 reads of the level above and a write */
    const int radius = blur_radius_of(p, r);
    double total = radius > 0 ? 2 * texels * (2 * radius + 2) : 2 * texels;
    for (int side = sm->desc.size_texels / 2; side >= 1; side /= 2)
        total += 5.0 * side * side;
    return total;
}

struct shadowmap_sat_block *shadowmap_sat_fields(struct shadowmap *sm, int p)
{
    return kinds[p].sat_channels ? &sm->block.sat[sat_slot_of(p)] : NULL;
}

void shadowmap_bind(const struct shadowmap *sm)
{
    glBindBufferBase(GL_UNIFORM_BUFFER, BLOCK_BINDING, sm->ubo);
    glBindTextureUnit((GLuint)shadowmap_blue_noise_binding(), sm->blue_noise);
    glBindSampler((GLuint)shadowmap_blue_noise_binding(), 0);
    for (int i = 0; i < SM_PRODUCT_COUNT; i++) {
        const struct product_kind *k = &kinds[i];
        const struct shadowmap_product *p = &sm->products[i];
        if (!k->format) {
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding_of(i), p->buffer);
            continue;
        }
        glBindTextureUnit(binding_of(i), p->texture);
        glBindSampler(binding_of(i), 0);
        if (k->compare_sampler) {
            glBindTextureUnit(binding_of(i) + 1, p->texture);
            glBindSampler(binding_of(i) + 1, sm->compare_sampler);
        }
    }
}

void shadowmap_destroy(struct shadowmap *sm)
{
    for (int i = 0; i < SM_PRODUCT_COUNT; i++) {
        struct shadowmap_product *p = &sm->products[i];
        for (int k = 0; k < 2; k++)
            if (p->programs[k])
                glDeleteProgram(p->programs[k]);
        glDeleteFramebuffers(2, p->framebuffers);
        GLuint textures[] = {p->texture, p->temp_texture};
        glDeleteTextures(2, textures);
        if (p->buffer)
            glDeleteBuffers(1, &p->buffer);
    }
    if (sm->blue_noise)
        glDeleteTextures(1, &sm->blue_noise);
    if (sm->fullscreen_vao)
        glDeleteVertexArrays(1, &sm->fullscreen_vao);
    if (sm->compare_sampler)
        glDeleteSamplers(1, &sm->compare_sampler);
    if (sm->ubo)
        glDeleteBuffers(1, &sm->ubo);
    memset(sm, 0, sizeof *sm);
}
