/* The headless GL 4.5 core context, from one of two backends: OSMesa
 * (llvmpipe in this process, the default) or EGL (a GPU through
 * EGL_EXT_platform_device where one is present, else Mesa's surfaceless
 * platform). Both render into the same framebuffer objects; GL functions
 * load through the backend's getproc from gl.h's one list. */
#ifndef SB_GL_CONTEXT_H
#define SB_GL_CONTEXT_H

#include <stdbool.h>

/* GLFW: a window, for the viewer only (gl_window.h); not a --gl choice. */
enum gl_backend { GL_BACKEND_OSMESA, GL_BACKEND_EGL, GL_BACKEND_GLFW };

/* "osmesa" or "egl" into *out: 0, or -1 for another name (not logged). */
int gl_backend_parse(const char *name, enum gl_backend *out);

/* The least address space (ulimit -v) a context is made under: below it
 * Mesa's llvmpipe crashes rather than failing (gl_context.c). */
#define GL_MIN_ADDRESS_SPACE_MIB 1024

/* Creates and makes current a GL 4.5 core context, loads the entry points,
 * installs debug output and sets the conventions every pass relies on
 * (glClipControl zero-to-one with reversed Z). Returns 0 or -1 (one
 * logged line: also an address-space limit below
 * GL_MIN_ADDRESS_SPACE_MIB). */
int gl_context_create(enum gl_backend backend);
void gl_context_destroy(void);

/* Loads the read-backs only tests call (gl.h: GL_TEST_FUNCS) into the
 * current context. */
bool gl_context_load_test_functions(void);

/* GL_RENDERER, GL_VENDOR and GL_VERSION of the current context, and where
 * it runs ("OSMesa", "EGL device 0", "EGL surfaceless"); "none" without. */
const char *gl_context_renderer(void);
const char *gl_context_vendor(void);
const char *gl_context_version(void);
const char *gl_context_platform(void);

/* Whether the renderer rasterises on the CPU (llvmpipe, softpipe): there
 * stages are timed by wall clock around glFinish (a query is no measure of
 * a CPU's pipeline, though on llvmpipe reading one waits for the work and
 * gave the same times, docs/metrics.md), on a GPU by GL_TIME_ELAPSED queries. */
bool gl_context_is_cpu(void);

#endif
