#include "receiver.h"
#include "base/log.h"
#include "base/util.h"
#include "gl/shader.h"
#include "techniques/param_rows.h"
#include "techniques/params.h"
#include "techniques/shadowmap.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* What the screen-space stages draw into and with, made on first use
 * (receiver_prepare): a scene whose cells declare none makes none. */
struct receiver_screen {
    int mask_width, mask_height;         /* blocks */
    GLuint mask_raw, mask, mask_fetches;  /* 2D arrays, a layer a cascade: the pre-pass's classes
                                            and view depths (RG), the classes dilated, and the
                                            pre-pass's fetches per block (counting) */
    GLuint mask_depth;
    GLuint mask_fbo[CASCADES_MAX], dilate_fbo[CASCADES_MAX];
    GLuint dilate_program;
    int mask_layers;                     /* the layers the last mask render wrote */
    GLuint denoise_temp, denoise_fbo[2]; /* [0] into the temporary, [1] back into V_tech */
    GLuint denoise_program;
    GLuint fullscreen_vao;               /* the full-screen passes' (no attributes) */
};

int receiver_create(struct receiver *r, const struct scene *s, int width, int height)
{
    memset(r, 0, sizeof *r);
    r->width = width;
    r->height = height;
    receiver_set_camera(r, s);

    r->visibility = gl_texture_2d(GL_R32F, width, height, "receiver: visibility");
    r->distance = gl_texture_2d(GL_R32F, width, height, "receiver: camera distance");
    r->depth = gl_texture_2d(GL_DEPTH_COMPONENT32F, width, height, "receiver: depth");
    r->cost = gl_texture_2d(GL_RGBA32F, width, height, "receiver: cost (counting)");
    r->fbo = gl_framebuffer((const GLuint[]){r->visibility, r->distance, r->cost}, 3, r->depth, "receiver pass");
    if (!r->fbo) {
        receiver_destroy(r);
        return -1;
    }
    return 0;
}

void receiver_set_camera(struct receiver *r, const struct scene *s)
{
    const struct scene_camera *c = &s->camera;
    float t = c->znear * tanf(0.5f * c->yfov_rad), rr = t * (float)r->width / (float)r->height;
    r->view_proj = m4_mul(m4_frustum_reversed_z(-rr, rr, -t, t, c->znear, INFINITY),
                          m4_view(c->pos, c->x, c->y, c->z));
    r->camera_pos = c->pos;
    r->camera_fwd = v3_scale(c->z, -1.0f);
    r->ray_right = v3_scale(c->x, rr / c->znear);
    r->ray_up = v3_scale(c->y, t / c->znear);
}

void receiver_stages_of(const struct technique *t, const void *settings, struct receiver_stages *out)
{
    const struct technique_param *mask = params_find(t, "penumbra_mask"),
                                 *dilate = params_find(t, "mask_dilate_blocks"),
                                 *dilate_world = params_find(t, "mask_dilate_world"),
                                 *radius = params_find(t, "denoise_radius_px"),
                                 *sigma = params_find(t, "denoise_sigma_world"),
                                 *normal = params_find(t, "denoise_normal_power");
    *out = (struct receiver_stages){
        .penumbra_mask = mask && params_get(mask, settings) != 0,
        .mask_dilate_blocks = dilate ? (int)params_get(dilate, settings) : 0,
        .mask_dilate_world = dilate_world ? (float)params_get(dilate_world, settings) : 0,
        .denoise_radius_px = radius && sigma ? (int)params_get(radius, settings) : 0,
        .denoise_sigma_world = sigma ? (float)params_get(sigma, settings) : 0,
        .denoise_normal_power = normal ? (float)params_get(normal, settings) : 0,
    };
}

bool receiver_program_animated(GLuint program)
{
    return glGetUniformLocation(program, "sm_noise_frame") >= 0;
}

/* One of t's programs: the receiver pass, or the mask's pre-pass. */
static GLuint technique_program(const struct technique *t, const void *settings, enum light_shape shape,
                                bool counting, const struct receiver_stages *st, bool mask)
{
    struct strbuf defines = {0};
    shadowmap_shader_defines(&defines);
    strbuf_printf(&defines, "#define SM_CASCADES_MAX %d\n", CASCADES_MAX);
    strbuf_printf(&defines, "#define SM_LIGHT_SHAPE %d\n", (int)shape);
    strbuf_printf(&defines, "#define SM_COUNT_FETCHES %d\n#define SM_PENUMBRA_MASK %d\n", counting,
                  st->penumbra_mask);
    params_defines(t, settings, &defines);
    char *label = util_printf("%s%s: %s, %s light", mask ? "penumbra mask" : "receiver pass",
                              counting ? " (counting)" : "", t->name, light_shape_names[shape]);
    GLuint p = shader_program(
        label, defines.data,
        (const struct shader_stage[]){{GL_VERTEX_SHADER, {"receiver.vert"}},
                                      {GL_FRAGMENT_SHADER, {mask ? "penumbra_mask.frag" : "receiver.frag", t->shader}}},
        2);
    free(label);
    strbuf_free(&defines);
    return p;
}

void receiver_programs_make(const struct technique *t, const void *settings, enum light_shape shape, bool counting,
                            struct receiver_programs *out)
{
    *out = (struct receiver_programs){0};
    receiver_stages_of(t, settings, &out->stages);
    out->receiver = technique_program(t, settings, shape, counting, &out->stages, false);
    if (out->receiver && out->stages.penumbra_mask &&
        !(out->mask = technique_program(t, settings, shape, counting, &out->stages, true)))
        receiver_programs_delete(out);
}

void receiver_programs_delete(struct receiver_programs *p)
{
    if (p->receiver)
        glDeleteProgram(p->receiver);
    if (p->mask)
        glDeleteProgram(p->mask);
    *p = (struct receiver_programs){0};
}

/* A full-screen pass's program (fullscreen.vert and frag). */
static GLuint screen_program(const char *label, const char *frag)
{
    struct strbuf defines = {0};
    shadowmap_shader_defines(&defines);
    strbuf_printf(&defines, "#define MASK_MAX_DILATE_BLOCKS %d\n", MASK_MAX_DILATE_BLOCKS);
    GLuint p = shader_program(label, defines.data,
                              (const struct shader_stage[]){{GL_VERTEX_SHADER, {"fullscreen.vert"}},
                                                            {GL_FRAGMENT_SHADER, {frag}}},
                              2);
    strbuf_free(&defines);
    return p;
}

static GLuint layered_texture(GLenum format, int width, int height, const char *label)
{
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D_ARRAY, t);
    glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, format, width, height, CASCADES_MAX);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl_label(GL_TEXTURE, t, label);
    return t;
}

/* A framebuffer drawing into layer `layer` of colors[0..count-1], and depth. */
static GLuint layer_framebuffer(const GLuint *colors, int count, int layer, GLuint depth, const char *label)
{
    GLuint fbo;
    GLenum buffers[2];
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    if (depth)
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth, 0);
    for (int i = 0; i < count; i++) {
        glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)i, colors[i], 0, layer);
        buffers[i] = GL_COLOR_ATTACHMENT0 + (GLenum)i;
    }
    glDrawBuffers(count, buffers);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    gl_label(GL_FRAMEBUFFER, fbo, label);
    if (status == GL_FRAMEBUFFER_COMPLETE)
        return fbo;
    log_error("%s: framebuffer incomplete (0x%x)", label, status);
    glDeleteFramebuffers(1, &fbo);
    return 0;
}

static int prepare_mask(struct receiver *r, struct receiver_screen *sc)
{
    sc->mask_width = (r->width + RECEIVER_MASK_BLOCK - 1) / RECEIVER_MASK_BLOCK;
    sc->mask_height = (r->height + RECEIVER_MASK_BLOCK - 1) / RECEIVER_MASK_BLOCK;
    sc->mask_raw = layered_texture(GL_RG32F, sc->mask_width, sc->mask_height, "penumbra mask: classes, distances");
    sc->mask = layered_texture(GL_R32F, sc->mask_width, sc->mask_height, "penumbra mask: dilated");
    sc->mask_fetches = layered_texture(GL_R32F, sc->mask_width, sc->mask_height, "penumbra mask: fetches");
    sc->mask_depth = gl_texture_2d(GL_DEPTH_COMPONENT32F, sc->mask_width, sc->mask_height, "penumbra mask: depth");
    for (int k = 0; k < CASCADES_MAX; k++)
        if (!(sc->mask_fbo[k] = layer_framebuffer((const GLuint[]){sc->mask_raw, sc->mask_fetches}, 2, k,
                                                  sc->mask_depth, "penumbra mask pre-pass")) ||
            !(sc->dilate_fbo[k] = layer_framebuffer(&sc->mask, 1, k, 0, "penumbra mask dilation")))
            return -1;
    return (sc->dilate_program = screen_program("penumbra mask dilation", "penumbra_dilate.frag")) ? 0 : -1;
}

static int prepare_denoise(struct receiver *r, struct receiver_screen *sc)
{
    sc->denoise_temp = gl_texture_2d(GL_R32F, r->width, r->height, "denoiser: first direction");
    if (!(sc->denoise_fbo[0] = gl_framebuffer(&sc->denoise_temp, 1, 0, "denoiser, rows")) ||
        !(sc->denoise_fbo[1] = gl_framebuffer(&r->visibility, 1, 0, "denoiser, columns")))
        return -1;
    return (sc->denoise_program = screen_program("denoiser", "denoise.frag")) ? 0 : -1;
}

int receiver_prepare(struct receiver *r, const struct receiver_programs *p)
{
    if (!p->stages.penumbra_mask && !p->stages.denoise_radius_px)
        return 0;
    if (!r->screen) {
        r->screen = xcalloc(1, sizeof *r->screen);
        glGenVertexArrays(1, &r->screen->fullscreen_vao);
    }
    struct receiver_screen *sc = r->screen;
    if (p->stages.penumbra_mask && !sc->dilate_program && prepare_mask(r, sc) != 0)
        return -1;
    if (p->stages.denoise_radius_px && !sc->denoise_program && prepare_denoise(r, sc) != 0)
        return -1;
    return 0;
}

/* The uniforms of the camera passes (receiver.frag, penumbra_mask.frag). */
static void camera_uniforms(const struct receiver *r, GLuint program, struct mat4 view_proj,
                            const struct shadow_cascades *c)
{
    glUseProgram(program);
    glUniformMatrix4fv(glGetUniformLocation(program, "u_camera_view_proj"), 1, GL_FALSE, view_proj.m);
    glUniform3f(glGetUniformLocation(program, "u_camera_pos"), r->camera_pos.x, r->camera_pos.y, r->camera_pos.z);
    glUniform3f(glGetUniformLocation(program, "u_camera_fwd"), r->camera_fwd.x, r->camera_fwd.y, r->camera_fwd.z);
    glUniform1f(glGetUniformLocation(program, "sm_noise_frame"), r->noise_frame);  /* -1 (unused): ignored */
    glUniform1i(glGetUniformLocation(program, "u_cascade_count"), c->count);
    glUniform1fv(glGetUniformLocation(program, "u_cascade_z"), c->count + 1, c->z);
    glUniform1fv(glGetUniformLocation(program, "u_cascade_band"), c->count, c->band);
}

void receiver_render_mask(const struct receiver *r, const struct receiver_programs *p, const struct scene_mesh *mesh,
                          const struct shadow_cascades *c, bool counting)
{
    struct receiver_screen *sc = r->screen;
    if (sc)
        sc->mask_layers = 0;  /* receiver_read_cost adds only this frame's pre-pass */
    if (!p->mask || !sc)
        return;
    /* The camera's projection scaled so a fragment is a block: the blocks
     * cover ceil(W / 4) x 4 pixels, a little past the image's edge. */
    const float sx = (float)r->width / (float)(RECEIVER_MASK_BLOCK * sc->mask_width),
                sy = (float)r->height / (float)(RECEIVER_MASK_BLOCK * sc->mask_height);
    struct mat4 fit = m4_identity();
    fit.m[0] = sx, fit.m[5] = sy, fit.m[12] = sx - 1.0f, fit.m[13] = sy - 1.0f;
    camera_uniforms(r, p->mask, m4_mul(fit, r->view_proj), c);
    const GLint which = glGetUniformLocation(p->mask, "u_cascade");
    const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glViewport(0, 0, sc->mask_width, sc->mask_height);
    for (int k = 0; k < c->count; k++) {
        glBindFramebuffer(GL_FRAMEBUFFER, sc->mask_fbo[k]);
        glDrawBuffers(counting ? 2 : 1, buffers);
        glClearBufferfv(GL_COLOR, 0, (const float[4]){0.5f, 0, 0, 0});  /* no geometry: penumbra, depth 0 */
        if (counting)
            glClearBufferfv(GL_COLOR, 1, (const float[4]){0, 0, 0, 0});
        glClearBufferfv(GL_DEPTH, 0, (const float[]){0.0f});
        glUseProgram(p->mask);
        glUniform1i(which, k);
        shadowmap_bind(&c->map[k]);
        scene_mesh_draw(mesh);
    }
    sc->mask_layers = counting ? c->count : 0;
    glUseProgram(sc->dilate_program);
    glUniform1i(glGetUniformLocation(sc->dilate_program, "u_radius"), p->stages.mask_dilate_blocks);
    /* a block's side in world units per unit of view depth: 4 pixels of
     * the image plane at depth 1 (|ray_up| = tan(yfov / 2)) */
    const float block_angle = (float)RECEIVER_MASK_BLOCK * 2.0f * v3_length(r->ray_up) / (float)r->height;
    glUniform1f(glGetUniformLocation(sc->dilate_program, "u_radius_world"), p->stages.mask_dilate_world);
    glUniform1f(glGetUniformLocation(sc->dilate_program, "u_block_angle"), block_angle);
    glBindTextureUnit(SHADOWMAP_PASS_SOURCE_UNIT, sc->mask_raw);
    glBindSampler(SHADOWMAP_PASS_SOURCE_UNIT, 0);
    glDisable(GL_DEPTH_TEST);
    glBindVertexArray(sc->fullscreen_vao);
    for (int k = 0; k < c->count; k++) {
        glBindFramebuffer(GL_FRAMEBUFFER, sc->dilate_fbo[k]);
        glUniform1i(glGetUniformLocation(sc->dilate_program, "u_layer"), k);
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    glEnable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void receiver_render(const struct receiver *r, const struct receiver_programs *p, const struct scene_mesh *mesh,
                     const struct shadow_cascades *c, bool counting)
{
    glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
    glDrawBuffers(counting ? 3 : 2, (const GLenum[]){GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2});
    glViewport(0, 0, r->width, r->height);
    /* One map: V itself. Cascades add up w_c V_c, from 0. */
    glClearBufferfv(GL_COLOR, 0, (const float[4]){c->count > 1 ? 0.0f : 1.0f, 0, 0, 0});
    glClearBufferfv(GL_COLOR, 1, (const float[4]){-1, 0, 0, 0});
    if (counting)
        glClearBufferfv(GL_COLOR, 2, (const float[4]){0, 0, 0, 0});
    glClearBufferfv(GL_DEPTH, 0, (const float[]){0.0f}); /* reversed Z: far */
    camera_uniforms(r, p->receiver, r->view_proj, c);
    if (p->mask && r->screen) {
        glBindTextureUnit((GLuint)shadowmap_screen_binding(), r->screen->mask);
        glBindSampler((GLuint)shadowmap_screen_binding(), 0);
    }
    const GLint which = glGetUniformLocation(p->receiver, "u_cascade");
    for (int k = 0; k < c->count; k++) {
        if (k == 1) {  /* the first pass laid the depth: the others shade the same surface, adding */
            glEnablei(GL_BLEND, 0);
            if (counting)
                glEnablei(GL_BLEND, 2);
            glBlendFunc(GL_ONE, GL_ONE);
            glDepthFunc(GL_EQUAL);
            glDepthMask(GL_FALSE);
        }
        glUniform1i(which, k);
        shadowmap_bind(&c->map[k]);
        scene_mesh_draw(mesh);
    }
    if (c->count > 1) {
        glDisablei(GL_BLEND, 0);
        glDisablei(GL_BLEND, 2);
        glDepthFunc(GL_GREATER);
        glDepthMask(GL_TRUE);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void receiver_render_denoise(const struct receiver *r, const struct receiver_programs *p)
{
    const struct receiver_screen *sc = r->screen;
    if (!p->stages.denoise_radius_px || !sc)
        return;
    const GLuint program = sc->denoise_program;
    glUseProgram(program);
    glUniform1i(glGetUniformLocation(program, "u_radius"), p->stages.denoise_radius_px);
    glUniform1f(glGetUniformLocation(program, "u_sigma_world"), p->stages.denoise_sigma_world);
    glUniform1f(glGetUniformLocation(program, "u_normal_power"), p->stages.denoise_normal_power);
    glUniform3f(glGetUniformLocation(program, "u_camera_pos"), r->camera_pos.x, r->camera_pos.y, r->camera_pos.z);
    glUniform3f(glGetUniformLocation(program, "u_ray_fwd"), r->camera_fwd.x, r->camera_fwd.y, r->camera_fwd.z);
    glUniform3f(glGetUniformLocation(program, "u_ray_right"), r->ray_right.x, r->ray_right.y, r->ray_right.z);
    glUniform3f(glGetUniformLocation(program, "u_ray_up"), r->ray_up.x, r->ray_up.y, r->ray_up.z);
    glUniform2fv(glGetUniformLocation(program, "u_size"), 1, (const float[]){(float)r->width, (float)r->height});
    glBindTextureUnit(SHADOWMAP_PASS_SOURCE_UNIT + 1, r->distance);
    glBindSampler(SHADOWMAP_PASS_SOURCE_UNIT + 1, 0);
    glViewport(0, 0, r->width, r->height);
    glDisable(GL_DEPTH_TEST);
    glBindVertexArray(sc->fullscreen_vao);
    const GLuint sources[2] = {r->visibility, sc->denoise_temp};
    for (int pass = 0; pass < 2; pass++) {  /* rows, then columns */
        glBindFramebuffer(GL_FRAMEBUFFER, sc->denoise_fbo[pass]);
        glUniform2i(glGetUniformLocation(program, "u_direction"), pass == 0, pass == 1);
        glBindTextureUnit(SHADOWMAP_PASS_SOURCE_UNIT, sources[pass]);
        glBindSampler(SHADOWMAP_PASS_SOURCE_UNIT, 0);
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    glEnable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void receiver_read(const struct receiver *r, float *visibility, float *distance)
{
    glBindFramebuffer(GL_READ_FRAMEBUFFER, r->fbo);
    if (visibility)
        gl_read_red(GL_COLOR_ATTACHMENT0, r->width, r->height, visibility);
    if (distance)
        gl_read_red(GL_COLOR_ATTACHMENT1, r->width, r->height, distance);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}

void receiver_read_cost(const struct receiver *r, struct receiver_cost *out, float *shortcut)
{
    const size_t count = (size_t)r->width * (size_t)r->height;
    float *cost = xmalloc(sizeof(float) * 4 * count), *distance = xmalloc(sizeof(float) * count);
    receiver_read(r, NULL, distance);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, r->fbo);
    gl_read_rgba(GL_COLOR_ATTACHMENT2, r->width, r->height, cost);
    *out = (struct receiver_cost){0};
    for (size_t i = 0; i < count; i++) {
        const float *c = &cost[4 * i];
        const bool covered = distance[i] >= 0, full = c[1] > 0, skipped = !full && c[2] > 0;
        out->fetches += c[0];
        out->covered += covered;
        out->expensive += covered && full;
        if (shortcut)
            shortcut[i] = covered && skipped;
    }
    const struct receiver_screen *sc = r->screen;
    if (sc && sc->mask_layers) {  /* the pre-pass's fetches, every block of every layer it wrote */
        float *blocks = xmalloc(sizeof(float) * (size_t)sc->mask_width * (size_t)sc->mask_height);
        for (int k = 0; k < sc->mask_layers; k++) {
            glBindFramebuffer(GL_READ_FRAMEBUFFER, sc->mask_fbo[k]);
            gl_read_red(GL_COLOR_ATTACHMENT1, sc->mask_width, sc->mask_height, blocks);
            for (int i = 0; i < sc->mask_width * sc->mask_height; i++)
                out->fetches += blocks[i];
        }
        free(blocks);
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    free(cost), free(distance);
}

void receiver_destroy(struct receiver *r)
{
    if (r->fbo)
        glDeleteFramebuffers(1, &r->fbo);
    GLuint tex[4] = {r->visibility, r->distance, r->depth, r->cost};
    glDeleteTextures(4, tex);
    struct receiver_screen *sc = r->screen;
    if (sc) {
        glDeleteFramebuffers(CASCADES_MAX, sc->mask_fbo);
        glDeleteFramebuffers(CASCADES_MAX, sc->dilate_fbo);
        glDeleteFramebuffers(2, sc->denoise_fbo);
        GLuint more[5] = {sc->mask_raw, sc->mask, sc->mask_fetches, sc->mask_depth, sc->denoise_temp};
        glDeleteTextures(5, more);
        if (sc->dilate_program)
            glDeleteProgram(sc->dilate_program);
        if (sc->denoise_program)
            glDeleteProgram(sc->denoise_program);
        glDeleteVertexArrays(1, &sc->fullscreen_vao);
        free(sc);
    }
    memset(r, 0, sizeof *r);
}
