/* The two implementations behind gl_context.h: each creates a headless GL
 * 4.5 core context and makes it current; gl_context.c does the rest
 * (entry points, debug output, conventions) the same way for both. */
#ifndef SB_GL_BACKEND_H
#define SB_GL_BACKEND_H

#include "gl.h"

#include <stddef.h>

struct gl_backend_ops {
    /* Creates the context and makes it current; where it runs in words
     * into platform ("OSMesa", "EGL device 0", "EGL surfaceless"). Returns
     * 0, or -1 after one logged line. */
    int (*create)(char *platform, size_t size);
    void (*destroy)(void);
    gl_proc (*getproc)(const char *name);
};

extern const struct gl_backend_ops gl_backend_osmesa, gl_backend_egl, gl_backend_glfw;

#endif
