/* shadowbench view: the interactive viewer (view/viewer.h) in a GLFW
 * window; --script replays key events, --screenshot writes the window as a
 * PNG. */
#include "cli.h"
#include "base/log.h"
#include "base/util.h"
#include "gl/gl_window.h"
#include "view/script.h"
#include "view/viewer.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void key_callback(GLFWwindow *win, int key, int scancode, int action, int mods)
{
    (void)scancode;
    if (action == GLFW_PRESS || action == GLFW_REPEAT)
        viewer_key(glfwGetWindowUserPointer(win), key, mods);
}

static void cursor_callback(GLFWwindow *win, double x, double y)
{
    struct viewer *v = glfwGetWindowUserPointer(win);
    const float dx = (float)(x - v->mouse_x), dy = (float)(y - v->mouse_y);
    v->mouse_x = x, v->mouse_y = y;
    int width, height;
    glfwGetWindowSize(win, &width, &height);
    viewer_drag(v, dx, dy, glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS,
                glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS, width);
}

static void scroll_callback(GLFWwindow *win, double xoff, double yoff)
{
    (void)xoff;
    viewer_scroll(glfwGetWindowUserPointer(win), yoff);
}

/* A screenshot's path, checked before the window opens: a file name in a
 * writable folder, and nothing there yet but a regular file (the PNG
 * replaces what is there: a device, a FIFO or a link would be lost). */
static int check_screenshot_path(const char *path)
{
    struct stat st;
    const size_t len = strlen(path);
    const char *why = !len                                       ? "an empty file name"
                      : path[len - 1] == '/' || util_is_dir(path) ? "a folder, not a file"
                      : lstat(path, &st) == 0 && !S_ISREG(st.st_mode)
                          ? "not a regular file (a device, FIFO or link is not replaced)"
                          : NULL;
    if (why) {
        log_error("--screenshot %s: %s", path, why);
        return -1;
    }
    const char *slash = strrchr(path, '/');
    char *dir = slash ? util_printf("%.*s", slash == path ? 1 : (int)(slash - path), path) : xstrdup(".");
    const bool ok = util_is_dir(dir) && access(dir, W_OK) == 0;
    if (!ok)
        log_error("--screenshot %s: %s is not a writable folder", path, dir);
    free(dir);
    return ok ? 0 : -1;
}

/* Draws frames until the window closes, Esc, or --frames; the screenshot
 * after the last. Returns the exit status. */
static int run_window(struct viewer *v, GLFWwindow *win, const struct options *o, const struct script_event *script,
                      int events)
{
    const int frames = o->frames;  /* 0: until the window closes */
    int next_event = 0;
    for (int frame = 0; frames == 0 || frame < frames; frame++) {
        glfwPollEvents();
        for (; next_event < events && script[next_event].frame <= frame; next_event++)
            viewer_key(v, script[next_event].key, script[next_event].mods);
        if (v->quit || glfwWindowShouldClose(win)) {
            if (o->screenshot) {
                log_error("view: closed before frame %d of %d: %s not written", frame + 1, frames, o->screenshot);
                return EXIT_CHECK_FAILED;
            }
            return EXIT_OK;
        }
        viewer_apply_pose(v);
        /* the screenshot's frame waits for the pose's finished ground truth,
         * so that what it shows does not depend on the machine's speed */
        const bool last = frames && frame == frames - 1;
        if (viewer_frame(v, last && o->screenshot) != 0)
            return EXIT_CHECK_FAILED;
        int fw, fh;
        glfwGetFramebufferSize(win, &fw, &fh);
        viewer_present(v, fw, fh);
        if (last && o->screenshot && viewer_screenshot(fw, fh, o->screenshot) != 0)
            return EXIT_CHECK_FAILED;
        glfwSwapBuffers(win);
    }
    return EXIT_OK;
}

int view_main(const struct options *o)
{
    static struct script_event script[SCRIPT_MAX_EVENTS];
    int events = 0;
    if (o->script && (events = script_load(o->script, script, SCRIPT_MAX_EVENTS)) < 0)
        return EXIT_USAGE;
    if (events && o->frames && script[events - 1].frame >= o->frames) {  /* it would never be pressed */
        log_error("--script %s: a key at frame %d, past the last of --frames %d (frames count from 0)", o->script,
                  script[events - 1].frame, o->frames);
        return EXIT_USAGE;
    }
    if (o->screenshot && check_screenshot_path(o->screenshot) != 0)
        return EXIT_USAGE;
    struct scene s;
    int scene_count = 0;
    if (cli_load_scenes(o, NULL, 0, &s, 1, &scene_count) != 0) {
        if (scene_count)
            scene_free(&s);
        return EXIT_USAGE;
    }
    char *title = util_printf("shadowbench view: %s", s.name);
    gl_window_request(o->width, o->height, title);
    if (cli_gl_open(o, GL_BACKEND_GLFW) != 0) {
        free(title);
        scene_free(&s);
        return EXIT_USAGE;
    }
    GLFWwindow *win = gl_window();
    glfwSwapInterval(o->screenshot ? 0 : 1);
    log_info("view: %s, %d x %d, OpenGL %s; keys: shadowbench view --help", s.name, o->width, o->height,
             gl_context_renderer());

    struct viewer_desc d = {.width = o->width, .height = o->height, .gt_samples = o->gt_samples,
                            .shadow_map_size = o->shadow_map_size, .cascades = &o->cascades,
                            .technique_count = o->technique_count};
    for (int i = 0; i < o->technique_count; i++)
        d.techniques[i] = o->techniques[i], d.settings[i] = cli_settings(o, o->techniques[i]);
    static struct viewer v;  /* large; one per process */
    int status = viewer_open(&v, &d, &s) == 0 ? EXIT_OK : EXIT_CHECK_FAILED;
    glfwSetWindowUserPointer(win, &v);
    glfwSetKeyCallback(win, key_callback);
    glfwSetCursorPosCallback(win, cursor_callback);
    glfwSetScrollCallback(win, scroll_callback);
    glfwGetCursorPos(win, &v.mouse_x, &v.mouse_y);
    if (status == EXIT_OK)
        status = run_window(&v, win, o, script, events);
    if (status == EXIT_OK) {
        char summary[512];
        viewer_summary(&v, summary, sizeof summary);
        log_info("view: %s", summary);
    }
    viewer_free(&v);
    gl_context_destroy();
    free(title);
    scene_free(&s);
    return status;
}
