// Small helpers over the GL table: programs built with feature #defines, float textures,
// framebuffers, error checks that throw std::runtime_error with the operation's name.
#pragma once

#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "brushwork/render/gl_name.hpp"
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

// a new vertex array `vao` over new buffers `vbo` (vertices) and `ibo` (indices): attribute a
// is widths[a] floats, interleaved in that order; leaves no vertex array bound
// (in `ctx`, current)
void indexed_vertex_array(const RenderContext* ctx, GlVertexArray& vao, GlBuffer& vbo, GlBuffer& ibo,
                          std::initializer_list<int> widths);

// vertex attributes interleaved for one buffer: (V, sum of widths) floats, each attribute a
// (V, width) array given as (data, width), in the order listed
inline std::vector<float> interleave(int V, std::initializer_list<std::pair<const float*, int>> attributes) {
  int stride = 0;
  for (const auto& a : attributes) stride += a.second;
  std::vector<float> out(static_cast<std::size_t>(stride) * V);
  for (int v = 0; v < V; ++v) {
    float* o = &out[static_cast<std::size_t>(stride) * v];
    for (const auto& [data, width] : attributes)
      for (int d = 0; d < width; ++d) *o++ = data[static_cast<std::size_t>(width) * v + d];
  }
  return out;
}

}  // namespace brushwork::glu
