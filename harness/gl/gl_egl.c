/* The EGL backend, headless: a GPU through EGL_EXT_platform_device where
 * one is present, else Mesa's surfaceless platform (llvmpipe, as OSMesa).
 * No window and no surface: every pass renders into its own framebuffer
 * object (EGL_KHR_surfaceless_context). */
#include "gl_backend.h"
#include "base/log.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <stdio.h>
#include <string.h>

static EGLDisplay display = EGL_NO_DISPLAY;
static EGLContext context = EGL_NO_CONTEXT;

/* Whether the space-separated list `list` holds `name` as a whole word. */
static bool has_extension(const char *list, const char *name)
{
    const size_t n = strlen(name);
    for (const char *p = list; p && (p = strstr(p, name)); p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return true;
    return false;
}

/* The first hardware device that initialises (Mesa lists llvmpipe as a
 * device too, EGL_MESA_device_software: left to the surfaceless platform,
 * which names it), else the surfaceless platform. */
static EGLDisplay open_display(char *platform, size_t size)
{
    const char *client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_display =
        (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    PFNEGLQUERYDEVICESEXTPROC query_devices = (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
    PFNEGLQUERYDEVICESTRINGEXTPROC device_string =
        (PFNEGLQUERYDEVICESTRINGEXTPROC)eglGetProcAddress("eglQueryDeviceStringEXT");
    if (!client || !get_display)
        return EGL_NO_DISPLAY;
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (has_extension(client, "EGL_EXT_platform_device") && query_devices && device_string &&
        query_devices(16, devices, &count))
        for (EGLint i = 0; i < count; i++) {
            if (has_extension(device_string(devices[i], EGL_EXTENSIONS), "EGL_MESA_device_software"))
                continue;
            EGLDisplay d = get_display(EGL_PLATFORM_DEVICE_EXT, devices[i], NULL);
            if (d != EGL_NO_DISPLAY && eglInitialize(d, NULL, NULL)) {
                snprintf(platform, size, "EGL device %d", (int)i);
                return d;
            }
        }
    if (has_extension(client, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay d = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
        if (d != EGL_NO_DISPLAY && eglInitialize(d, NULL, NULL)) {
            snprintf(platform, size, "EGL surfaceless");
            return d;
        }
    }
    return EGL_NO_DISPLAY;
}

/* The display stays initialised: eglTerminate would unload Mesa's driver,
 * which leaves 240 bytes it allocated unreferenced; LeakSanitizer reports
 * them against an unknown module, which no suppression can name. A
 * display is process-wide, and shadowbench opens one per process. */
static void egl_destroy(void)
{
    if (display != EGL_NO_DISPLAY) {
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (context != EGL_NO_CONTEXT)
            eglDestroyContext(display, context);
        eglReleaseThread();
    }
    display = EGL_NO_DISPLAY;
    context = EGL_NO_CONTEXT;
}

static int egl_create(char *platform, size_t size)
{
    display = open_display(platform, size);
    if (display == EGL_NO_DISPLAY) {
        log_error("OpenGL: EGL found no display: neither a GPU (EGL_EXT_platform_device) nor Mesa's surfaceless "
                  "platform (is libegl1-mesa installed?)");
        return -1;
    }
    const char *ext = eglQueryString(display, EGL_EXTENSIONS);
    if (!has_extension(ext, "EGL_KHR_surfaceless_context") || !eglBindAPI(EGL_OPENGL_API)) {
        log_error("OpenGL: %s offers no desktop OpenGL context without a surface", platform);
        egl_destroy();
        return -1;
    }
    /* No config where the display allows it; else any that renders GL. */
    EGLConfig config = EGL_NO_CONFIG_KHR;
    EGLint configs = 0;
    static const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
    if (!has_extension(ext, "EGL_KHR_no_config_context") &&
        (!eglChooseConfig(display, config_attribs, &config, 1, &configs) || configs < 1)) {
        log_error("OpenGL: %s has no config for desktop OpenGL", platform);
        egl_destroy();
        return -1;
    }
    static const EGLint context_attribs[] = {
        EGL_CONTEXT_MAJOR_VERSION, 4,
        EGL_CONTEXT_MINOR_VERSION, 5,
        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
        EGL_NONE,
    };
    context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attribs);
    if (context == EGL_NO_CONTEXT || !eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
        log_error("OpenGL: %s could not create a 4.5 core context (EGL error 0x%x)", platform, eglGetError());
        egl_destroy();
        return -1;
    }
    return 0;
}

static gl_proc egl_getproc(const char *name)
{
    return (gl_proc)eglGetProcAddress(name);
}

const struct gl_backend_ops gl_backend_egl = {egl_create, egl_destroy, egl_getproc};
