/* The GL 4.5 core entry points shadowbench uses, loaded at run time through
 * a getproc function (OSMesaGetProcAddress or eglGetProcAddress headless,
 * gl_context.h's backends; glfwGetProcAddress in the viewer): libOSMesa does not export every 4.5 function, so nothing is
 * linked directly. Adding a function is one line in GL_FUNCS; gl_load()
 * refuses to start when one is missing, so list only what is called. */
#ifndef SB_GL_H
#define SB_GL_H

#include <GL/glcorearb.h>

#include <stdbool.h>

#define GL_FUNCS(X) \
    X(PFNGLGETSTRINGPROC, glGetString) \
    X(PFNGLENABLEPROC, glEnable) \
    X(PFNGLVIEWPORTPROC, glViewport) \
    X(PFNGLCLEARBUFFERFVPROC, glClearBufferfv) \
    X(PFNGLDEPTHFUNCPROC, glDepthFunc) \
    X(PFNGLCLIPCONTROLPROC, glClipControl) \
    X(PFNGLFINISHPROC, glFinish) \
    X(PFNGLREADPIXELSPROC, glReadPixels) \
    X(PFNGLPIXELSTOREIPROC, glPixelStorei) \
    X(PFNGLGENTEXTURESPROC, glGenTextures) \
    X(PFNGLDELETETEXTURESPROC, glDeleteTextures) \
    X(PFNGLBINDTEXTUREPROC, glBindTexture) \
    X(PFNGLTEXSTORAGE2DPROC, glTexStorage2D) \
    X(PFNGLTEXSTORAGE3DPROC, glTexStorage3D) \
    X(PFNGLFRAMEBUFFERTEXTURELAYERPROC, glFramebufferTextureLayer) \
    X(PFNGLTEXPARAMETERIPROC, glTexParameteri) \
    X(PFNGLBINDTEXTUREUNITPROC, glBindTextureUnit) \
    X(PFNGLGENERATEMIPMAPPROC, glGenerateMipmap) \
    X(PFNGLGENFRAMEBUFFERSPROC, glGenFramebuffers) \
    X(PFNGLDELETEFRAMEBUFFERSPROC, glDeleteFramebuffers) \
    X(PFNGLBINDFRAMEBUFFERPROC, glBindFramebuffer) \
    X(PFNGLFRAMEBUFFERTEXTURE2DPROC, glFramebufferTexture2D) \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, glCheckFramebufferStatus) \
    X(PFNGLDRAWBUFFERSPROC, glDrawBuffers) \
    X(PFNGLREADBUFFERPROC, glReadBuffer) \
    X(PFNGLBLITFRAMEBUFFERPROC, glBlitFramebuffer) \
    X(PFNGLTEXSUBIMAGE2DPROC, glTexSubImage2D) \
    X(PFNGLTEXTURESUBIMAGE2DPROC, glTextureSubImage2D) \
    X(PFNGLGENBUFFERSPROC, glGenBuffers) \
    X(PFNGLDELETEBUFFERSPROC, glDeleteBuffers) \
    X(PFNGLBINDBUFFERPROC, glBindBuffer) \
    X(PFNGLBUFFERDATAPROC, glBufferData) \
    X(PFNGLBUFFERSUBDATAPROC, glBufferSubData) \
    X(PFNGLBINDBUFFERBASEPROC, glBindBufferBase) \
    X(PFNGLGENVERTEXARRAYSPROC, glGenVertexArrays) \
    X(PFNGLDELETEVERTEXARRAYSPROC, glDeleteVertexArrays) \
    X(PFNGLBINDVERTEXARRAYPROC, glBindVertexArray) \
    X(PFNGLVERTEXATTRIBPOINTERPROC, glVertexAttribPointer) \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, glEnableVertexAttribArray) \
    X(PFNGLDRAWELEMENTSPROC, glDrawElements) \
    X(PFNGLDRAWARRAYSPROC, glDrawArrays) \
    X(PFNGLCREATESHADERPROC, glCreateShader) \
    X(PFNGLSHADERSOURCEPROC, glShaderSource) \
    X(PFNGLCOMPILESHADERPROC, glCompileShader) \
    X(PFNGLGETSHADERIVPROC, glGetShaderiv) \
    X(PFNGLGETSHADERINFOLOGPROC, glGetShaderInfoLog) \
    X(PFNGLDELETESHADERPROC, glDeleteShader) \
    X(PFNGLCREATEPROGRAMPROC, glCreateProgram) \
    X(PFNGLATTACHSHADERPROC, glAttachShader) \
    X(PFNGLLINKPROGRAMPROC, glLinkProgram) \
    X(PFNGLGETPROGRAMIVPROC, glGetProgramiv) \
    X(PFNGLGETPROGRAMINFOLOGPROC, glGetProgramInfoLog) \
    X(PFNGLDELETEPROGRAMPROC, glDeleteProgram) \
    X(PFNGLUSEPROGRAMPROC, glUseProgram) \
    X(PFNGLGETUNIFORMLOCATIONPROC, glGetUniformLocation) \
    X(PFNGLUNIFORM1IPROC, glUniform1i) \
    X(PFNGLUNIFORM1FPROC, glUniform1f) \
    X(PFNGLUNIFORM3FPROC, glUniform3f) \
    X(PFNGLUNIFORMMATRIX4FVPROC, glUniformMatrix4fv) \
    X(PFNGLDEBUGMESSAGECALLBACKPROC, glDebugMessageCallback) \
    X(PFNGLDEBUGMESSAGECONTROLPROC, glDebugMessageControl) \
    X(PFNGLOBJECTLABELPROC, glObjectLabel) \
    X(PFNGLDISPATCHCOMPUTEPROC, glDispatchCompute) \
    X(PFNGLMEMORYBARRIERPROC, glMemoryBarrier) \
    X(PFNGLGENQUERIESPROC, glGenQueries) \
    X(PFNGLDELETEQUERIESPROC, glDeleteQueries) \
    X(PFNGLBEGINQUERYPROC, glBeginQuery) \
    X(PFNGLENDQUERYPROC, glEndQuery) \
    X(PFNGLGETQUERYOBJECTUI64VPROC, glGetQueryObjectui64v) \
    X(PFNGLGENSAMPLERSPROC, glGenSamplers) \
    X(PFNGLDELETESAMPLERSPROC, glDeleteSamplers) \
    X(PFNGLBINDSAMPLERPROC, glBindSampler) \
    X(PFNGLSAMPLERPARAMETERIPROC, glSamplerParameteri) \
    X(PFNGLUNIFORM2IPROC, glUniform2i) \
    X(PFNGLUNIFORM1FVPROC, glUniform1fv) \
    X(PFNGLUNIFORM2FVPROC, glUniform2fv) \
    X(PFNGLDISABLEPROC, glDisable) \
    X(PFNGLDEPTHMASKPROC, glDepthMask) \
    X(PFNGLENABLEIPROC, glEnablei) \
    X(PFNGLDISABLEIPROC, glDisablei) \
    X(PFNGLBLENDFUNCPROC, glBlendFunc)

/* The read-backs only the tests call (a product's texture or buffer
 * contents): loaded by gl_context_load_test_functions, never by the
 * program. */
#define GL_TEST_FUNCS(X) \
    X(PFNGLGETTEXIMAGEPROC, glGetTexImage) \
    X(PFNGLGETBUFFERSUBDATAPROC, glGetBufferSubData)

/* Each entry point is a pointer with the function's own name, so code calls
 * glFoo(...) as written. glcorearb.h declares no prototypes (that takes
 * GL_GLEXT_PROTOTYPES), so these are the only declarations; hidden
 * visibility keeps the pointers out of the dynamic symbol table, where they
 * would interpose the functions the driver itself exports under those names. */
#define GL_ENTRY_POINT __attribute__((visibility("hidden")))
#define X(type, name) extern GL_ENTRY_POINT type name;
GL_FUNCS(X)
GL_TEST_FUNCS(X)
#undef X

typedef void (*gl_proc)(void);

/* Loads every function of GL_FUNCS (with_tests: and GL_TEST_FUNCS); logs
 * each missing one and returns false if any is missing. */
bool gl_load(gl_proc (*getproc)(const char *name), bool with_tests);

/* Installs the GL debug-output callback (messages go to the log) and labels
 * objects: call once per context. */
void gl_install_debug_output(void);

/* A framebuffer drawing into level 0 of colors[0..count-1] (count <= 8, at
 * colour attachments 0, 1, ...; none: a depth-only pass) and of depth (0: none),
 * labelled, left unbound; 0 after logging "<label>: framebuffer
 * incomplete". */
GLuint gl_framebuffer(const GLuint *colors, int count, GLuint depth, const char *label);

/* glObjectLabel with a C string. */
void gl_label(GLenum type, GLuint object, const char *label);

/* A labelled 2D texture of one level, storage allocated (left bound). */
GLuint gl_texture_2d(GLenum format, int width, int height, const char *label);

/* The red channel of the read framebuffer's attachment as floats, top
 * row first (GL's rows start at the bottom). */
void gl_read_red(GLenum attachment, int width, int height, float *out);

/* The same of all four channels (out: 4 floats a pixel). */
void gl_read_rgba(GLenum attachment, int width, int height, float *out);

#endif
