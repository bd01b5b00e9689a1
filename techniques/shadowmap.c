#include "shadowmap.h"
#include "../harness/log.h"
#include "../harness/shader.h"

#include <math.h>
#include <string.h>

/* ---- frustum ----------------------------------------------------------- */

struct light_point { float x, y, d; };  /* light space, d = planar depth (-z) */

/* Clips a triangle to d >= d_min (Sutherland-Hodgman against one plane). */
static int clip_front(const struct light_point in[3], float d_min, struct light_point out[4])
{
    int n = 0;
    for (int i = 0; i < 3; i++) {
        struct light_point a = in[i], b = in[(i + 1) % 3];
        bool a_in = a.d >= d_min, b_in = b.d >= d_min;
        if (a_in)
            out[n++] = a;
        if (a_in != b_in) {
            float t = (d_min - a.d) / (b.d - a.d);
            out[n++] = (struct light_point){a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), d_min};
        }
    }
    return n;
}

int shadowmap_fit(const struct scene *s, struct shadowmap_frustum *f)
{
    const struct scene_light *L = &s->light;
    memset(f, 0, sizeof *f);
    f->view = m4_view(L->pos, L->x, L->y, L->z);

    const float d_clip = 1e-4f * scene_extent(s);  /* keeps x/d finite at the light plane */
    const float t_max = (float)tan(SHADOWMAP_MAX_HALF_ANGLE_DEG * M_PI / 180.0);
    float tx_lo = INFINITY, tx_hi = -INFINITY, ty_lo = INFINITY, ty_hi = -INFINITY;
    float d_lo = INFINITY, d_hi = 0;
    for (size_t t = 0; t < s->triangle_count; t++) {
        struct light_point tri[3], poly[4];
        for (int k = 0; k < 3; k++) {
            const float *p = &s->positions[3 * s->indices[3 * t + k]];
            struct vec3 q = m4_point(f->view, v3(p[0], p[1], p[2]));
            tri[k] = (struct light_point){q.x, q.y, -q.z};
        }
        int n = clip_front(tri, d_clip, poly);
        for (int k = 0; k < n; k++) {
            float tx = fminf(fmaxf(poly[k].x / poly[k].d, -t_max), t_max);
            float ty = fminf(fmaxf(poly[k].y / poly[k].d, -t_max), t_max);
            tx_lo = fminf(tx_lo, tx), tx_hi = fmaxf(tx_hi, tx);
            ty_lo = fminf(ty_lo, ty), ty_hi = fmaxf(ty_hi, ty);
            d_lo = fminf(d_lo, poly[k].d), d_hi = fmaxf(d_hi, poly[k].d);
        }
    }
    if (isinf(d_lo)) {  /* nothing survived the clip: all of it is behind the light */
        log_error("%s: no geometry in front of the area light (it emits towards its local -Z)",
                  s->path);
        return -1;
    }
    /* Margins: 0.1% in depth so nothing clips at near/far, 1% of the window
     * so the outermost geometry is not sampled on the border texel. */
    f->near_world = fmaxf(d_lo * 0.999f, d_clip);
    f->far_world = d_hi * 1.001f;
    float mx = 0.01f * (tx_hi - tx_lo), my = 0.01f * (ty_hi - ty_lo);
    f->l = (fmaxf(tx_lo - mx, -t_max)) * f->near_world;
    f->r = (fminf(tx_hi + mx, t_max)) * f->near_world;
    f->b = (fmaxf(ty_lo - my, -t_max)) * f->near_world;
    f->t = (fminf(ty_hi + my, t_max)) * f->near_world;
    struct mat4 proj = m4_frustum_reversed_z(f->l, f->r, f->b, f->t, f->near_world, f->far_world);
    f->view_proj = m4_mul(proj, f->view);
    f->light_size_uv[0] = L->width / (f->r - f->l);
    f->light_size_uv[1] = L->height / (f->t - f->b);
    return 0;
}

bool shadowmap_inside(const struct shadowmap_frustum *f, struct vec3 p)
{
    struct vec3 q = m4_point(f->view, p);
    float d = -q.z;
    if (!(d >= f->near_world && d <= f->far_world))
        return false;
    float x = q.x * f->near_world / d, y = q.y * f->near_world / d;
    return x >= f->l && x <= f->r && y >= f->b && y <= f->t;
}

/* ---- GL products ------------------------------------------------------- */

static void fill_block(const struct shadowmap *sm, const struct scene *s, struct shadowmap_block *b)
{
    const struct shadowmap_frustum *f = &sm->frustum;
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

int shadowmap_create(struct shadowmap *sm, const struct scene *s, const struct shadowmap_desc *desc)
{
    memset(sm, 0, sizeof *sm);
    sm->desc = *desc;
    if (!sm->desc.size_texels)
        sm->desc.size_texels = SHADOWMAP_DEFAULT_SIZE;
    if (shadowmap_fit(s, &sm->frustum) != 0)
        return -1;

    struct shadowmap_block block;
    fill_block(sm, s, &block);
    glGenBuffers(1, &sm->ubo);
    glBindBuffer(GL_UNIFORM_BUFFER, sm->ubo);
    glBufferData(GL_UNIFORM_BUFFER, sizeof block, &block, GL_STATIC_DRAW);
    gl_label(GL_BUFFER, sm->ubo, "ShadowMapBlock");

    int n = sm->desc.size_texels;
    glGenTextures(1, &sm->depth_texture);
    glBindTexture(GL_TEXTURE_2D, sm->depth_texture);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT32F, n, n);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    /* Outside the map: depth 0, the far plane in reversed Z, so nothing
     * there occludes (lit), as engines do. */
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
    glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, (const float[4]){0, 0, 0, 0});
    gl_label(GL_TEXTURE, sm->depth_texture, "shadow map: depth");

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

void shadowmap_render_product(struct shadowmap *sm, const struct scene_mesh *mesh,
                              enum shadowmap_product product)
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
    case SM_MOMENTS_SAT:
        log_error("shadow map: moments products are not implemented yet");
        return;
    }
    sm->current |= product;
}

void shadowmap_require(struct shadowmap *sm, const struct scene_mesh *mesh, unsigned products)
{
    for (unsigned p = SM_DEPTH; p <= SM_MOMENTS_SAT; p <<= 1)
        if ((products & p) && !(sm->current & p))
            shadowmap_render_product(sm, mesh, (enum shadowmap_product)p);
}

void shadowmap_bind(const struct shadowmap *sm)
{
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, sm->ubo);
    glBindTextureUnit(0, sm->depth_texture);
}

void shadowmap_destroy(struct shadowmap *sm)
{
    if (sm->depth_program)
        glDeleteProgram(sm->depth_program);
    if (sm->depth_fbo)
        glDeleteFramebuffers(1, &sm->depth_fbo);
    if (sm->depth_texture)
        glDeleteTextures(1, &sm->depth_texture);
    if (sm->ubo)
        glDeleteBuffers(1, &sm->ubo);
    memset(sm, 0, sizeof *sm);
}
