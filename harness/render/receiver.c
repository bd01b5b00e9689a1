#include "receiver.h"
#include "base/log.h"
#include "base/util.h"
#include "gl/shader.h"
#include "techniques/params.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int receiver_create(struct receiver *r, const struct scene *s, int width, int height)
{
    memset(r, 0, sizeof *r);
    r->width = width;
    r->height = height;
    receiver_set_camera(r, s);

    r->visibility = gl_texture_2d(GL_R32F, width, height, "receiver: visibility");
    r->distance = gl_texture_2d(GL_R32F, width, height, "receiver: camera distance");
    r->depth = gl_texture_2d(GL_DEPTH_COMPONENT32F, width, height, "receiver: depth");
    r->fbo = gl_framebuffer((const GLuint[]){r->visibility, r->distance}, 2, r->depth, "receiver pass");
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

void receiver_read(const struct receiver *r, float *visibility, float *distance)
{
    glBindFramebuffer(GL_READ_FRAMEBUFFER, r->fbo);
    gl_read_red(GL_COLOR_ATTACHMENT0, r->width, r->height, visibility);
    gl_read_red(GL_COLOR_ATTACHMENT1, r->width, r->height, distance);
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
