#include "shadowmap.h"
#include "base/log.h"
#include "base/util.h"
#include "gl/shader.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- GL products ------------------------------------------------------- */

static void fill_block(struct shadowmap *sm, const struct scene *s)
{
    const struct light_frustum *f = &sm->frustum;
    struct shadowmap_block *b = &sm->block;
    memset(b, 0, sizeof *b);
    memcpy(b->light_view_proj, f->view_proj.m, sizeof b->light_view_proj);
    memcpy(b->light_view, f->view.m, sizeof b->light_view);
    memcpy(b->light_pos_world, &s->light.pos, sizeof(struct vec3));
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

static GLuint map_texture(GLenum format, int levels, int n, const float border[4], const char *label)
{
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexStorage2D(GL_TEXTURE_2D, levels, format, n, n);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, levels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, levels > 1 ? GL_LINEAR : GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
    glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, border);
    gl_label(GL_TEXTURE, t, label);
    return t;
}

/* Outside the map is the far plane, so nothing there occludes (lit), as
 * engines do: hardware depth 0 (reversed Z), moments (1, 1). */
static const float border_depth[4] = {0, 0, 0, 0}, border_moments[4] = {1, 1, 0, 0};

int shadowmap_create(struct shadowmap *sm, const struct scene *s, const struct shadowmap_desc *desc)
{
    memset(sm, 0, sizeof *sm);
    sm->desc = *desc;
    if (!sm->desc.size_texels)
        sm->desc.size_texels = SHADOWMAP_DEFAULT_SIZE;
    if (light_frustum_fit(s, &sm->frustum) != 0)
        return -1;

    fill_block(sm, s);
    glGenBuffers(1, &sm->ubo);
    glBindBuffer(GL_UNIFORM_BUFFER, sm->ubo);
    glBufferData(GL_UNIFORM_BUFFER, sizeof sm->block, &sm->block, GL_DYNAMIC_DRAW);
    gl_label(GL_BUFFER, sm->ubo, "ShadowMapBlock");

    int n = sm->desc.size_texels;
    sm->depth_texture = map_texture(GL_DEPTH_COMPONENT32F, 1, n, border_depth, "shadow map: depth");
    /* The same texture through a comparison sampler: hardware 2x2 PCF. */
    glGenSamplers(1, &sm->compare_sampler);
    glSamplerParameteri(sm->compare_sampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glSamplerParameteri(sm->compare_sampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glSamplerParameteri(sm->compare_sampler, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
    glSamplerParameteri(sm->compare_sampler, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
    glSamplerParameterfv(sm->compare_sampler, GL_TEXTURE_BORDER_COLOR, border_depth);
    glSamplerParameteri(sm->compare_sampler, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glSamplerParameteri(sm->compare_sampler, GL_TEXTURE_COMPARE_FUNC, GL_GEQUAL); /* reversed Z: lit */
    gl_label(GL_SAMPLER, sm->compare_sampler, "shadow map: depth comparison sampler");

    glGenFramebuffers(1, &sm->depth_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, sm->depth_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, sm->depth_texture, 0);
    glDrawBuffers(1, (const GLenum[]){GL_NONE});
    glReadBuffer(GL_NONE);
    GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    gl_label(GL_FRAMEBUFFER, sm->depth_fbo, "shadow map: depth pass");
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        log_error("shadow map: depth framebuffer incomplete (0x%x)", status);
        shadowmap_destroy(sm);
        return -1;
    }

    sm->depth_program = shader_program(
        "shadow map depth pass", NULL,
        (const struct shader_stage[]){{GL_VERTEX_SHADER, {"shadowmap_depth.vert"}},
                                      {GL_FRAGMENT_SHADER, {"shadowmap_depth.frag"}}},
        2);
    if (!sm->depth_program) {
        shadowmap_destroy(sm);
        return -1;
    }
    return 0;
}

static GLuint compute_program(const char *label, const char *file, const char *defines)
{
    return shader_program(label, defines, &(struct shader_stage){GL_COMPUTE_SHADER, {file}}, 1);
}

static GLuint image_program(const char *label, const char *fragment, const char *defines)
{
    return shader_program(label, defines,
                          (const struct shader_stage[]){{GL_VERTEX_SHADER, {"fullscreen.vert"}},
                                                        {GL_FRAGMENT_SHADER, {fragment}}},
                          2);
}

/* A framebuffer rendering into level 0 of an RG32F map texture. */
static GLuint image_target(GLuint texture, const char *label)
{
    GLuint fbo;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
    glDrawBuffers(1, (const GLenum[]){GL_COLOR_ATTACHMENT0});
    GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    gl_label(GL_FRAMEBUFFER, fbo, label);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        log_error("%s: framebuffer incomplete (0x%x)", label, status);
        glDeleteFramebuffers(1, &fbo);
        return 0;
    }
    return fbo;
}

int shadowmap_prepare(struct shadowmap *sm, const struct shadowmap_request *r)
{
    int n = sm->desc.size_texels;
    if ((r->products & SM_MOMENTS) && !sm->moments) {
        int levels = 1;
        while ((n >> levels) > 0)
            levels++;
        sm->moments = map_texture(GL_RG32F, levels, n, border_moments, "shadow map: moments");
        sm->moments_temp = map_texture(GL_RG32F, 1, n, border_moments, "shadow map: blur temporary");
        glGenVertexArrays(1, &sm->fullscreen_vao);
        if (!(sm->moments_fbo = image_target(sm->moments, "moments pass")) ||
            !(sm->temp_fbo = image_target(sm->moments_temp, "moments blur, rows")) ||
            !(sm->blur_rows_program = image_program("moments blur, rows", "moments_blur.frag",
                                                    "#define BLUR_FROM_DEPTH 1\n")) ||
            !(sm->blur_columns_program = image_program("moments blur, columns", "moments_blur.frag",
                                                       "#define BLUR_FROM_DEPTH 0\n")))
            return -1;
    }
    if ((r->products & SM_MOMENTS_SAT) && !sm->sat_buffer) {
        /* Zeroed once: the first row stays zero (the passes never write it). */
        size_t bytes = sizeof(uint32_t) * 2 * (size_t)(n + 1) * (size_t)(n + 1);
        void *zero = xcalloc(1, bytes);
        glGenBuffers(1, &sm->sat_buffer);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, sm->sat_buffer);
        glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)bytes, zero, GL_DYNAMIC_COPY);
        free(zero);
        gl_label(GL_BUFFER, sm->sat_buffer, "shadow map: moments SAT");
        sm->sat_rows_program = compute_program("SAT rows", "sat_build.comp", "#define SAT_PASS_ROWS 1\n");
        sm->sat_columns_program = compute_program("SAT columns", "sat_build.comp", "#define SAT_PASS_ROWS 0\n");
        if (!sm->sat_rows_program || !sm->sat_columns_program)
            return -1;
    }
    return 0;
}

void shadowmap_sat_int32_scale(const struct shadowmap_request *r, int n, float *scale,
                               float *max_box_texels)
{
    /* A box of side s has edges in at most ceil(s) + 1 texels per axis, and
     * the 16-value read forms boxes one texel wider: (ceil(s) + 2)^2 texels,
     * each at most 1.0 = 2^k units. */
    double side = r->sat_max_box_texels > 0 ? fmin(r->sat_max_box_texels, (double)n) : (double)n;
    double area = (ceil(side) + 2.0) * (ceil(side) + 2.0);
    int k = 30 - (int)floor(log2(area));
    k = k > 24 ? 24 : k;  /* float d has 24 significant bits */
    *scale = ldexpf(1.0f, k);
    *max_box_texels = (float)side;
}

/* One full-screen pass of `program` into fbo, reading `source` on unit 0. */
static void image_pass(struct shadowmap *sm, GLuint fbo, GLuint program, GLuint source)
{
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, sm->desc.size_texels, sm->desc.size_texels);
    glUseProgram(program);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, sm->ubo);
    glBindTextureUnit(0, source);
    glBindSampler(0, 0);
    glBindVertexArray(sm->fullscreen_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
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

static void render_moments(struct shadowmap *sm, const struct shadowmap_request *r)
{
    /* Normalised Gaussian weights, sigma = radius / 2, by |offset|. Radius
     * 0 is the rows pass alone with weight 1: depth converted to moments. */
    int radius = r->moments_blur_radius_texels;
    float w[SHADOWMAP_MAX_BLUR_RADIUS + 1], sum = 0;
    for (int k = 0; k <= radius; k++) {
        w[k] = expf(-2.0f * (float)(k * k) / (float)(radius * radius > 0 ? radius * radius : 1));
        sum += k ? 2 * w[k] : w[k];
    }
    for (int k = 0; k <= radius; k++)
        w[k] /= sum;
    if (radius > 0) {
        blur_pass(sm, sm->temp_fbo, sm->blur_rows_program, sm->depth_texture, 1, 0, radius, w);
        blur_pass(sm, sm->moments_fbo, sm->blur_columns_program, sm->moments_temp, 0, 1, radius, w);
    } else {
        blur_pass(sm, sm->moments_fbo, sm->blur_rows_program, sm->depth_texture, 1, 0, 0, w);
    }
    glBindTexture(GL_TEXTURE_2D, sm->moments);
    glGenerateMipmap(GL_TEXTURE_2D);
}

static void render_sat(struct shadowmap *sm, const struct shadowmap_request *r)
{
    int n = sm->desc.size_texels;
    struct shadowmap_block *b = &sm->block;
    b->sat_format = (int)r->sat_format;
    if (r->sat_format == SAT_INT32) {
        shadowmap_sat_int32_scale(r, n, &b->sat_scale, &b->sat_max_box_texels);
    } else {
        b->sat_scale = 1.0f;
        b->sat_max_box_texels = (float)n;
    }
    glBindBuffer(GL_UNIFORM_BUFFER, sm->ubo);
    glBufferSubData(GL_UNIFORM_BUFFER, 0, sizeof *b, b);

    glBindBufferBase(GL_UNIFORM_BUFFER, 0, sm->ubo);
    glBindTextureUnit(0, sm->depth_texture);
    glBindSampler(0, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, sm->sat_buffer);
    glUseProgram(sm->sat_rows_program);
    glDispatchCompute((GLuint)(n + 63) / 64, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glUseProgram(sm->sat_columns_program);
    glDispatchCompute((GLuint)(n + 63) / 64, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void shadowmap_render_product(struct shadowmap *sm, const struct scene_mesh *mesh,
                              enum shadowmap_product product, const struct shadowmap_request *r)
{
    switch (product) {
    case SM_DEPTH:
        glBindFramebuffer(GL_FRAMEBUFFER, sm->depth_fbo);
        glViewport(0, 0, sm->desc.size_texels, sm->desc.size_texels);
        glClearBufferfv(GL_DEPTH, 0, (const float[]){0.0f}); /* reversed Z: far */
        glUseProgram(sm->depth_program);
        glBindBufferBase(GL_UNIFORM_BUFFER, 0, sm->ubo);
        scene_mesh_draw(mesh);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        break;
    case SM_MOMENTS:
        render_moments(sm, r);
        sm->made.moments_blur_radius_texels = r->moments_blur_radius_texels;
        break;
    case SM_MOMENTS_SAT:
        render_sat(sm, r);
        sm->made.sat_format = r->sat_format;
        sm->made.sat_max_box_texels = r->sat_max_box_texels;
        break;
    }
    sm->current |= product;
}

bool shadowmap_same_product(enum shadowmap_product p, const struct shadowmap_request *a,
                            const struct shadowmap_request *b)
{
    switch (p) {
    case SM_DEPTH: return true;
    case SM_MOMENTS: return a->moments_blur_radius_texels == b->moments_blur_radius_texels;
    case SM_MOMENTS_SAT:
        return a->sat_format == b->sat_format &&
               (a->sat_format != SAT_INT32 || a->sat_max_box_texels == b->sat_max_box_texels);
    }
    return false;
}

void shadowmap_require(struct shadowmap *sm, const struct scene_mesh *mesh,
                       const struct shadowmap_request *r)
{
    for (unsigned p = SM_DEPTH; p <= SM_MOMENTS_SAT; p <<= 1)
        if ((r->products & p) &&
            !((sm->current & p) && shadowmap_same_product((enum shadowmap_product)p, &sm->made, r)))
            shadowmap_render_product(sm, mesh, (enum shadowmap_product)p, r);
}

void shadowmap_bind(const struct shadowmap *sm)
{
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, sm->ubo);
    glBindTextureUnit(0, sm->depth_texture);
    glBindSampler(0, 0);
    glBindTextureUnit(1, sm->depth_texture);
    glBindSampler(1, sm->compare_sampler);
    glBindTextureUnit(2, sm->moments);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, sm->sat_buffer);
}

void shadowmap_destroy(struct shadowmap *sm)
{
    GLuint programs[] = {sm->depth_program, sm->blur_rows_program,
                         sm->blur_columns_program, sm->sat_rows_program, sm->sat_columns_program};
    for (size_t i = 0; i < sizeof programs / sizeof *programs; i++)
        if (programs[i])
            glDeleteProgram(programs[i]);
    GLuint fbos[] = {sm->depth_fbo, sm->moments_fbo, sm->temp_fbo};
    glDeleteFramebuffers(3, fbos);
    if (sm->fullscreen_vao)
        glDeleteVertexArrays(1, &sm->fullscreen_vao);
    if (sm->compare_sampler)
        glDeleteSamplers(1, &sm->compare_sampler);
    GLuint textures[] = {sm->depth_texture, sm->moments_temp, sm->moments};
    glDeleteTextures(3, textures);
    GLuint buffers[] = {sm->ubo, sm->sat_buffer};
    glDeleteBuffers(2, buffers);
    memset(sm, 0, sizeof *sm);
}
