/* The OSMesa backend: Mesa's llvmpipe in this process, no display. */
#include "gl_backend.h"
#include "base/log.h"

/* osmesa.h includes GL/gl.h, whose prototypes would clash with gl.h's
 * entry-point pointers of the same names; glcorearb.h (through gl.h)
 * already has every type it needs, so GL/gl.h is skipped through its
 * include guard. */
#define __gl_h_
#define GLAPIENTRY APIENTRY
#include <GL/osmesa.h>

#include <stdio.h>

static OSMesaContext context;
static unsigned char dummy_buffer[4 * 4 * 4]; /* OSMesa needs one; we render to FBOs */

static void osmesa_destroy(void)
{
    if (context) {
        OSMesaMakeCurrent(NULL, NULL, 0, 0, 0);  /* releases the framebuffer first */
        OSMesaDestroyContext(context);
    }
    context = NULL;
}

static int osmesa_create(char *platform, size_t size)
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
        osmesa_destroy();
        return -1;
    }
    snprintf(platform, size, "OSMesa");
    return 0;
}

static gl_proc osmesa_getproc(const char *name)
{
    return (gl_proc)OSMesaGetProcAddress(name);
}

const struct gl_backend_ops gl_backend_osmesa = {osmesa_create, osmesa_destroy, osmesa_getproc};
