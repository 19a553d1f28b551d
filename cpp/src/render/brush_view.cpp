// The brush view: the tuft over the painting, for previews (seed "System prototype", Figure 8).
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "brushwork/render.hpp"
#include "gl_util.hpp"
#include "render_mesh.hpp"
#include "shaders.hpp"

namespace brushwork {
namespace {

using Mat4 = Eigen::Matrix4f;

constexpr float kPiF = 3.14159265f;  // pi in float, as the camera's arithmetic uses it

// right-handed look-at (OpenGL convention: the camera looks down -z)
Mat4 look_at(const Eigen::Vector3f& eye, const Eigen::Vector3f& target, Eigen::Vector3f up) {
  const Eigen::Vector3f f = (target - eye).normalized();
  if (std::fabs(f.dot(up)) > 0.999f) up = Eigen::Vector3f::UnitY();  // looking straight down
  const Eigen::Vector3f s = f.cross(up).normalized(), u = s.cross(f);
  Mat4 m = Mat4::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = f.dot(eye);
  return m;
}

Mat4 perspective(float fov_deg, float aspect, float near, float far) {
  const float t = 1.0f / std::tan(0.5f * fov_deg * kPiF / 180.0f);
  Mat4 m = Mat4::Zero();
  m(0, 0) = t / aspect;
  m(1, 1) = t;
  m(2, 2) = (far + near) / (near - far);
  m(2, 3) = 2.0f * far * near / (near - far);
  m(3, 2) = -1.0f;
  return m;
}

Mat4 orthographic(float half_w, float half_h, float near, float far) {
  Mat4 m = Mat4::Identity();
  m(0, 0) = 1.0f / half_w;
  m(1, 1) = 1.0f / half_h;
  m(2, 2) = -2.0f / (far - near);
  m(2, 3) = -(far + near) / (far - near);
  return m;
}

}  // namespace

void ViewOptions::validate() const {
  if (mode != "shaded" && mode != "outlined" && mode != "transparent")
    throw std::invalid_argument("view mode '" + mode + "': expected shaded, outlined or transparent");
  if (!eye.allFinite() || !target.allFinite() || !light.allFinite())
    throw std::invalid_argument("view: eye, target and light must be finite");
  if ((eye - target).norm() < 1e-6) throw std::invalid_argument("view: eye and target coincide");
  if (!(fov_deg >= 0.0 && fov_deg < 170.0)) throw std::invalid_argument("view: fov_deg must be 0 (orthographic) .. 170");
  if (!(ortho_height_mm > 0.0) || !std::isfinite(ortho_height_mm))
    throw std::invalid_argument("view: ortho_height_mm must be > 0");
  if (light.norm() < 1e-9 || light.z() <= 0.0)
    throw std::invalid_argument("view: the light must shine from above the paper (light.z > 0)");
}

BrushView::BrushView(int width_px, int height_px) : W_(width_px), H_(height_px) {
  if (W_ < 8 || H_ < 8 || W_ > 8192 || H_ > 8192)
    throw std::invalid_argument("brush view of " + std::to_string(W_) + " x " + std::to_string(H_) +
                                " px: each side must be 8..8192");
  ctx_ = RenderContext::acquire();
  ctx_->make_current();
  GLint max_samples = 1;
  gl::GetIntegerv(GL_MAX_SAMPLES, &max_samples);
  const GLsizei samples = std::clamp(static_cast<int>(max_samples), 1, 4);
  color_ms_.generate(ctx_.get());
  gl::BindRenderbuffer(GL_RENDERBUFFER, color_ms_);
  gl::RenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, W_, H_);
  depth_ms_.generate(ctx_.get());
  gl::BindRenderbuffer(GL_RENDERBUFFER, depth_ms_);
  gl::RenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH24_STENCIL8, W_, H_);
  fbo_ms_.generate(ctx_.get());
  gl::BindFramebuffer(GL_FRAMEBUFFER, fbo_ms_);
  gl::FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_ms_);
  gl::FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth_ms_);
  glu::check_framebuffer("brush view");
  color_.reset(ctx_.get(), glu::texture(GL_RGBA8, W_, H_, GL_RGBA, GL_UNSIGNED_BYTE, nullptr, false, GL_CLAMP_TO_EDGE));
  fbo_.generate(ctx_.get());
  gl::BindFramebuffer(GL_FRAMEBUFFER, fbo_);
  gl::FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color_, 0);
  glu::check_framebuffer("brush view resolve");

  brush_prog_ = ctx_->program(shaders::kViewVertex, shaders::kViewFragment, {});
  paper_prog_ = ctx_->program(shaders::kPaperVertex, shaders::kPaperFragment, {});
  glu::indexed_vertex_array(ctx_.get(), vao_, vbo_, ibo_, {3, 3, 2});  // position, normal, uv
  paper_vao_.generate(ctx_.get());
  paper_vbo_.generate(ctx_.get());
  gl::BindVertexArray(paper_vao_);
  gl::BindBuffer(GL_ARRAY_BUFFER, paper_vbo_);
  gl::EnableVertexAttribArray(0);
  gl::VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
  gl::EnableVertexAttribArray(1);
  gl::VertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float), reinterpret_cast<const void*>(2 * sizeof(float)));
  gl::BindVertexArray(0);
  ramp_tex_.reset(ctx_.get(), glu::texture(GL_RGBA32F, 1, 1, GL_RGBA, GL_FLOAT, nullptr, true, GL_CLAMP_TO_EDGE));
  glu::check("brush view set-up");
}

BrushView::~BrushView() = default;  // the GL objects delete themselves (GlName)

namespace {

constexpr int kViewRings = 6;                // rings per spine segment of the viewed tuft
constexpr int kViewAround = 48;              // vertices around one ring of the viewed tuft
constexpr float kNearPerspective = 0.02f;    // near plane over the eye's distance (perspective)
constexpr float kNearOrtho = 0.01f;          // near plane over the eye's distance (orthographic)
constexpr float kFar = 50.0f;                // far plane over the eye's distance
constexpr float kShadowZ = 0.02f;            // mm above the paper the shadow is flattened to
constexpr float kShadowAlpha = 0.28f;        // opacity of the shadow's black
constexpr float kOutlinePx = 2.0f;           // px the outline shell stands out of the surface
constexpr float kTransparentAlpha = 0.35f;   // opacity of the tuft in "transparent" mode
const std::array<float, 4> kBackground{{0.82f, 0.82f, 0.80f, 1.0f}};  // RGBA around the paper
const std::array<float, 3> kPaperColor{{0.97f, 0.955f, 0.92f}};        // RGB of the bare paper
const std::array<float, 4> kOutlineColor{{0.95f, 0.55f, 0.1f, 1.0f}};  // a contrasting outline (seed Figure 8)

// the camera of `o` on a W x H view: its matrix and the eye's distance to the target (mm)
Mat4 camera(const ViewOptions& o, int W, int H, float& dist) {
  const Eigen::Vector3f eye = o.eye.cast<float>(), target = o.target.cast<float>();
  dist = (eye - target).norm();
  const float aspect = static_cast<float>(W) / H;
  const Mat4 view = look_at(eye, target, Eigen::Vector3f::UnitZ());
  const Mat4 proj = o.fov_deg > 0.0
                        ? perspective(static_cast<float>(o.fov_deg), aspect, kNearPerspective * dist, kFar * dist)
                        : orthographic(0.5f * static_cast<float>(o.ortho_height_mm) * aspect,
                                       0.5f * static_cast<float>(o.ortho_height_mm), kNearOrtho * dist, kFar * dist);
  return proj * view;
}

// blending of a flat colour over what is drawn, keeping the view's alpha opaque
void blend_keeping_alpha() {
  gl::Enable(GL_BLEND);
  gl::BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
}

}  // namespace

void BrushView::draw_paper(const std::vector<Paper::TileRef>& tiles, double ppm, const float* mvp) {
  // each tile a quad on z = 0 showing its ink on warm white
  gl::UseProgram(paper_prog_);
  gl::UniformMatrix4fv(glu::uniform(paper_prog_, "u_mvp"), 1, GL_FALSE, mvp);
  gl::Uniform3f(glu::uniform(paper_prog_, "u_paper_color"), kPaperColor[0], kPaperColor[1], kPaperColor[2]);
  gl::Uniform1i(glu::uniform(paper_prog_, "u_paper"), 0);
  gl::Uniform1i(glu::uniform(paper_prog_, "u_layer"), 1);
  gl::BindVertexArray(paper_vao_);
  for (const auto& t : tiles) {
    const float x0 = static_cast<float>(t.x0 / ppm), y0 = static_cast<float>(t.y0 / ppm);
    const float x1 = static_cast<float>((t.x0 + t.w) / ppm), y1 = static_cast<float>((t.y0 + t.h) / ppm);
    const float quad[24] = {x0, y0, 0, 0, x1, y0, 1, 0, x1, y1, 1, 1,
                            x0, y0, 0, 0, x1, y1, 1, 1, x0, y1, 0, 1};
    gl::BindBuffer(GL_ARRAY_BUFFER, paper_vbo_);
    gl::BufferData(GL_ARRAY_BUFFER, sizeof(quad), quad, GL_STREAM_DRAW);
    for (int u = 0; u < 2; ++u) {
      gl::ActiveTexture(GL_TEXTURE0 + u);
      gl::BindTexture(GL_TEXTURE_2D, u == 0 ? t.paper : t.layer);
      // the float ink is sampled with linear filtering when the view magnifies it
      gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
      gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    }
    gl::Uniform1i(glu::uniform(paper_prog_, "u_has_layer"), t.layer != 0 ? 1 : 0);
    gl::Uniform4f(glu::uniform(paper_prog_, "u_layer_ink"), t.layer_ink[0], t.layer_ink[1], t.layer_ink[2],
                  t.layer_ink[3]);
    gl::DrawArrays(GL_TRIANGLES, 0, 6);
  }
  gl::ActiveTexture(GL_TEXTURE0);
}

int BrushView::upload_tuft(const TuftFrame& tuft, const std::vector<std::array<float, 4>>* ramp_in) {
  // the tuft: positions, normals, uv; its ink's colours along the spine in the ramp texture
  MeshOptions opt;
  opt.rings_per_segment = kViewRings;
  opt.around = kViewAround;
  const RenderMesh mesh = build_render_mesh(tuft.sections, opt);
  const int V = mesh.vertices();
  const std::vector<float> vb =
      glu::interleave(V, {{mesh.position.data(), 3}, {mesh.normal.data(), 3}, {mesh.uv.data(), 2}});
  gl::UseProgram(brush_prog_);
  gl::BindVertexArray(vao_);
  gl::BindBuffer(GL_ARRAY_BUFFER, vbo_);
  gl::BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vb.size() * sizeof(float)), vb.data(), GL_STREAM_DRAW);
  gl::BindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo_);
  gl::BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.faces.size() * sizeof(std::uint32_t)),
                 mesh.faces.data(), GL_STREAM_DRAW);
  std::vector<std::array<float, 4>> ramp = ramp_in != nullptr ? *ramp_in : std::vector<std::array<float, 4>>{{0, 0, 0, 1}};
  gl::ActiveTexture(GL_TEXTURE0);
  gl::BindTexture(GL_TEXTURE_2D, ramp_tex_);
  gl::TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, static_cast<GLsizei>(ramp.size()), 1, 0, GL_RGBA, GL_FLOAT, ramp.data());
  return static_cast<int>(mesh.faces.size());
}

void BrushView::draw_tuft(const ViewOptions& o, bool shadow, int n_idx, float dist, const float* mvp) {
  const Eigen::Vector3f light = o.light.cast<float>().normalized();
  gl::UniformMatrix4fv(glu::uniform(brush_prog_, "u_mvp"), 1, GL_FALSE, mvp);
  gl::Uniform1i(glu::uniform(brush_prog_, "u_ramp"), 0);
  gl::Uniform3f(glu::uniform(brush_prog_, "u_light"), light.x(), light.y(), light.z());
  const GLint u_push = glu::uniform(brush_prog_, "u_push"), u_flat = glu::uniform(brush_prog_, "u_flat");
  const GLint u_shadow = glu::uniform(brush_prog_, "u_shadow"), u_shade = glu::uniform(brush_prog_, "u_shade");
  const GLint u_alpha = glu::uniform(brush_prog_, "u_alpha");
  gl::Uniform3f(glu::uniform(brush_prog_, "u_flatten"), light.x(), light.y(), light.z());
  auto draw = [n_idx] { gl::DrawElements(GL_TRIANGLES, n_idx, GL_UNSIGNED_INT, nullptr); };

  // shadow: the tuft flattened onto the paper along the light, darkened once (stencil)
  if (shadow) {
    gl::Uniform1f(glu::uniform(brush_prog_, "u_flatten_z"), kShadowZ);
    gl::Uniform1i(u_shadow, 1);
    gl::Uniform1f(u_push, 0.0f);
    gl::Uniform4f(u_flat, 0.0f, 0.0f, 0.0f, kShadowAlpha);
    gl::Enable(GL_STENCIL_TEST);
    gl::StencilFunc(GL_NOTEQUAL, 1, 0xFF);
    gl::StencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    blend_keeping_alpha();
    gl::DepthMask(GL_FALSE);
    draw();
    gl::DepthMask(GL_TRUE);
    gl::Disable(GL_STENCIL_TEST);
    gl::Disable(GL_BLEND);
    gl::Uniform1i(u_shadow, 0);
  }

  // outline: a shell pushed out along the normals, back faces only, drawn dark
  if (o.mode == "outlined") {
    const float px_mm = (o.fov_deg > 0.0 ? 2.0f * dist * std::tan(0.5f * static_cast<float>(o.fov_deg) * kPiF / 180.0f)
                                         : static_cast<float>(o.ortho_height_mm)) / H_;
    gl::Uniform1f(u_push, kOutlinePx * px_mm);
    gl::Uniform4f(u_flat, kOutlineColor[0], kOutlineColor[1], kOutlineColor[2], kOutlineColor[3]);
    gl::Enable(GL_CULL_FACE);
    gl::FrontFace(GL_CCW);
    gl::CullFace(GL_FRONT);
    draw();
    gl::Disable(GL_CULL_FACE);
    gl::Uniform1f(u_push, 0.0f);
  }

  // the tuft itself
  gl::Uniform4f(u_flat, 0, 0, 0, 0);
  gl::Uniform1i(u_shade, o.mode == "outlined" ? 0 : 1);
  const bool transparent = o.mode == "transparent";
  gl::Uniform1f(u_alpha, transparent ? kTransparentAlpha : 1.0f);
  if (transparent) {
    blend_keeping_alpha();
    gl::DepthMask(GL_FALSE);
  }
  gl::Enable(GL_CULL_FACE);
  gl::CullFace(GL_BACK);
  draw();
  gl::Disable(GL_CULL_FACE);
  gl::DepthMask(GL_TRUE);
  gl::Disable(GL_BLEND);
}

void BrushView::read_back(std::uint8_t* out) {
  // resolve the samples and read back; GL rows run bottom-up, flipped here once
  gl::BindFramebuffer(GL_READ_FRAMEBUFFER, fbo_ms_);
  gl::BindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_);
  gl::BlitFramebuffer(0, 0, W_, H_, 0, 0, W_, H_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  gl::BindFramebuffer(GL_FRAMEBUFFER, fbo_);
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(4) * W_ * H_);
  gl::PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl::ReadPixels(0, 0, W_, H_, GL_RGBA, GL_UNSIGNED_BYTE, buf.data());
  for (int j = 0; j < H_; ++j)
    std::copy_n(&buf[4 * static_cast<std::size_t>(j) * W_], 4 * W_, out + 4 * static_cast<std::size_t>(H_ - 1 - j) * W_);
}

void BrushView::render(Paper* paper, const BrushFrame& brush, const Ink* ink, const ViewOptions& o,
                       std::uint8_t* out) {
  o.validate();
  if (ink != nullptr) ink->validate(brush.nodes);
  ctx_->make_current();
  // paper tiles first: they flush nothing, but may resolve the stroke in progress
  const auto tiles = paper != nullptr ? paper->tile_textures() : std::vector<Paper::TileRef>{};
  float dist = 0.0f;
  const Mat4 mvp = camera(o, W_, H_, dist);

  gl::BindFramebuffer(GL_FRAMEBUFFER, fbo_ms_);
  gl::Viewport(0, 0, W_, H_);
  gl::Disable(GL_SCISSOR_TEST);
  gl::ClearColor(kBackground[0], kBackground[1], kBackground[2], kBackground[3]);
  gl::ClearDepth(1.0);
  gl::ClearStencil(0);
  gl::DepthMask(GL_TRUE);
  gl::Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  gl::Enable(GL_DEPTH_TEST);
  gl::DepthFunc(GL_LEQUAL);
  if (paper != nullptr) draw_paper(tiles, paper->px_per_mm(), mvp.data());
  // every tuft of a split brush, the main tuft first; each child's ink is its own
  for (const TuftFrame& t : brush.tufts) {
    const std::vector<std::array<float, 4>>* ramp =
        ink == nullptr ? nullptr : t.tuft == 0 ? &ink->ramp : !t.ramp.empty() ? &t.ramp : nullptr;
    const int n_idx = upload_tuft(t, ramp);
    draw_tuft(o, o.shadow && paper != nullptr, n_idx, dist, mvp.data());
  }
  gl::Disable(GL_DEPTH_TEST);
  gl::BindVertexArray(0);
  read_back(out);
  glu::check("brush view");
}

}  // namespace brushwork
