/* Runs a GLSL function of the shipped shaders on inputs a test chooses: a
 * fragment shader ("probe.frag", the test's source) that includes the
 * shaders under test, built from a copy of shaders/ in a scratch folder
 * with the layer's defines plus the test's, drawn over a width x height
 * RGBA32F target, one result per pixel. The test binds its inputs (the
 * layer's block and products, its own storage buffers) before the draw. */
#ifndef SB_GLSL_PROBE_H
#define SB_GLSL_PROBE_H

#include "check.h"
#include "base/util.h"
#include "gl/gl_context.h"
#include "gl/shader.h"
#include "techniques/shadowmap.h"

#include <stdlib.h>
#include <string.h>

/* The probe's program from source, built in dir; 0 if it does not build
 * (logged). */
static inline GLuint glsl_probe_program(const char *dir, const char *source, const char *defines)
{
    char *copy = util_printf("cp '%s'/shaders/* '%s'", SB_SOURCE_DIR, dir);
    char *path = util_printf("%s/probe.frag", dir);
    CHECK(system(copy) == 0, "%s", copy);
    util_write_file_atomic(path, source, strlen(source));
    struct strbuf all = {0};
    shadowmap_shader_defines(&all);
    strbuf_printf(&all, "#define SM_LIGHT_SHAPE SM_LIGHT_RECT\n%s", defines);
    GLuint program = 0;
    if (shader_init(dir) == 0)
        program = shader_program("probe", all.data,
                                 (const struct shader_stage[]){{GL_VERTEX_SHADER, {"fullscreen.vert"}},
                                                               {GL_FRAGMENT_SHADER, {"probe.frag"}}},
                                 2);
    strbuf_free(&all);
    free(copy), free(path);
    return program;
}

/* Draws program over a width x height target; results: width x height x 4
 * floats, row by row. */
static inline void glsl_probe_draw(GLuint program, int width, int height, float *results)
{
    GLuint vao, target = gl_texture_2d(GL_RGBA32F, width, height, "probe");
    const GLuint fbo = gl_framebuffer(&target, 1, 0, "probe");
    CHECK(fbo, "probe framebuffer");
    glGenVertexArrays(1, &vao);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);  /* gl_framebuffer leaves it unbound */
    glViewport(0, 0, width, height);
    glUseProgram(program);
    glBindVertexArray(vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, results);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteVertexArrays(1, &vao);
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(1, &target);
}

#endif
