#include "gl_context.h"
#include "gl.h"
#include "base/log.h"

/* osmesa.h includes GL/gl.h, whose prototypes would clash with gl.h's
 * entry-point pointers of the same names; glcorearb.h (through gl.h)
 * already has every type it needs, so GL/gl.h is skipped through its
 * include guard. */
#define __gl_h_
#define GLAPIENTRY APIENTRY
#include <GL/osmesa.h>

#include <stddef.h>

static OSMesaContext context;
static unsigned char dummy_buffer[4 * 4 * 4]; /* OSMesa needs one; we render to FBOs */

static gl_proc osmesa_getproc(const char *name)
{
    return (gl_proc)OSMesaGetProcAddress(name);
}

int gl_context_create(void)
{
    static const int attribs[] = {
        OSMESA_FORMAT, OSMESA_RGBA,
        OSMESA_DEPTH_BITS, 0,
        OSMESA_PROFILE, OSMESA_CORE_PROFILE,
        OSMESA_CONTEXT_MAJOR_VERSION, 4,
        OSMESA_CONTEXT_MINOR_VERSION, 5,
        0,
    };
    context = OSMesaCreateContextAttribs(attribs, NULL);
    if (!context) {
        log_error("OpenGL: OSMesa could not create a 4.5 core context (is libosmesa6 installed?)");
        return -1;
    }
    if (!OSMesaMakeCurrent(context, dummy_buffer, GL_UNSIGNED_BYTE, 4, 4)) {
        log_error("OpenGL: OSMesaMakeCurrent failed");
        gl_context_destroy();
        return -1;
    }
    if (!gl_load(osmesa_getproc)) {
        gl_context_destroy();
        return -1;
    }
    gl_install_debug_output();
    /* Reversed Z in [0, 1] for every depth buffer: near = 1, far = 0, so
     * float depth keeps its precision where perspective needs it. */
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_GREATER);
    glEnable(GL_DEPTH_TEST);
    log_debug("OpenGL: %s, %s", gl_context_renderer(), gl_context_version());
    return 0;
}

void gl_context_destroy(void)
{
    if (context) {
        OSMesaMakeCurrent(NULL, NULL, 0, 0, 0);  /* releases the framebuffer first */
        OSMesaDestroyContext(context);
    }
    context = NULL;
}

const char *gl_context_renderer(void)
{
    return context ? (const char *)glGetString(GL_RENDERER) : "none";
}

const char *gl_context_version(void)
{
    return context ? (const char *)glGetString(GL_VERSION) : "none";
}
