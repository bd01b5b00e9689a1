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
    r->camera_fwd = v3_scale(c->z, -1.0f);
}

bool receiver_program_animated(GLuint program)
{
    return glGetUniformLocation(program, "sm_noise_frame") >= 0;
}

GLuint receiver_program(const struct technique *t, const void *settings, enum light_shape shape)
{
    struct strbuf defines = {0};
    shadowmap_shader_defines(&defines);
    strbuf_printf(&defines, "#define SM_CASCADES_MAX %d\n", CASCADES_MAX);
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
                     const struct shadow_cascades *c)
{
    glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
    glViewport(0, 0, r->width, r->height);
    /* One map: V itself. Cascades add up w_c V_c, from 0. */
    glClearBufferfv(GL_COLOR, 0, (const float[4]){c->count > 1 ? 0.0f : 1.0f, 0, 0, 0});
    glClearBufferfv(GL_COLOR, 1, (const float[4]){-1, 0, 0, 0});
    glClearBufferfv(GL_DEPTH, 0, (const float[]){0.0f}); /* reversed Z: far */
    glUseProgram(program);
    glUniformMatrix4fv(glGetUniformLocation(program, "u_camera_view_proj"), 1, GL_FALSE,
                       r->view_proj.m);
    glUniform3f(glGetUniformLocation(program, "u_camera_pos"), r->camera_pos.x, r->camera_pos.y, r->camera_pos.z);
    glUniform3f(glGetUniformLocation(program, "u_camera_fwd"), r->camera_fwd.x, r->camera_fwd.y, r->camera_fwd.z);
    glUniform1f(glGetUniformLocation(program, "sm_noise_frame"), r->noise_frame);  /* -1 (unused): ignored */
    glUniform1i(glGetUniformLocation(program, "u_cascade_count"), c->count);
    glUniform1fv(glGetUniformLocation(program, "u_cascade_z"), c->count + 1, c->z);
    glUniform1fv(glGetUniformLocation(program, "u_cascade_band"), c->count, c->band);
    const GLint which = glGetUniformLocation(program, "u_cascade");
    for (int k = 0; k < c->count; k++) {
        if (k == 1) {  /* the first pass laid the depth: the others shade the same surface, adding */
            glEnablei(GL_BLEND, 0);
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
        glDepthFunc(GL_GREATER);
        glDepthMask(GL_TRUE);
    }
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
