/* The GLFW backend: a window with a GL 4.5 core context (the viewer). Its
 * default framebuffer is the window; every pass still renders into its own
 * framebuffer objects, and the viewer copies its picture to the window. */
#include "gl_backend.h"
#include "gl_window.h"
#include "base/log.h"

/* glfw3.h would include GL/gl.h, whose prototypes would clash with gl.h's
 * entry-point pointers of the same names. */
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <stdio.h>

static GLFWwindow *window;
static struct {
    int width, height;
    const char *title;
} wanted = {512, 512, "shadowbench"};

void gl_window_request(int width, int height, const char *title)
{
    wanted.width = width, wanted.height = height, wanted.title = title;
}

GLFWwindow *gl_window(void)
{
    return window;
}

/* GLFW stays initialised once a window was made (no glfwTerminate), for
 * the reason gl_egl.c keeps its display: closing the X connection unloads
 * Mesa's driver, which leaves 240 bytes it allocated unreferenced,
 * reported by LeakSanitizer against an unknown module. One window per
 * process. */
static void glfw_destroy(void)
{
    if (window)
        glfwDestroyWindow(window);
    window = NULL;
}

static int glfw_create(char *platform, size_t size)
{
    const char *why = NULL;
    if (!glfwInit()) {
        glfwGetError(&why);
        log_error("view: no window system (%s); without a display, run it under xvfb-run",
                  why ? why : "glfwInit failed");
        glfwTerminate();
        return -1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_DOUBLEBUFFER, GLFW_TRUE);
    window = glfwCreateWindow(wanted.width, wanted.height, wanted.title, NULL, NULL);
    if (!window) {
        glfwGetError(&why);
        log_error("view: no window with a GL 4.5 core context (%s)", why ? why : "glfwCreateWindow failed");
        glfwTerminate();
        return -1;
    }
    glfwMakeContextCurrent(window);
    snprintf(platform, size, "GLFW window");
    return 0;
}

static gl_proc glfw_getproc(const char *name)
{
    return (gl_proc)glfwGetProcAddress(name);
}

const struct gl_backend_ops gl_backend_glfw = {glfw_create, glfw_destroy, glfw_getproc};
