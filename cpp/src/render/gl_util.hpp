// Small helpers over the GL table: programs built with feature #defines, float textures,
// framebuffers, error checks that throw std::runtime_error with the operation's name.
#pragma once

#include <string>
#include <vector>

#include "gl_api.hpp"

namespace brushwork::glu {

// compile and link `vertex` + `fragment` (GLSL 330 core) with "#define NAME" lines for each of
// `defines` inserted after the version line; throws with the info log on failure
GLuint program(const std::string& vertex, const std::string& fragment,
               const std::vector<std::string>& defines);

// a 2-D texture of `internal` format (GL_RGBA32F, GL_R32F, ...), size w x h, linear filtering
// (or nearest), wrap mode `wrap`; `data` may be null
GLuint texture(GLenum internal, int w, int h, GLenum format, GLenum type, const void* data,
               bool linear, GLenum wrap);

// throw if the bound draw framebuffer is incomplete, naming `what`
void check_framebuffer(const char* what);

// throw if glGetError reports anything, naming `what`
void check(const char* what);

// uniform location, -1 tolerated (the feature may be compiled out)
inline GLint uniform(GLuint prog, const char* name) { return gl::GetUniformLocation(prog, name); }

}  // namespace brushwork::glu
