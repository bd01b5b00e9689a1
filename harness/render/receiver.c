#include "receiver.h"
#include "base/log.h"
#include "base/util.h"
#include "gl/shader.h"
#include "techniques/params.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static GLuint target(GLenum format, int w, int h, const char *label)
{
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexStorage2D(GL_TEXTURE_2D, 1, format, w, h);
    gl_label(GL_TEXTURE, t, label);
    return t;
}

int receiver_create(struct receiver *r, const struct scene *s, int width, int height)
{
    memset(r, 0, sizeof *r);
    r->width = width;
    r->height = height;
    receiver_set_camera(r, s);

    r->visibility = target(GL_R32F, width, height, "receiver: visibility");
    r->distance = target(GL_R32F, width, height, "receiver: camera distance");
    r->depth = target(GL_DEPTH_COMPONENT32F, width, height, "receiver: depth");
    glGenFramebuffers(1, &r->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, r->visibility, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, r->distance, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, r->depth, 0);
    glDrawBuffers(2, (const GLenum[]){GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1});
    if (!gl_framebuffer_complete(r->fbo, "receiver pass")) {
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
}

bool receiver_program_animated(GLuint program)
{
    return glGetUniformLocation(program, "sm_noise_frame") >= 0;
}

GLuint receiver_program(const struct technique *t, const void *settings, enum light_shape shape)
{
    struct strbuf defines = {0};
    shadowmap_shader_defines(&defines);
    strbuf_printf(&defines, "#define SM_LIGHT_SHAPE %d\n", (int)shape);
    params_defines(t, settings, &defines);
    char *label = util_printf("receiver pass: %s, %s light", t->name, light_shape_names[shape]);
    GLuint p = shader_program(
        label, defines.data,
        (const struct shader_stage[]){{GL_VERTEX_SHADER, {"receiver.vert"}},
                                      {GL_FRAGMENT_SHADER, {"receiver.frag", t->shader}}},
        2);
    free(label);
    strbuf_free(&defines);
    return p;
}

void receiver_render(const struct receiver *r, GLuint program, const struct scene_mesh *mesh,
                     const struct shadowmap *sm)
{
    glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
    glViewport(0, 0, r->width, r->height);
    glClearBufferfv(GL_COLOR, 0, (const float[4]){1, 0, 0, 0});
    glClearBufferfv(GL_COLOR, 1, (const float[4]){-1, 0, 0, 0});
    glClearBufferfv(GL_DEPTH, 0, (const float[]){0.0f}); /* reversed Z: far */
    glUseProgram(program);
    glUniformMatrix4fv(glGetUniformLocation(program, "u_camera_view_proj"), 1, GL_FALSE,
                       r->view_proj.m);
    GLint cam = glGetUniformLocation(program, "u_camera_pos");
    glUniform3f(cam, r->camera_pos.x, r->camera_pos.y, r->camera_pos.z);
    glUniform1f(glGetUniformLocation(program, "sm_noise_frame"), r->noise_frame);  /* -1 (unused): ignored */
    shadowmap_bind(sm);
    scene_mesh_draw(mesh);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

static void read_flipped(GLenum attachment, int w, int h, float *out)
{
    glReadBuffer(attachment);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    float *tmp = xmalloc(sizeof(float) * (size_t)w * (size_t)h);
    glReadPixels(0, 0, w, h, GL_RED, GL_FLOAT, tmp);
    for (int y = 0; y < h; y++) /* GL's rows start at the bottom */
        memcpy(out + (size_t)y * w, tmp + (size_t)(h - 1 - y) * w, sizeof(float) * (size_t)w);
    free(tmp);
}

void receiver_read(const struct receiver *r, float *visibility, float *distance)
{
    glBindFramebuffer(GL_READ_FRAMEBUFFER, r->fbo);
    read_flipped(GL_COLOR_ATTACHMENT0, r->width, r->height, visibility);
    read_flipped(GL_COLOR_ATTACHMENT1, r->width, r->height, distance);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}

void receiver_destroy(struct receiver *r)
{
    if (r->fbo)
        glDeleteFramebuffers(1, &r->fbo);
    GLuint tex[3] = {r->visibility, r->distance, r->depth};
    glDeleteTextures(3, tex);
    memset(r, 0, sizeof *r);
}
