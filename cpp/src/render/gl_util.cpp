#include "gl_util.hpp"

#include <cstdio>
#include <stdexcept>

namespace brushwork::glu {
namespace {

GLuint compile(GLenum kind, const std::string& src, const std::vector<std::string>& defines) {
  // "#version" must stay the first line; the feature switches follow it
  const auto eol = src.find('\n');
  std::string text = src.substr(0, eol + 1);
  for (const auto& d : defines) text += "#define " + d + "\n";
  text += src.substr(eol + 1);
  const GLuint sh = gl::CreateShader(kind);
  const char* p = text.c_str();
  gl::ShaderSource(sh, 1, &p, nullptr);
  gl::CompileShader(sh);
  GLint ok = 0;
  gl::GetShaderiv(sh, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096] = {0};
    gl::GetShaderInfoLog(sh, sizeof(log) - 1, nullptr, log);
    gl::DeleteShader(sh);
    throw std::runtime_error(std::string(kind == GL_VERTEX_SHADER ? "vertex" : "fragment") +
                             " shader does not compile: " + log);
  }
  return sh;
}

}  // namespace

GLuint program(const std::string& vertex, const std::string& fragment,
               const std::vector<std::string>& defines) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex, defines);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment, defines);
  const GLuint prog = gl::CreateProgram();
  gl::AttachShader(prog, vs);
  gl::AttachShader(prog, fs);
  gl::LinkProgram(prog);
  gl::DeleteShader(vs);
  gl::DeleteShader(fs);
  GLint ok = 0;
  gl::GetProgramiv(prog, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[4096] = {0};
    gl::GetProgramInfoLog(prog, sizeof(log) - 1, nullptr, log);
    gl::DeleteProgram(prog);
    throw std::runtime_error(std::string("shader program does not link: ") + log);
  }
  return prog;
}

GLuint texture(GLenum internal, int w, int h, GLenum format, GLenum type, const void* data,
               bool linear, GLenum wrap) {
  GLuint tex = 0;
  gl::GenTextures(1, &tex);
  gl::BindTexture(GL_TEXTURE_2D, tex);
  gl::PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl::TexImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(internal), w, h, 0, format, type, data);
  const GLint filter = linear ? GL_LINEAR : GL_NEAREST;
  gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
  gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
  gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, static_cast<GLint>(wrap));
  gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, static_cast<GLint>(wrap));
  check("texture allocation (out of GPU memory?)");
  return tex;
}

void indexed_vertex_array(const RenderContext* ctx, GlVertexArray& vao, GlBuffer& vbo, GlBuffer& ibo,
                          std::initializer_list<int> widths) {
  vao.generate(ctx);
  vbo.generate(ctx);
  ibo.generate(ctx);
  gl::BindVertexArray(vao);
  gl::BindBuffer(GL_ARRAY_BUFFER, vbo);
  gl::BindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
  GLsizei stride = 0;
  for (const int w : widths) stride += w * static_cast<GLsizei>(sizeof(float));
  std::size_t off = 0;
  GLuint a = 0;
  for (const int w : widths) {
    gl::EnableVertexAttribArray(a);
    gl::VertexAttribPointer(a++, w, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(off));
    off += w * sizeof(float);
  }
  gl::BindVertexArray(0);
}

void check_framebuffer(const char* what) {
  const GLenum st = gl::CheckFramebufferStatus(GL_FRAMEBUFFER);
  if (st != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error(std::string(what) + ": framebuffer incomplete (status 0x" +
                             [st] {
                               char b[16];
                               std::snprintf(b, sizeof(b), "%X", st);
                               return std::string(b);
                             }() +
                             ")");
}

void check(const char* what) {
  const GLenum err = gl::GetError();
  if (err != GL_NO_ERROR) {
    char b[16];
    std::snprintf(b, sizeof(b), "%X", err);
    throw std::runtime_error(std::string(what) + ": OpenGL error 0x" + b);
  }
}

}  // namespace brushwork::glu
