/* The headless GL 4.5 core context (OSMesa on llvmpipe): the default and
 * the only one the harness needs. */
#ifndef SB_GL_CONTEXT_H
#define SB_GL_CONTEXT_H

/* Creates and makes current a GL 4.5 core context, loads the entry points,
 * installs debug output and sets the conventions every pass relies on
 * (glClipControl zero-to-one with reversed Z). Returns 0 or -1 (logged). */
int gl_context_create(void);
void gl_context_destroy(void);

/* GL_RENDERER / GL_VERSION strings of the current context. */
const char *gl_context_renderer(void);
const char *gl_context_version(void);

#endif
