#include "gl.h"
#include "base/log.h"
#include "base/util.h"

#include <stdlib.h>
#include <string.h>

#define X(type, name) GL_ENTRY_POINT type name;
GL_FUNCS(X)
GL_TEST_FUNCS(X)
#undef X

bool gl_load(gl_proc (*getproc)(const char *name), bool with_tests)
{
    bool ok = true;
#define X(type, name)                                              \
    name = (type)getproc(#name);                                   \
    if (!name) {                                                   \
        log_error("OpenGL: %s is not available from this driver", #name); \
        ok = false;                                                \
    }
    GL_FUNCS(X)
    if (with_tests) {
        GL_TEST_FUNCS(X)
    }
#undef X
    return ok;
}

static const char *debug_source(GLenum s)
{
    switch (s) {
    case GL_DEBUG_SOURCE_API: return "api";
    case GL_DEBUG_SOURCE_SHADER_COMPILER: return "shader compiler";
    case GL_DEBUG_SOURCE_WINDOW_SYSTEM: return "window system";
    case GL_DEBUG_SOURCE_APPLICATION: return "application";
    default: return "other";
    }
}

static void APIENTRY on_debug_message(GLenum source, GLenum type, GLuint id, GLenum severity,
                                      GLsizei length, const GLchar *message, const void *user)
{
    (void)length, (void)user;
    enum log_level level = type == GL_DEBUG_TYPE_ERROR ? LOG_ERROR
                           : severity == GL_DEBUG_SEVERITY_HIGH || severity == GL_DEBUG_SEVERITY_MEDIUM
                               ? LOG_WARN
                               : LOG_DEBUG;
    log_msg(level, "OpenGL (%s, id %u): %s", debug_source(source), id, message);
}

void gl_install_debug_output(void)
{
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS); /* messages arrive at the offending call */
    glDebugMessageCallback(on_debug_message, NULL);
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, NULL, GL_TRUE);
}

GLuint gl_framebuffer(const GLuint *colors, int count, GLuint depth, const char *label)
{
    GLuint fbo;
    GLenum buffers[8] = {GL_NONE};
    if (count > 8) {
        log_error("%s: %d colour attachments, at most 8", label, count);
        return 0;
    }
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    for (int i = 0; i < count; i++) {
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)i, GL_TEXTURE_2D, colors[i], 0);
        buffers[i] = GL_COLOR_ATTACHMENT0 + (GLenum)i;
    }
    if (depth)
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth, 0);
    glDrawBuffers(count > 0 ? count : 1, buffers);
    if (count == 0)
        glReadBuffer(GL_NONE);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    gl_label(GL_FRAMEBUFFER, fbo, label);
    if (status == GL_FRAMEBUFFER_COMPLETE)
        return fbo;
    log_error("%s: framebuffer incomplete (0x%x)", label, status);
    glDeleteFramebuffers(1, &fbo);
    return 0;
}

void gl_label(GLenum type, GLuint object, const char *label)
{
    glObjectLabel(type, object, (GLsizei)strlen(label), label);
}

GLuint gl_texture_2d(GLenum format, int width, int height, const char *label)
{
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexStorage2D(GL_TEXTURE_2D, 1, format, width, height);
    gl_label(GL_TEXTURE, t, label);
    return t;
}

static void read_rows(GLenum attachment, GLenum format, int channels, int width, int height, float *out)
{
    glReadBuffer(attachment);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    const size_t row = (size_t)channels * (size_t)width;
    float *tmp = xmalloc(sizeof(float) * row * (size_t)height);
    glReadPixels(0, 0, width, height, format, GL_FLOAT, tmp);
    for (int y = 0; y < height; y++)
        memcpy(out + (size_t)y * row, tmp + (size_t)(height - 1 - y) * row, sizeof(float) * row);
    free(tmp);
}

void gl_read_red(GLenum attachment, int width, int height, float *out)
{
    read_rows(attachment, GL_RED, 1, width, height, out);
}

void gl_read_rgba(GLenum attachment, int width, int height, float *out)
{
    read_rows(attachment, GL_RGBA, 4, width, height, out);
}
