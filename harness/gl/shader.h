/* GLSL programs from files in shaders/, composed with a small
 * `#include "file.glsl"` mechanism. Compile and link errors name the file and
 * its own line number (STYLE.md item 8). */
#ifndef SB_SHADER_H
#define SB_SHADER_H

#include "gl.h"

/* Where shaders are read from: `dir` if non-NULL, else $SHADOWBENCH_SHADERS,
 * next to the executable, the source tree. Returns 0 or -1 (logged). */
int shader_init(const char *dir);

/* The path of `file` in the shaders folder (a data file the shaders read
 * as a texture), newly malloc'ed; shader_init must have succeeded. */
char *shader_path(const char *file);

/* One stage is composed from up to three files, in order (the first has
 * the #version line): e.g. the receiver pass is receiver.frag followed by the
 * technique's file, which defines shadow_visibility(). */
struct shader_stage {
    GLenum type;           /* GL_VERTEX_SHADER, GL_FRAGMENT_SHADER, GL_COMPUTE_SHADER */
    const char *files[3];  /* relative to the shaders folder; unused ones NULL */
};

/* Compiles and links the stages into a labelled program. `defines` (may be
 * NULL) is inserted after each stage's #version line: this is how variants
 * and technique parameters reach a shader. Returns 0 on failure (logged). */
GLuint shader_program(const char *label, const char *defines, const struct shader_stage *stages,
                      int stage_count);

#endif
