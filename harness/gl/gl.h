/* The GL 4.5 core entry points shadowbench uses, loaded at run time through
 * a getproc function (OSMesaGetProcAddress headless, glfwGetProcAddress in
 * the viewer): libOSMesa does not export every 4.5 function, so nothing is
 * linked directly. Add a function here, once, to use it anywhere. */
#ifndef SB_GL_H
#define SB_GL_H

#include <GL/glcorearb.h>

#include <stdbool.h>

#define GL_FUNCS(X) \
    X(PFNGLGETSTRINGPROC, glGetString) \
    X(PFNGLGETSTRINGIPROC, glGetStringi) \
    X(PFNGLGETINTEGERVPROC, glGetIntegerv) \
    X(PFNGLGETERRORPROC, glGetError) \
    X(PFNGLENABLEPROC, glEnable) \
    X(PFNGLDISABLEPROC, glDisable) \
    X(PFNGLVIEWPORTPROC, glViewport) \
    X(PFNGLCLEARPROC, glClear) \
    X(PFNGLCLEARBUFFERFVPROC, glClearBufferfv) \
    X(PFNGLDEPTHFUNCPROC, glDepthFunc) \
    X(PFNGLCLIPCONTROLPROC, glClipControl) \
    X(PFNGLFINISHPROC, glFinish) \
    X(PFNGLFLUSHPROC, glFlush) \
    X(PFNGLREADPIXELSPROC, glReadPixels) \
    X(PFNGLPIXELSTOREIPROC, glPixelStorei) \
    X(PFNGLPOLYGONOFFSETPROC, glPolygonOffset) \
    X(PFNGLGENTEXTURESPROC, glGenTextures) \
    X(PFNGLDELETETEXTURESPROC, glDeleteTextures) \
    X(PFNGLBINDTEXTUREPROC, glBindTexture) \
    X(PFNGLTEXSTORAGE2DPROC, glTexStorage2D) \
    X(PFNGLTEXPARAMETERIPROC, glTexParameteri) \
    X(PFNGLTEXPARAMETERFVPROC, glTexParameterfv) \
    X(PFNGLBINDTEXTUREUNITPROC, glBindTextureUnit) \
    X(PFNGLACTIVETEXTUREPROC, glActiveTexture) \
    X(PFNGLGETTEXIMAGEPROC, glGetTexImage) \
    X(PFNGLGENERATEMIPMAPPROC, glGenerateMipmap) \
    X(PFNGLGENFRAMEBUFFERSPROC, glGenFramebuffers) \
    X(PFNGLDELETEFRAMEBUFFERSPROC, glDeleteFramebuffers) \
    X(PFNGLBINDFRAMEBUFFERPROC, glBindFramebuffer) \
    X(PFNGLFRAMEBUFFERTEXTURE2DPROC, glFramebufferTexture2D) \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, glCheckFramebufferStatus) \
    X(PFNGLDRAWBUFFERSPROC, glDrawBuffers) \
    X(PFNGLREADBUFFERPROC, glReadBuffer) \
    X(PFNGLGENBUFFERSPROC, glGenBuffers) \
    X(PFNGLDELETEBUFFERSPROC, glDeleteBuffers) \
    X(PFNGLBINDBUFFERPROC, glBindBuffer) \
    X(PFNGLBUFFERDATAPROC, glBufferData) \
    X(PFNGLBUFFERSUBDATAPROC, glBufferSubData) \
    X(PFNGLBINDBUFFERBASEPROC, glBindBufferBase) \
    X(PFNGLGETBUFFERSUBDATAPROC, glGetBufferSubData) \
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
    X(PFNGLUNIFORM2FPROC, glUniform2f) \
    X(PFNGLUNIFORM3FPROC, glUniform3f) \
    X(PFNGLUNIFORM4FPROC, glUniform4f) \
    X(PFNGLUNIFORMMATRIX4FVPROC, glUniformMatrix4fv) \
    X(PFNGLGETUNIFORMBLOCKINDEXPROC, glGetUniformBlockIndex) \
    X(PFNGLUNIFORMBLOCKBINDINGPROC, glUniformBlockBinding) \
    X(PFNGLDEBUGMESSAGECALLBACKPROC, glDebugMessageCallback) \
    X(PFNGLDEBUGMESSAGECONTROLPROC, glDebugMessageControl) \
    X(PFNGLOBJECTLABELPROC, glObjectLabel) \
    X(PFNGLDISPATCHCOMPUTEPROC, glDispatchCompute) \
    X(PFNGLMEMORYBARRIERPROC, glMemoryBarrier) \
    X(PFNGLBINDIMAGETEXTUREPROC, glBindImageTexture) \
    X(PFNGLCOPYIMAGESUBDATAPROC, glCopyImageSubData) \
    X(PFNGLGENSAMPLERSPROC, glGenSamplers) \
    X(PFNGLDELETESAMPLERSPROC, glDeleteSamplers) \
    X(PFNGLBINDSAMPLERPROC, glBindSampler) \
    X(PFNGLSAMPLERPARAMETERIPROC, glSamplerParameteri) \
    X(PFNGLSAMPLERPARAMETERFVPROC, glSamplerParameterfv) \
    X(PFNGLUNIFORM2IPROC, glUniform2i) \
    X(PFNGLUNIFORM1FVPROC, glUniform1fv)

#define X(type, name) extern type sb_##name;
GL_FUNCS(X)
#undef X

/* Code calls glFoo(...) as usual; it resolves to the loaded pointer. */
#define glGetString sb_glGetString
#define glGetStringi sb_glGetStringi
#define glGetIntegerv sb_glGetIntegerv
#define glGetError sb_glGetError
#define glEnable sb_glEnable
#define glDisable sb_glDisable
#define glViewport sb_glViewport
#define glClear sb_glClear
#define glClearBufferfv sb_glClearBufferfv
#define glDepthFunc sb_glDepthFunc
#define glClipControl sb_glClipControl
#define glFinish sb_glFinish
#define glFlush sb_glFlush
#define glReadPixels sb_glReadPixels
#define glPixelStorei sb_glPixelStorei
#define glPolygonOffset sb_glPolygonOffset
#define glGenTextures sb_glGenTextures
#define glDeleteTextures sb_glDeleteTextures
#define glBindTexture sb_glBindTexture
#define glTexStorage2D sb_glTexStorage2D
#define glTexParameteri sb_glTexParameteri
#define glTexParameterfv sb_glTexParameterfv
#define glBindTextureUnit sb_glBindTextureUnit
#define glActiveTexture sb_glActiveTexture
#define glGetTexImage sb_glGetTexImage
#define glGenerateMipmap sb_glGenerateMipmap
#define glGenFramebuffers sb_glGenFramebuffers
#define glDeleteFramebuffers sb_glDeleteFramebuffers
#define glBindFramebuffer sb_glBindFramebuffer
#define glFramebufferTexture2D sb_glFramebufferTexture2D
#define glCheckFramebufferStatus sb_glCheckFramebufferStatus
#define glDrawBuffers sb_glDrawBuffers
#define glReadBuffer sb_glReadBuffer
#define glGenBuffers sb_glGenBuffers
#define glDeleteBuffers sb_glDeleteBuffers
#define glBindBuffer sb_glBindBuffer
#define glBufferData sb_glBufferData
#define glBufferSubData sb_glBufferSubData
#define glBindBufferBase sb_glBindBufferBase
#define glGetBufferSubData sb_glGetBufferSubData
#define glGenVertexArrays sb_glGenVertexArrays
#define glDeleteVertexArrays sb_glDeleteVertexArrays
#define glBindVertexArray sb_glBindVertexArray
#define glVertexAttribPointer sb_glVertexAttribPointer
#define glEnableVertexAttribArray sb_glEnableVertexAttribArray
#define glDrawElements sb_glDrawElements
#define glDrawArrays sb_glDrawArrays
#define glCreateShader sb_glCreateShader
#define glShaderSource sb_glShaderSource
#define glCompileShader sb_glCompileShader
#define glGetShaderiv sb_glGetShaderiv
#define glGetShaderInfoLog sb_glGetShaderInfoLog
#define glDeleteShader sb_glDeleteShader
#define glCreateProgram sb_glCreateProgram
#define glAttachShader sb_glAttachShader
#define glLinkProgram sb_glLinkProgram
#define glGetProgramiv sb_glGetProgramiv
#define glGetProgramInfoLog sb_glGetProgramInfoLog
#define glDeleteProgram sb_glDeleteProgram
#define glUseProgram sb_glUseProgram
#define glGetUniformLocation sb_glGetUniformLocation
#define glUniform1i sb_glUniform1i
#define glUniform1f sb_glUniform1f
#define glUniform2f sb_glUniform2f
#define glUniform3f sb_glUniform3f
#define glUniform4f sb_glUniform4f
#define glUniformMatrix4fv sb_glUniformMatrix4fv
#define glGetUniformBlockIndex sb_glGetUniformBlockIndex
#define glUniformBlockBinding sb_glUniformBlockBinding
#define glDebugMessageCallback sb_glDebugMessageCallback
#define glDebugMessageControl sb_glDebugMessageControl
#define glObjectLabel sb_glObjectLabel
#define glDispatchCompute sb_glDispatchCompute
#define glMemoryBarrier sb_glMemoryBarrier
#define glBindImageTexture sb_glBindImageTexture
#define glCopyImageSubData sb_glCopyImageSubData
#define glGenSamplers sb_glGenSamplers
#define glDeleteSamplers sb_glDeleteSamplers
#define glBindSampler sb_glBindSampler
#define glSamplerParameteri sb_glSamplerParameteri
#define glSamplerParameterfv sb_glSamplerParameterfv
#define glUniform2i sb_glUniform2i
#define glUniform1fv sb_glUniform1fv

typedef void (*gl_proc)(void);

/* Loads every function of GL_FUNCS; logs each missing one and returns false
 * if any is missing. */
bool gl_load(gl_proc (*getproc)(const char *name));

/* Installs the GL debug-output callback (messages go to the log) and labels
 * objects: call once per context. */
void gl_install_debug_output(void);

/* glObjectLabel with a C string. */
void gl_label(GLenum type, GLuint object, const char *label);

#endif
