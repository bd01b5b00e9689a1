#include "irradiance.h"
#include "base/util.h"
#include "gl/shader.h"

#include <math.h>
#include <string.h>

int irradiance_create(struct irradiance_pass *p, const struct scene *s, int width, int height)
{
    memset(p, 0, sizeof *p);
    p->width = width, p->height = height;
    struct strbuf defines = {0};
    shadowmap_shader_defines(&defines);  /* shadow_common.glsl's, for its facing normal */
    strbuf_printf(&defines, "#define SM_LIGHT_SHAPE %d\n", (int)s->light.shape);
    p->program = shader_program("unshadowed irradiance", defines.data,
                                (const struct shader_stage[]){{GL_VERTEX_SHADER, {"receiver.vert"}},
                                                              {GL_FRAGMENT_SHADER, {"view_shading.frag"}}},
                                2);
    strbuf_free(&defines);
    if (!p->program)
        return -1;
    p->target = gl_texture_2d(GL_R32F, width, height, "irradiance");
    p->depth = gl_texture_2d(GL_DEPTH_COMPONENT32F, width, height, "irradiance depth");
    p->fbo = gl_framebuffer(&p->target, 1, p->depth, "irradiance pass");
    return p->fbo ? 0 : -1;
}

double irradiance_render(const struct irradiance_pass *p, const struct scene *s, const struct receiver *r,
                         const struct scene_mesh *mesh, float *out)
{
    const struct scene_light *L = &s->light;
    const GLuint prog = p->program;
    glBindFramebuffer(GL_FRAMEBUFFER, p->fbo);
    glViewport(0, 0, p->width, p->height);
    glClearBufferfv(GL_COLOR, 0, (const float[4]){-1, 0, 0, 0});  /* no geometry */
    glClearBufferfv(GL_DEPTH, 0, (const float[]){0.0f});
    glUseProgram(prog);
    glUniformMatrix4fv(glGetUniformLocation(prog, "u_camera_view_proj"), 1, GL_FALSE, r->view_proj.m);
    const struct vec3 cam = r->camera_pos;
    glUniform3f(glGetUniformLocation(prog, "u_camera_pos"), cam.x, cam.y, cam.z);
    glUniform3f(glGetUniformLocation(prog, "u_light_pos"), L->pos.x, L->pos.y, L->pos.z);
    glUniform3f(glGetUniformLocation(prog, "u_light_x"), L->x.x, L->x.y, L->x.z);
    glUniform3f(glGetUniformLocation(prog, "u_light_y"), L->y.x, L->y.y, L->y.z);
    glUniform3f(glGetUniformLocation(prog, "u_light_z"), L->z.x, L->z.y, L->z.z);
    glUniform1f(glGetUniformLocation(prog, "u_light_half_width"), 0.5f * L->width);
    glUniform1f(glGetUniformLocation(prog, "u_light_half_height"), 0.5f * L->height);
    glUniform1f(glGetUniformLocation(prog, "u_light_radius"), L->shape == LIGHT_SUN ? tanf(L->half_angle) : L->radius);
    glUniform1i(glGetUniformLocation(prog, "u_light_disk"), L->shape != LIGHT_RECT);
    glUniform1i(glGetUniformLocation(prog, "u_light_sun"), L->shape == LIGHT_SUN);
    scene_mesh_draw(mesh);
    gl_read_red(GL_COLOR_ATTACHMENT0, p->width, p->height, out);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    double sum = 0;
    long n = 0;
    for (size_t i = 0; i < (size_t)p->width * (size_t)p->height; i++)
        if (out[i] >= 0)
            sum += out[i], n++;
    return n ? sum / (double)n : 0;
}

void irradiance_destroy(struct irradiance_pass *p)
{
    if (p->program)
        glDeleteProgram(p->program);
    if (p->fbo)
        glDeleteFramebuffers(1, &p->fbo);
    GLuint textures[] = {p->target, p->depth};
    glDeleteTextures(2, textures);
    memset(p, 0, sizeof *p);
}
