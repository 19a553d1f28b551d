// The OpenGL 3.3 core entry points the renderer uses, loaded at run time through
// eglGetProcAddress (so the module links neither libGL nor libEGL: a machine without EGL can still
// import brushwork and use the brush; only rendering raises, saying what to install).
#pragma once

#include <GL/glcorearb.h>

namespace brushwork::gl {

// X-macro list: return type, name, parameter list.
#define BRUSHWORK_GL_FUNCTIONS(X)                                                              \
  X(const GLubyte*, GetString, (GLenum))                                                       \
  X(void, GetIntegerv, (GLenum, GLint*))                                                       \
  X(GLenum, GetError, (void))                                                                  \
  X(void, Viewport, (GLint, GLint, GLsizei, GLsizei))                                          \
  X(void, Scissor, (GLint, GLint, GLsizei, GLsizei))                                           \
  X(void, Enable, (GLenum))                                                                    \
  X(void, Disable, (GLenum))                                                                   \
  X(void, ClearColor, (GLfloat, GLfloat, GLfloat, GLfloat))                                    \
  X(void, ClearDepth, (GLdouble))                                                              \
  X(void, Clear, (GLbitfield))                                                                 \
  X(void, BlendFunc, (GLenum, GLenum))                                                         \
  X(void, BlendEquation, (GLenum))                                                             \
  X(void, BlendFuncSeparate, (GLenum, GLenum, GLenum, GLenum))                                 \
  X(void, DepthFunc, (GLenum))                                                                 \
  X(void, DepthMask, (GLboolean))                                                              \
  X(void, CullFace, (GLenum))                                                                  \
  X(void, FrontFace, (GLenum))                                                                 \
  X(void, StencilFunc, (GLenum, GLint, GLuint))                                                \
  X(void, StencilOp, (GLenum, GLenum, GLenum))                                                 \
  X(void, ClearStencil, (GLint))                                                               \
  X(void, ReadPixels, (GLint, GLint, GLsizei, GLsizei, GLenum, GLenum, void*))                 \
  X(void, PixelStorei, (GLenum, GLint))                                                        \
  X(void, GenTextures, (GLsizei, GLuint*))                                                     \
  X(void, DeleteTextures, (GLsizei, const GLuint*))                                            \
  X(void, BindTexture, (GLenum, GLuint))                                                       \
  X(void, TexImage2D,                                                                          \
    (GLenum, GLint, GLint, GLsizei, GLsizei, GLint, GLenum, GLenum, const void*))              \
  X(void, TexSubImage2D,                                                                       \
    (GLenum, GLint, GLint, GLint, GLsizei, GLsizei, GLenum, GLenum, const void*))              \
  X(void, TexParameteri, (GLenum, GLenum, GLint))                                              \
  X(void, ActiveTexture, (GLenum))                                                             \
  X(void, GenFramebuffers, (GLsizei, GLuint*))                                                 \
  X(void, DeleteFramebuffers, (GLsizei, const GLuint*))                                        \
  X(void, BindFramebuffer, (GLenum, GLuint))                                                   \
  X(void, FramebufferTexture2D, (GLenum, GLenum, GLenum, GLuint, GLint))                       \
  X(GLenum, CheckFramebufferStatus, (GLenum))                                                  \
  X(void, GenRenderbuffers, (GLsizei, GLuint*))                                                \
  X(void, DeleteRenderbuffers, (GLsizei, const GLuint*))                                       \
  X(void, BindRenderbuffer, (GLenum, GLuint))                                                  \
  X(void, RenderbufferStorageMultisample, (GLenum, GLsizei, GLenum, GLsizei, GLsizei))         \
  X(void, FramebufferRenderbuffer, (GLenum, GLenum, GLenum, GLuint))                           \
  X(void, BlitFramebuffer,                                                                     \
    (GLint, GLint, GLint, GLint, GLint, GLint, GLint, GLint, GLbitfield, GLenum))              \
  X(GLuint, CreateShader, (GLenum))                                                            \
  X(void, ShaderSource, (GLuint, GLsizei, const GLchar* const*, const GLint*))                 \
  X(void, CompileShader, (GLuint))                                                             \
  X(void, GetShaderiv, (GLuint, GLenum, GLint*))                                               \
  X(void, GetShaderInfoLog, (GLuint, GLsizei, GLsizei*, GLchar*))                              \
  X(GLuint, CreateProgram, (void))                                                             \
  X(void, AttachShader, (GLuint, GLuint))                                                      \
  X(void, LinkProgram, (GLuint))                                                               \
  X(void, GetProgramiv, (GLuint, GLenum, GLint*))                                              \
  X(void, GetProgramInfoLog, (GLuint, GLsizei, GLsizei*, GLchar*))                             \
  X(void, DeleteShader, (GLuint))                                                              \
  X(void, DeleteProgram, (GLuint))                                                             \
  X(void, UseProgram, (GLuint))                                                                \
  X(GLint, GetUniformLocation, (GLuint, const GLchar*))                                        \
  X(void, Uniform1i, (GLint, GLint))                                                           \
  X(void, Uniform1f, (GLint, GLfloat))                                                         \
  X(void, Uniform2f, (GLint, GLfloat, GLfloat))                                                \
  X(void, Uniform2i, (GLint, GLint, GLint))                                                  \
  X(void, Uniform3f, (GLint, GLfloat, GLfloat, GLfloat))                                       \
  X(void, Uniform4f, (GLint, GLfloat, GLfloat, GLfloat, GLfloat))                              \
  X(void, Uniform1fv, (GLint, GLsizei, const GLfloat*))                                        \
  X(void, UniformMatrix4fv, (GLint, GLsizei, GLboolean, const GLfloat*))                       \
  X(void, GenVertexArrays, (GLsizei, GLuint*))                                                 \
  X(void, BindVertexArray, (GLuint))                                                           \
  X(void, DeleteVertexArrays, (GLsizei, const GLuint*))                                        \
  X(void, GenBuffers, (GLsizei, GLuint*))                                                      \
  X(void, BindBuffer, (GLenum, GLuint))                                                        \
  X(void, BufferData, (GLenum, GLsizeiptr, const void*, GLenum))                               \
  X(void, BufferSubData, (GLenum, GLintptr, GLsizeiptr, const void*))                           \
  X(void, DeleteBuffers, (GLsizei, const GLuint*))                                             \
  X(void, VertexAttribPointer, (GLuint, GLint, GLenum, GLboolean, GLsizei, const void*))       \
  X(void, EnableVertexAttribArray, (GLuint))                                                   \
  X(void, DrawElements, (GLenum, GLsizei, GLenum, const void*))                                \
  X(void, DrawElementsInstanced, (GLenum, GLsizei, GLenum, const void*, GLsizei))              \
  X(void, DrawArrays, (GLenum, GLint, GLsizei))

#define BRUSHWORK_GL_DECLARE(ret, name, args) extern ret(*name) args;
BRUSHWORK_GL_FUNCTIONS(BRUSHWORK_GL_DECLARE)
#undef BRUSHWORK_GL_DECLARE

// Fill the table through `get` (eglGetProcAddress); returns the first name that is missing, or
// nullptr when all resolved.
using ProcGetter = void (*(*)(const char*))();
const char* load(ProcGetter get);

}  // namespace brushwork::gl
