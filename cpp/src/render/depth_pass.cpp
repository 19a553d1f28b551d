// The depth pass of the 3-D outlines (see brushwork/depth.hpp): the camera's projection is done
// here in double precision, so meshes in any unit and far from the origin keep their depth
// resolution; GL only rasterises and keeps the nearest depth.
#include "brushwork/depth.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "brushwork/render.hpp"
#include "gl_util.hpp"

namespace brushwork {
namespace {

constexpr int kMaxSide = 8192;          // px, the largest depth image
constexpr float kEmpty = 4.0f;          // cleared value, beyond any depth in [-1, 1]

// clip-space position in, the depth p2/p3 out, interpolated linearly on the screen (noperspective:
// p2/p3 is affine in window coordinates)
constexpr const char* kDepthVertex = R"(#version 330 core
layout(location = 0) in vec4 a_clip;
noperspective out float v_depth;
void main() {
  gl_Position = a_clip;
  v_depth = a_clip.z / a_clip.w;
}
)";

constexpr const char* kDepthFragment = R"(#version 330 core
noperspective in float v_depth;
layout(location = 0) out float o_depth;
void main() { o_depth = v_depth; }
)";

void check_input(int n_vertices, const std::int64_t* faces, int n_faces, int width, int height) {
  if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide)
    throw std::invalid_argument("render_depth: image of " + std::to_string(width) + " x " +
                                std::to_string(height) + " px; each side must be 1.." + std::to_string(kMaxSide));
  for (std::size_t i = 0; i < static_cast<std::size_t>(n_faces) * 3; ++i)
    if (faces[i] < 0 || faces[i] >= n_vertices)
      throw std::invalid_argument("render_depth: face index " + std::to_string(faces[i]) + " out of range 0.." +
                                  std::to_string(n_vertices - 1));
}

// GL clip coordinates (x, y, z, w) per vertex from p = M [v, 1]: x_ndc = 2 p0 / (W p3) - 1,
// y_ndc = 1 - 2 p1 / (H p3) (the image's y runs down), z_ndc = p2 / p3
std::vector<float> clip_positions(const double* v, int n, const double* M, int W, int H) {
  std::vector<float> out(static_cast<std::size_t>(n) * 4);
  for (int i = 0; i < n; ++i) {
    double p[4];
    for (int r = 0; r < 4; ++r)
      p[r] = M[4 * r] * v[3 * i] + M[4 * r + 1] * v[3 * i + 1] + M[4 * r + 2] * v[3 * i + 2] + M[4 * r + 3];
    float* o = &out[4 * static_cast<std::size_t>(i)];
    o[0] = static_cast<float>(2.0 * p[0] / W - p[3]);
    o[1] = static_cast<float>(p[3] - 2.0 * p[1] / H);
    o[2] = static_cast<float>(p[2]);
    o[3] = static_cast<float>(p[3]);
  }
  return out;
}

// the GL objects of one pass, released when it ends (also on an exception)
struct DepthTargets {
  const RenderContext* ctx = nullptr;  // current, the pass's
  GlFramebuffer fbo;
  GlTexture color;
  GlRenderbuffer depth;
  GlVertexArray vao;
  GlBuffer vbo, ibo;
};

// a framebuffer of one float colour (the depth p2/p3) and a depth buffer for the test
void make_targets(DepthTargets& t, int W, int H) {
  t.color.reset(t.ctx, glu::texture(GL_R32F, W, H, GL_RED, GL_FLOAT, nullptr, false, GL_CLAMP_TO_EDGE));
  t.depth.generate(t.ctx);
  gl::BindRenderbuffer(GL_RENDERBUFFER, t.depth);
  gl::RenderbufferStorageMultisample(GL_RENDERBUFFER, 0, GL_DEPTH_COMPONENT32F, W, H);
  t.fbo.generate(t.ctx);
  gl::BindFramebuffer(GL_FRAMEBUFFER, t.fbo);
  gl::FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t.color, 0);
  gl::FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, t.depth);
  glu::check_framebuffer("depth pass");
}

void upload(DepthTargets& t, const std::vector<float>& clip, const std::int64_t* faces, int n_faces) {
  std::vector<std::uint32_t> idx(faces, faces + static_cast<std::size_t>(n_faces) * 3);
  glu::indexed_vertex_array(t.ctx, t.vao, t.vbo, t.ibo, {4});
  gl::BindVertexArray(t.vao);
  gl::BindBuffer(GL_ARRAY_BUFFER, t.vbo);
  gl::BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(clip.size() * sizeof(float)), clip.data(), GL_STREAM_DRAW);
  gl::BindBuffer(GL_ELEMENT_ARRAY_BUFFER, t.ibo);
  gl::BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(idx.size() * sizeof(std::uint32_t)), idx.data(),
                 GL_STREAM_DRAW);
}

// read the float image back, row 0 at the top (GL's rows run bottom-up); empty pixels -> +inf
void read_depth(int W, int H, float* out) {
  std::vector<float> buf(static_cast<std::size_t>(W) * H);
  gl::PixelStorei(GL_PACK_ALIGNMENT, 4);
  gl::ReadPixels(0, 0, W, H, GL_RED, GL_FLOAT, buf.data());
  const float inf = std::numeric_limits<float>::infinity();
  for (int j = 0; j < H; ++j) {
    const float* row = &buf[static_cast<std::size_t>(j) * W];
    float* o = out + static_cast<std::size_t>(H - 1 - j) * W;
    for (int i = 0; i < W; ++i) o[i] = row[i] > 1.5f ? inf : row[i];
  }
}

}  // namespace

void render_depth(const double* vertices, int n_vertices, const std::int64_t* faces, int n_faces,
                  const double* matrix, int width, int height, float* out) {
  check_input(n_vertices, faces, n_faces, width, height);
  auto ctx = RenderContext::acquire();
  ctx->make_current();
  const GLuint prog = ctx->program(kDepthVertex, kDepthFragment, {});
  DepthTargets t;
  t.ctx = ctx.get();
  make_targets(t, width, height);
  gl::Viewport(0, 0, width, height);
  gl::Disable(GL_SCISSOR_TEST);
  gl::Disable(GL_BLEND);
  gl::Disable(GL_CULL_FACE);
  gl::ClearColor(kEmpty, 0.0f, 0.0f, 0.0f);
  gl::ClearDepth(1.0);
  gl::DepthMask(GL_TRUE);
  gl::Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (n_faces > 0 && n_vertices > 0) {
    upload(t, clip_positions(vertices, n_vertices, matrix, width, height), faces, n_faces);
    gl::UseProgram(prog);
    gl::Enable(GL_DEPTH_TEST);
    gl::DepthFunc(GL_LESS);
    gl::DrawElements(GL_TRIANGLES, 3 * n_faces, GL_UNSIGNED_INT, nullptr);
    gl::Disable(GL_DEPTH_TEST);
    gl::BindVertexArray(0);
  }
  read_depth(width, height, out);
  gl::BindFramebuffer(GL_FRAMEBUFFER, 0);
  glu::check("depth pass");
}

}  // namespace brushwork
