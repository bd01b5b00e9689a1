/* The viewer's context: a window from GLFW (gl_context_create with
 * GL_BACKEND_GLFW), sized and titled by gl_window_request beforehand. */
#ifndef SB_GL_WINDOW_H
#define SB_GL_WINDOW_H

typedef struct GLFWwindow GLFWwindow;

/* The next GLFW context's window: its size in screen coordinates, its title. */
void gl_window_request(int width, int height, const char *title);

/* The window of the current GLFW context, or NULL. */
GLFWwindow *gl_window(void);

#endif
