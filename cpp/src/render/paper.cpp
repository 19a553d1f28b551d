// The paper: float ink in tiles, the footprint pass, strokes, undo and readback
// (seed "Ink depositing", "System prototype": stroke undo, image saving and loading).
#include <algorithm>
#include <array>
#if defined(__SSE2__)
#include <xmmintrin.h>
#endif
#include <cmath>
#include <stdexcept>
#include <string>

#include "brushwork/render.hpp"
#include "gl_util.hpp"
#include "maps.hpp"
#include "render_mesh.hpp"
#include "shaders.hpp"

namespace brushwork {

// one tile of the canvas: the paper and, allocated on first use, the stroke layer
struct PaperTile {
  int x0 = 0, y0 = 0, w = 0, h = 0;  // px, y up
  GLuint paper_tex = 0, paper_fbo = 0;
  // the stroke layer: multisampled colour and depth (drawn into), and a single-sample
  // texture it resolves into (composited and read back)
  GLuint layer_color_ms = 0, layer_depth_ms = 0, layer_fbo = 0;
  GLuint layer_tex = 0, resolve_fbo = 0;
};

// the footprint program of one scene and its vertex buffers
class FootprintProgram {
 public:
  GLuint prog = 0, vao = 0, vbo = 0, ibo = 0;
  // bytes allocated to vbo and ibo: a deposit that fits writes into them (glBufferSubData)
  // rather than allocating new storage each frame, which llvmpipe clears and copies (~7% of a
  // 1024 px deposit's instructions; docs/experiments/deposit_instructions.sh).  With depletion
  // the last frame was read back, so the buffers are idle; without it llvmpipe flushes the
  // frame first (永和九年人大少 without depletion: the same time and pixels)
  GLsizeiptr vbo_bytes = 0, ibo_bytes = 0;
  GLint u_blends = -1, u_slides = -1, u_first = -1, u_shift = -1, u_view = -1, u_soak = -1, u_nodes = -1, u_wet = -1, u_press = -1, u_color = -1;
  GLint u_split = -1, u_dry = -1, u_grain = -1, u_ramp = -1, u_soak_shift = -1;
  GLint u_dry_param = -1, u_grain_scale = -1;
};

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxNodes = 33;  // u_wet / u_press array size (n_segments <= 16 needs 17)
constexpr int kSplitRows = 256, kSplitCols = 512, kGrainSize = 512;

using Rect = std::array<int, 4>;  // x0, y0, x1, y1 px (exclusive), y up

bool empty(const Rect& r) { return r[2] <= r[0] || r[3] <= r[1]; }
Rect unite(const Rect& a, const Rect& b) {
  if (empty(a)) return b;
  if (empty(b)) return a;
  return {std::min(a[0], b[0]), std::min(a[1], b[1]), std::max(a[2], b[2]), std::max(a[3], b[3])};
}
Rect intersect(const Rect& a, const Rect& b) {
  return {std::max(a[0], b[0]), std::max(a[1], b[1]), std::min(a[2], b[2]), std::min(a[3], b[3])};
}

void check_positive(const char* name, double v) {
  if (!std::isfinite(v) || v <= 0.0)
    throw std::invalid_argument(std::string(name) + " = " + std::to_string(v) +
                                ": expected a finite positive number");
}

}  // namespace

void SceneFeatures::validate() const {
  auto in01 = [](const char* name, double v, bool open_low) {
    if (!std::isfinite(v) || v < 0.0 || v > 1.0 || (open_low && v == 0.0))
      throw std::invalid_argument(std::string("scene.") + name + " = " + std::to_string(v) +
                                  (open_low ? ": expected 0 < value <= 1" : ": expected 0..1"));
  };
  in01("dry_onset", dry_onset, true);
  in01("grain_onset", grain_onset, true);
  if (!std::isfinite(dry_pressure) || dry_pressure < 0 || dry_pressure > 10)
    throw std::invalid_argument("scene.dry_pressure = " + std::to_string(dry_pressure) + ": expected 0..10");
  if (!std::isfinite(grain_pressure) || grain_pressure < 0 || grain_pressure > 10)
    throw std::invalid_argument("scene.grain_pressure = " + std::to_string(grain_pressure) + ": expected 0..10");
  check_positive("scene.grain_period_mm", grain_period_mm);
  check_positive("scene.soak_drain_mm", soak_drain_mm);
  if (!std::isfinite(soak_expand) || soak_expand < 0 || soak_expand > 2)
    throw std::invalid_argument("scene.soak_expand = " + std::to_string(soak_expand) + ": expected 0..2");
  in01("soak_shift", soak_shift, false);
  in01("capillary", capillary, false);
  if (mesh_rings < 1 || mesh_rings > 64)
    throw std::invalid_argument("scene.mesh_rings = " + std::to_string(mesh_rings) + ": expected 1..64");
  if (mesh_around < 8 || mesh_around > 512)
    throw std::invalid_argument("scene.mesh_around = " + std::to_string(mesh_around) + ": expected 8..512");
  if (!std::isfinite(mesh_px) || (mesh_px != 0.0 && (mesh_px < 0.5 || mesh_px > 100.0)))
    throw std::invalid_argument("scene.mesh_px = " + std::to_string(mesh_px) + ": expected 0 or 0.5..100");
  if (samples != 1 && samples != 2 && samples != 4 && samples != 8)
    throw std::invalid_argument("scene.samples = " + std::to_string(samples) + ": expected 1, 2, 4 or 8");
}

Ink Ink::full(const Brush& brush, double total_mm2) {
  check_positive("ink total", total_mm2);
  const auto secs = brush.sections();
  Ink ink;
  ink.capacity.resize(static_cast<Eigen::Index>(secs.size()));
  // capacity in proportion to the section area pi a c (the water a node can hold)
  for (std::size_t i = 0; i < secs.size(); ++i)
    ink.capacity[i] = std::max(0.5 * (secs[i].a_plus + secs[i].a_minus) * secs[i].c, 1e-9);
  ink.capacity *= total_mm2 / ink.capacity.sum();
  ink.load = ink.capacity;
  ink.excess = 1.0;  // freshly dipped: soaked
  return ink;
}

void Ink::validate(int nodes) const {
  if (ramp.empty()) throw std::invalid_argument("ink.ramp: at least one colour");
  for (const auto& c : ramp)
    for (float v : c)
      if (!std::isfinite(v) || v < 0.0f || v > 1.0f)
        throw std::invalid_argument("ink.ramp: colour components must be in 0..1");
  if (load.size() != nodes || capacity.size() != nodes)
    throw std::invalid_argument("ink: load and capacity need " + std::to_string(nodes) +
                                " entries (one per spine node), got " +
                                std::to_string(load.size()) + " and " +
                                std::to_string(capacity.size()));
  for (int i = 0; i < nodes; ++i)
    if (!std::isfinite(load[i]) || !std::isfinite(capacity[i]) || load[i] < 0 || capacity[i] <= 0)
      throw std::invalid_argument("ink: load[" + std::to_string(i) + "] = " + std::to_string(load[i]) +
                                  ", capacity = " + std::to_string(capacity[i]) +
                                  ": expected load >= 0, capacity > 0");
  if (!std::isfinite(excess) || excess < 0 || excess > 1)
    throw std::invalid_argument("ink.excess = " + std::to_string(excess) + ": expected 0..1");
}

Paper::Paper(double width_mm, double height_mm, double px_per_mm, const SceneFeatures& scene,
             int tile_px)
    : scene_(scene), width_mm_(width_mm), height_mm_(height_mm), ppm_(px_per_mm) {
  check_positive("width_mm", width_mm);
  check_positive("height_mm", height_mm);
  check_positive("px_per_mm", px_per_mm);
  scene_.validate();
  const double w = std::round(width_mm * px_per_mm), h = std::round(height_mm * px_per_mm);
  if (w < 1 || h < 1 || w > 32768 || h > 32768)
    throw std::invalid_argument("paper of " + std::to_string(w) + " x " + std::to_string(h) +
                                " px: each side must be 1..32768 px");
  W_ = static_cast<int>(w);
  H_ = static_cast<int>(h);
  if (tile_px != 0 && (tile_px < 16 || tile_px > 16384))
    throw std::invalid_argument("tile_px = " + std::to_string(tile_px) + ": expected 0 (auto) or 16..16384");

  ctx_ = RenderContext::acquire();
  ctx_->make_current();
  GLint max_rb = 0, max_vp[2] = {0, 0};
  gl::GetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_rb);
  gl::GetIntegerv(GL_MAX_VIEWPORT_DIMS, max_vp);
  const int limit = std::min({ctx_->info().max_texture_size, static_cast<int>(max_rb), max_vp[0], max_vp[1]});
  T_ = std::min(tile_px > 0 ? tile_px : 4096, limit);
  GLint max_samples = 1;
  gl::GetIntegerv(GL_MAX_SAMPLES, &max_samples);
  samples_ = std::clamp(static_cast<int>(max_samples), 1, scene_.samples);

  // tiles, each a float RGBA paper texture and its framebuffer, cleared to no ink
  for (int y0 = 0; y0 < H_; y0 += T_)
    for (int x0 = 0; x0 < W_; x0 += T_) {
      auto t = std::make_unique<PaperTile>();
      t->x0 = x0;
      t->y0 = y0;
      t->w = std::min(T_, W_ - x0);
      t->h = std::min(T_, H_ - y0);
      t->paper_tex = glu::texture(GL_RGBA32F, t->w, t->h, GL_RGBA, GL_FLOAT, nullptr, false, GL_CLAMP_TO_EDGE);
      gl::GenFramebuffers(1, &t->paper_fbo);
      gl::BindFramebuffer(GL_FRAMEBUFFER, t->paper_fbo);
      gl::FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->paper_tex, 0);
      glu::check_framebuffer("paper tile");
      gl::Disable(GL_SCISSOR_TEST);
      gl::ClearColor(0, 0, 0, 0);
      gl::Clear(GL_COLOR_BUFFER_BIT);
      tiles_.push_back(std::move(t));
    }

  // the footprint program with this scene's features compiled in, nothing else
  std::vector<std::string> defines;
  if (scene_.split_map) defines.push_back("USE_SPLIT");
  if (scene_.dry_map) defines.push_back("USE_DRY");
  if (scene_.grain) defines.push_back("USE_GRAIN");
  if (scene_.soaked_tip) defines.push_back("USE_SOAK");
  if (scene_.color_ramp) defines.push_back("USE_RAMP");
  if (scene_.depletion) defines.push_back("USE_DEPLETION");
  // one ink colour (no ramp): premultiplied (c a, a) grows with a in every component, so the
  // per-component maximum (blend equation MAX) keeps the densest deposit exactly as the depth
  // test on 1 - a does, without a depth buffer or a shader-written depth
  max_blend_ = !scene_.color_ramp;
  if (max_blend_) defines.push_back("USE_MAX_BLEND");
  program_ = std::make_unique<FootprintProgram>();
  FootprintProgram& fp = *program_;
  fp.prog = ctx_->program(shaders::kFootprintVertex, shaders::kFootprintFragment, defines);
  const GLuint p = fp.prog;
  fp.u_blends = glu::uniform(p, "u_blends");
  fp.u_slides = glu::uniform(p, "u_slides");
  fp.u_first = glu::uniform(p, "u_first");
  fp.u_shift = glu::uniform(p, "u_shift");
  fp.u_view = glu::uniform(p, "u_view");
  fp.u_soak = glu::uniform(p, "u_soak");
  fp.u_nodes = glu::uniform(p, "u_nodes");
  fp.u_wet = glu::uniform(p, "u_wet");
  fp.u_press = glu::uniform(p, "u_press");
  fp.u_color = glu::uniform(p, "u_color");
  fp.u_split = glu::uniform(p, "u_split");
  fp.u_dry = glu::uniform(p, "u_dry");
  fp.u_grain = glu::uniform(p, "u_grain");
  fp.u_ramp = glu::uniform(p, "u_ramp");
  fp.u_soak_shift = glu::uniform(p, "u_soak_shift");
  fp.u_dry_param = glu::uniform(p, "u_dry_param");
  fp.u_grain_scale = glu::uniform(p, "u_grain_scale");
  gl::GenVertexArrays(1, &fp.vao);
  gl::GenBuffers(1, &fp.vbo);
  gl::GenBuffers(1, &fp.ibo);
  gl::BindVertexArray(fp.vao);
  gl::BindBuffer(GL_ARRAY_BUFFER, fp.vbo);
  gl::BindBuffer(GL_ELEMENT_ARRAY_BUFFER, fp.ibo);
  // interleaved: prev (3), cur (3), centre prev (3), centre cur (3), uv (2) floats
  const GLsizei stride = 14 * sizeof(float);
  const int sizes[5] = {3, 3, 3, 3, 2};
  std::size_t off = 0;
  for (GLuint a = 0; a < 5; ++a) {
    gl::EnableVertexAttribArray(a);
    gl::VertexAttribPointer(a, sizes[a], GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(off));
    off += sizes[a] * sizeof(float);
  }
  gl::BindVertexArray(0);

  // composite: a full-tile triangle pair
  composite_program_ = ctx_->program(shaders::kQuadVertex, shaders::kCompositeFragment, {});
  const float quad[12] = {-1, -1, 1, -1, 1, 1, -1, -1, 1, 1, -1, 1};
  gl::GenVertexArrays(1, &quad_vao_);
  gl::GenBuffers(1, &quad_vbo_);
  gl::BindVertexArray(quad_vao_);
  gl::BindBuffer(GL_ARRAY_BUFFER, quad_vbo_);
  gl::BufferData(GL_ARRAY_BUFFER, sizeof(quad), quad, GL_STATIC_DRAW);
  gl::EnableVertexAttribArray(0);
  gl::VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 2 * sizeof(float), nullptr);
  gl::BindVertexArray(0);

  // the maps this scene uses, and only those
  if (scene_.split_map) {
    const auto& a = maps::cached('s', kSplitRows, kSplitCols, scene_.seed, maps::split_map);
    split_tex_ = glu::texture(GL_R32F, kSplitCols, kSplitRows, GL_RED, GL_FLOAT, a.data(), true, GL_REPEAT);
  }
  if (scene_.dry_map) {
    const auto& d = maps::cached('d', kSplitRows, kSplitCols, scene_.seed, maps::dry_map);
    dry_tex_ = glu::texture(GL_R32F, kSplitCols, kSplitRows, GL_RED, GL_FLOAT, d.data(), true, GL_REPEAT);
  }
  if (scene_.grain) {
    const auto& g = maps::cached('g', kGrainSize, kGrainSize, scene_.seed,
                                 [](int n, int, std::uint32_t seed) { return maps::grain_map(n, seed); });
    grain_tex_ = glu::texture(GL_R32F, kGrainSize, kGrainSize, GL_RED, GL_FLOAT, g.data(), true, GL_REPEAT);
  }
  if (scene_.color_ramp)
    ramp_tex_ = glu::texture(GL_RGBA32F, 1, 1, GL_RGBA, GL_FLOAT, nullptr, true, GL_CLAMP_TO_EDGE);
  glu::check("paper set-up");
}

Paper::~Paper() {
  if (!ctx_ || ctx_->closed()) return;  // the context took every GL object with it
  try {
    ctx_->make_current();
  } catch (...) {
    return;
  }
  for (auto& t : tiles_) {
    gl::DeleteFramebuffers(1, &t->paper_fbo);
    gl::DeleteTextures(1, &t->paper_tex);
    if (t->layer_fbo) {
      if (t->resolve_fbo != t->layer_fbo) gl::DeleteFramebuffers(1, &t->resolve_fbo);
      gl::DeleteFramebuffers(1, &t->layer_fbo);
      if (t->layer_color_ms) gl::DeleteRenderbuffers(1, &t->layer_color_ms);
      gl::DeleteRenderbuffers(1, &t->layer_depth_ms);
      gl::DeleteTextures(1, &t->layer_tex);
    }
  }
  if (program_) {  // (the programs belong to the context)
    gl::DeleteVertexArrays(1, &program_->vao);
    gl::DeleteBuffers(1, &program_->vbo);
    gl::DeleteBuffers(1, &program_->ibo);
  }
  gl::DeleteVertexArrays(1, &quad_vao_);
  gl::DeleteBuffers(1, &quad_vbo_);
  for (GLuint tex : {split_tex_, dry_tex_, grain_tex_, ramp_tex_})
    if (tex) gl::DeleteTextures(1, &tex);
}

void Paper::set_map(const std::string& which, const float* data, int rows, int cols) {
  if (rows < 2 || cols < 2 || rows > 8192 || cols > 8192)
    throw std::invalid_argument(which + " map of " + std::to_string(rows) + " x " +
                                std::to_string(cols) + ": each side must be 2..8192");
  for (long i = 0; i < static_cast<long>(rows) * cols; ++i)
    if (!std::isfinite(data[i]) || data[i] < 0.0f || data[i] > 1.0f)
      throw std::invalid_argument(which + " map: values must be in 0..1");
  GLuint* tex = nullptr;
  bool on = false;
  if (which == "split") tex = &split_tex_, on = scene_.split_map;
  else if (which == "dry") tex = &dry_tex_, on = scene_.dry_map;
  else if (which == "grain") tex = &grain_tex_, on = scene_.grain;
  else throw std::invalid_argument("map '" + which + "': expected split, dry or grain");
  if (!on)
    throw std::invalid_argument("the " + which + " map is not part of this paper's scene; "
                                "create the paper with it switched on");
  ctx_->make_current();
  if (*tex) gl::DeleteTextures(1, tex);
  *tex = glu::texture(GL_R32F, cols, rows, GL_RED, GL_FLOAT, data, true, GL_REPEAT);
}

void Paper::for_tiles(const Rect& rect, bool stroke_layer,
                      const std::function<void(PaperTile&, int, int, int, int)>& f) {
  for (auto& tp : tiles_) {
    PaperTile& t = *tp;
    const Rect r = intersect(rect, {t.x0, t.y0, t.x0 + t.w, t.y0 + t.h});
    if (empty(r)) continue;
    if (stroke_layer && t.layer_fbo == 0) {
      // first use of this tile's stroke layer: premultiplied RGBA and depth (1 - alpha; none
      // when the layer keeps the densest deposit by max blending);
      // multisampled (samples_ > 1) so that footprints thinner than a pixel still leave faint,
      // unbroken ink, then resolved into a single-sample texture (composited and read back);
      // with one sample the layer is drawn straight into that texture
      // with max blending and one ink colour the layer holds alpha alone (R32F): the colour is
      // the stroke's, applied when the layer is composited (a quarter of the bytes per fragment
      // blended and read back; ~20% of a deposit on llvmpipe)
      const GLenum layer_format = max_blend_ ? GL_R32F : GL_RGBA32F;
      t.layer_tex = glu::texture(layer_format, t.w, t.h, max_blend_ ? GL_RED : GL_RGBA, GL_FLOAT, nullptr, false,
                                 GL_CLAMP_TO_EDGE);
      if (!max_blend_) {
        gl::GenRenderbuffers(1, &t.layer_depth_ms);
        gl::BindRenderbuffer(GL_RENDERBUFFER, t.layer_depth_ms);
        gl::RenderbufferStorageMultisample(GL_RENDERBUFFER, samples_ > 1 ? samples_ : 0, GL_DEPTH_COMPONENT32F, t.w, t.h);
      }
      gl::GenFramebuffers(1, &t.layer_fbo);
      gl::BindFramebuffer(GL_FRAMEBUFFER, t.layer_fbo);
      if (samples_ > 1) {
        gl::GenRenderbuffers(1, &t.layer_color_ms);
        gl::BindRenderbuffer(GL_RENDERBUFFER, t.layer_color_ms);
        gl::RenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, layer_format, t.w, t.h);
        gl::FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t.layer_color_ms);
      } else {
        gl::FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t.layer_tex, 0);
      }
      if (!max_blend_)
        gl::FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, t.layer_depth_ms);
      glu::check_framebuffer("stroke layer tile");
      gl::Disable(GL_SCISSOR_TEST);
      gl::DepthMask(GL_TRUE);
      gl::ClearColor(0, 0, 0, 0);
      gl::ClearDepth(1.0);
      gl::Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      if (samples_ > 1) {
        gl::GenFramebuffers(1, &t.resolve_fbo);
        gl::BindFramebuffer(GL_FRAMEBUFFER, t.resolve_fbo);
        gl::FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t.layer_tex, 0);
        glu::check_framebuffer("stroke layer resolve");
        gl::Clear(GL_COLOR_BUFFER_BIT);
      } else {
        t.resolve_fbo = t.layer_fbo;  // nothing to resolve
      }
      glu::check("stroke layer allocation");
    }
    f(t, r[0] - t.x0, r[1] - t.y0, r[2] - r[0], r[3] - r[1]);
  }
}

void Paper::resolve_layer(const Rect& rect) {
  // average the samples of the layer into its texture, over `rect` only
  if (samples_ == 1) return;  // drawn straight into it
  gl::Disable(GL_SCISSOR_TEST);
  for (auto& tp : tiles_) {
    PaperTile& t = *tp;
    const Rect r = intersect(rect, {t.x0, t.y0, t.x0 + t.w, t.y0 + t.h});
    if (empty(r) || t.layer_fbo == 0) continue;
    const int x0 = r[0] - t.x0, y0 = r[1] - t.y0, x1 = r[2] - t.x0, y1 = r[3] - t.y0;
    gl::BindFramebuffer(GL_READ_FRAMEBUFFER, t.layer_fbo);
    gl::BindFramebuffer(GL_DRAW_FRAMEBUFFER, t.resolve_fbo);
    gl::BlitFramebuffer(x0, y0, x1, y1, x0, y0, x1, y1, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }
  gl::BindFramebuffer(GL_FRAMEBUFFER, 0);
}

void Paper::read_layer_alpha(const Rect& rect, std::vector<float>& out) {
  resolve_layer(rect);
  const int rw = rect[2] - rect[0], rh = rect[3] - rect[1];
  out.assign(static_cast<std::size_t>(rw) * rh, 0.0f);
  std::vector<float> buf;
  for (auto& tp : tiles_) {
    PaperTile& t = *tp;
    const Rect r = intersect(rect, {t.x0, t.y0, t.x0 + t.w, t.y0 + t.h});
    if (empty(r) || t.layer_fbo == 0) continue;
    const int w = r[2] - r[0], h = r[3] - r[1];
    const int comps = max_blend_ ? 1 : 4;  // an alpha-only layer, or premultiplied RGBA
    buf.resize(static_cast<std::size_t>(comps) * w * h);
    gl::BindFramebuffer(GL_FRAMEBUFFER, t.resolve_fbo);
    gl::PixelStorei(GL_PACK_ALIGNMENT, 4);
    gl::ReadPixels(r[0] - t.x0, r[1] - t.y0, w, h, max_blend_ ? GL_RED : GL_RGBA, GL_FLOAT, buf.data());
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        out[static_cast<std::size_t>(y + r[1] - rect[1]) * rw + (x + r[0] - rect[0])] =
            buf[comps * (static_cast<std::size_t>(y) * w + x) + comps - 1];
  }
}

MeshOptions Paper::mesh_options(const BrushModel& model) const {
  // a software rasteriser pays per triangle more than per pixel: a footprint drawn from 48 x 6
  // rings' 3-4 px triangles costs ~3x what 6 px ones do.  So the mesh is made only as fine as
  // mesh_px on this paper: the longest spine segment and the belly's circumference 2 pi r
  // (the widest ring, unpressed) over mesh_px, around rounded up to a multiple of 4.  The
  // chords of a ring of radius r px with A vertices lie up to r pi^2 / (2 A^2) px inside it
  // (0.2 px for the small brush's belly at 1024 px and 6 px); deposit() moves the vertices out
  // so that each ring keeps its section's area.
  // (A brush keeps its mesh for a whole stroke: the sweep pairs last and this deposit's
  // vertices, so the choice depends on nothing that changes from frame to frame.)
  MeshOptions opt;
  opt.rings_per_segment = scene_.mesh_rings;
  opt.around = scene_.mesh_around;
  if (scene_.mesh_px > 0.0) {
    const double seg_px = model.segment_lengths().maxCoeff() * ppm_;
    const double ring_px = 2.0 * kPi * model.belly_radius * ppm_;
    opt.rings_per_segment = std::clamp(static_cast<int>(std::ceil(seg_px / scene_.mesh_px)), 1, scene_.mesh_rings);
    opt.around = std::clamp(4 * static_cast<int>(std::ceil(ring_px / scene_.mesh_px / 4.0)), 8, scene_.mesh_around);
  }
  return opt;
}

DepositStats Paper::deposit(Brush& brush, Ink* ink) {
  ctx_->make_current();
  const int nodes = brush.model().n_segments + 1;
  if (nodes > kMaxNodes)
    throw std::invalid_argument("the renderer supports at most " + std::to_string(kMaxNodes - 1) + " spine segments");
  if (ink != nullptr) ink->validate(nodes);
  if (scene_.depletion && ink == nullptr)
    throw std::invalid_argument("this scene depletes ink: pass the brush's Ink to deposit()");
  DepositStats stats;

  const MeshOptions opt = mesh_options(brush.model());
  RenderMesh cur = build_render_mesh(brush, opt, false);
  {
    // a ring of A vertices is a polygon inscribed in its section: its area falls short by the
    // factor A sin(2 pi / A) / (2 pi) (1.1% at A = 24), and so would the ink.  Each vertex is
    // moved out from its ring's centre by the square root of the inverse, so that the polygon
    // has its section's area (vertices a little outside the surface, chord middles a little
    // inside)
    const double A = opt.around, k = std::sqrt(2.0 * kPi / (A * std::sin(2.0 * kPi / A)));
    for (std::size_t i = 0; i < cur.position.size(); ++i)
      cur.position[i] = static_cast<float>(cur.center[i] + k * (cur.position[i] - cur.center[i]));
  }
  const int V = cur.vertices();
  const double soak = (scene_.soaked_tip && ink != nullptr) ? scene_.soak_expand * ink->excess : 0.0;

  // the surface as the shader will place it (the soaked tip swells), for contact and bounds:
  // (V, 3) mm, each vertex moved out from its ring's centre by its growth at s = uv.x
  auto place = [&](const std::vector<float>& pos, const std::vector<float>& ctr, std::vector<double>& out) {
    out.resize(3 * static_cast<std::size_t>(V));
    for (int v = 0; v < V; ++v) {
      const double s = cur.uv[2 * v];
      const double t = std::clamp((s - 0.5) / 0.5, 0.0, 1.0);
      const double grow = 1.0 + soak * t * t * (3.0 - 2.0 * t);
      for (int d = 0; d < 3; ++d) out[3 * v + d] = ctr[3 * v + d] + (pos[3 * v + d] - ctr[3 * v + d]) * grow;
    }
  };
  // this deposit's surface so placed; the last deposit's below, once it is known
  std::vector<double> pc, pp;
  place(cur.position, cur.center, pc);
  double zmin = 1e300;
  for (int v = 0; v < V; ++v) zmin = std::min(zmin, pc[3 * v + 2]);
  stats.contact = zmin < 0.0;
  if (!stats.contact) {
    // the brush left the paper: the stroke ends here
    end_stroke();
    return stats;
  }

  // continue the stroke from the last deposit, or start one
  const bool continues = stroke_open_ && last_brush_ == &brush &&
                         last_vertices_.size() == cur.position.size();
  if (!continues) {
    flush_stroke();
    stats.new_stroke = true;
    stroke_rect_ = {0, 0, 0, 0};
    last_vertices_ = cur.position;
    last_centers_ = cur.center;
  }
  // the alpha-only layer takes one colour per stroke: a new colour composites the layer first
  // (the sweep goes on from the last deposit)
  const auto color = ink != nullptr ? ink->ramp.front() : std::array<float, 4>{0, 0, 0, 1};
  if (max_blend_ && stroke_pending_ && color != stroke_color_) flush_stroke();
  stroke_color_ = color;
  const std::vector<float>& prev = last_vertices_;
  const std::vector<float>& prev_c = last_centers_;
  // (the last deposit placed its surface with the same growth unless the soaked tip drained:
  // then it is the copy kept from then, the same numbers)
  if (!continues) pp = pc;
  else if (soak == last_soak_ && last_placed_.size() == pc.size()) pp.swap(last_placed_);
  else place(prev, prev_c, pp);

  // the triangles that can reach the paper at some point of the sweep (half a pixel of
  // antialiasing above it included), their pixel bounds and the largest travel; and those that
  // reach it in the last and in this deposit (the slid copies of each part draw only their own:
  // a pressed blob's slides need not rasterise the faces of the tip that only touches later)
  //
  // The sweep's list puts first the faces near the paper, then the inner ones: wholly below
  // it by more than half a pixel's depth in both deposits.  An inner face is inked all over
  // at every blend (its z is a mix of negative values) and lies inside the footprint, whose
  // outline runs through the faces near the paper (below the paper the surface does not fold:
  // a section's widest points are at its centre's height, above the paper).  The union of the
  // footprints over the blend is the two end footprints and the band their outline sweeps, so
  // the blends in between draw the near faces only and the last (t = 1) all of them (t = 0
  // is the last deposit's t = 1, drawn then).  ~40% of a pressed tuft's faces are inner: the
  // deposit takes ~10% less, and the ink of 永和九年 at 1024 px (without depletion, so the
  // same motion) differs from drawing every face on 3 of its 4.2 M pixels, by at most 0.18
  // in coverage.  The slid copies draw
  // all their faces: there the near band, steep at the tuft's sides, is thinner than the
  // 1.5 px between copies, and the slid parts' inner faces alone filled 1-px lines along the
  // stroke's edges (230 px of 永和九年).
  const double zcut = 1.0 / ppm_, inner = 0.5 / ppm_;
  std::vector<std::uint32_t> faces, faces_prev, faces_cur, inner_all;
  faces.reserve(cur.faces.size());
  std::vector<char> used(V, 0);
  faces_prev.reserve(cur.faces.size());
  faces_cur.reserve(cur.faces.size());
  inner_all.reserve(cur.faces.size());
  for (std::size_t f = 0; f < cur.faces.size(); f += 3) {
    const std::uint32_t* fv = &cur.faces[f];
    const double zc0 = pc[3 * fv[0] + 2], zc1 = pc[3 * fv[1] + 2], zc2 = pc[3 * fv[2] + 2];
    const double zp0 = pp[3 * fv[0] + 2], zp1 = pp[3 * fv[1] + 2], zp2 = pp[3 * fv[2] + 2];
    const double lo_cur = std::min({zc0, zc1, zc2}), lo_prev = std::min({zp0, zp1, zp2});
    if (std::min(lo_cur, lo_prev) < zcut) {  // (most of the tuft is above: those faces end here)
      const double hi_cur = std::max({zc0, zc1, zc2}), hi_prev = std::max({zp0, zp1, zp2});
      double ring_lo = 1e300;
      for (int e = 0; e < 3; ++e)
        ring_lo = std::min({ring_lo, static_cast<double>(cur.center[3 * fv[e] + 2]),
                            static_cast<double>(prev_c[3 * fv[e] + 2])});
      for (int e = 0; e < 3; ++e) used[cur.faces[f + e]] = 1;
      // (the premise above holds for a ring whose centre is above the paper; one whose centre
      // is below it has its widest points there too, and its faces can carry the outline, so
      // they stay near.  Spread sections rest their centres on the paper (Brush::sections),
      // but a ring's centre is the mean of its vertices, off the spine where a+ != a-, and the
      // apex is its own centre: without this, 永和九年 at 1024 px without depletion differs on
      // 3,851 px, saw teeth a frame apart along the edges)
      const bool inner_face = std::max(hi_cur, hi_prev) < -inner && ring_lo > -inner;
      std::vector<std::uint32_t>& sweep = inner_face ? inner_all : faces;
      sweep.insert(sweep.end(), &cur.faces[f], &cur.faces[f] + 3);
      if (lo_prev < zcut) faces_prev.insert(faces_prev.end(), &cur.faces[f], &cur.faces[f] + 3);
      if (lo_cur < zcut) faces_cur.insert(faces_cur.end(), &cur.faces[f], &cur.faces[f] + 3);
    }
  }
  // (near faces first, then the inner ones: a draw of the first near_all indices is the band)
  const std::size_t near_all = faces.size();
  faces.insert(faces.end(), inner_all.begin(), inner_all.end());
  double bx0 = 1e300, by0 = 1e300, bx1 = -1e300, by1 = -1e300;  // mm, whole sweep
  double cx0 = 1e300, cy0 = 1e300, cx1 = -1e300, cy1 = -1e300;  // mm, this frame's part below
  double travel = 0.0;                                           // mm
  // depth-weighted centres of the parts below the paper, last deposit and this one (mm)
  double wp = 0.0, wc = 0.0, pcx = 0.0, pcy = 0.0, ccx = 0.0, ccy = 0.0;
  for (int v = 0; v < V; ++v) {
    const double zc = pc[3 * v + 2], zp = pp[3 * v + 2];
    if (zc < 0.0) {
      const double x = pc[3 * v], y = pc[3 * v + 1];
      wc -= zc;
      ccx -= zc * x;
      ccy -= zc * y;
    }
    if (zp < 0.0) {
      const double x = pp[3 * v], y = pp[3 * v + 1];
      wp -= zp;
      pcx -= zp * x;
      pcy -= zp * y;
    }
  }

  // the slides are needed only where the blend breaks: where one end's part is much narrower
  // than the other's (a pressed blob and a thin trailing tip), or the surface blended between
  // the two deposits lifts off the paper or pinches to a neck on the way.  Widths are taken
  // across the move of the footprint's centre (mm): the extent, across the move, of the
  // blended near faces' vertices below the paper and of the points where their edges cross it
  // (the inner faces lie inside that outline; a lifted blend has no width), at t = 0 and 1 and
  // at t = 1/8 .. 7/8 against the narrower end's.  A blend that keeps at least kNeck of the
  // width leaves an unbroken band by itself: its copies are spaced no farther apart than this
  // frame's part is wide (below).  A centre that moves under half a pixel needs no slides.
  const bool both_below = wp > 0.0 && wc > 0.0;
  const double move_x = both_below ? ccx / wc - pcx / wp : 0.0, move_y = both_below ? ccy / wc - pcy / wp : 0.0;
  const double move_mm = std::hypot(move_x, move_y);
  // (each t blends only what can add to the width: the near faces' vertices below the paper
  // at either end, and their edges whose two ends can lie on the two sides of it at some t.
  // A blend (1 - t) a + t b of two depths of one sign keeps that sign, so a vertex above the
  // paper in both deposits is above it at every t, and an edge whose ends stay on one side
  // never crosses: the points added, and so the width, are those of all the near faces'.
  // Listed once, at the first t; each directed edge as often as the faces have it.)
  std::vector<int> dip_v, blend_v;
  std::vector<std::array<std::uint32_t, 2>> cross_e;
  std::vector<double> bl;  // (V, 3) mm, the blend at t of the vertices in blend_v
  auto width_across = [&](double t) {
    if (bl.empty()) {
      bl.resize(3 * static_cast<std::size_t>(V));
      std::vector<char> seen(V, 0);
      auto below = [&](std::uint32_t v) { return pp[3 * v + 2] < 0.0 || pc[3 * v + 2] < 0.0; };
      auto above = [&](std::uint32_t v) { return pp[3 * v + 2] >= 0.0 || pc[3 * v + 2] >= 0.0; };
      auto keep = [&](std::uint32_t v) {
        if (!seen[v]) seen[v] = 1, blend_v.push_back(static_cast<int>(v));
      };
      for (std::size_t f = 0; f < near_all; f += 3)
        for (int e = 0; e < 3; ++e) {
          const std::uint32_t a = faces[f + e], b = faces[f + (e + 1) % 3];
          if ((below(a) && above(b)) || (below(b) && above(a))) cross_e.push_back({a, b}), keep(a), keep(b);
        }
      std::vector<char> dipped(V, 0);
      for (std::size_t f = 0; f < near_all; ++f) {
        const std::uint32_t v = faces[f];
        if (!dipped[v] && below(v)) dipped[v] = 1, dip_v.push_back(static_cast<int>(v)), keep(v);
      }
    }
    for (const int v : blend_v)
      for (int d = 0; d < 3; ++d) bl[3 * v + d] = (1.0 - t) * pp[3 * v + d] + t * pc[3 * v + d];
    const double ux = move_x / move_mm, uy = move_y / move_mm;
    double lo = 1e300, hi = -1e300;
    auto add = [&](double x, double y) {
      const double b = -uy * x + ux * y;
      lo = std::min(lo, b), hi = std::max(hi, b);
    };
    for (const int v : dip_v)
      if (bl[3 * v + 2] < 0.0) add(bl[3 * v], bl[3 * v + 1]);
    for (const auto& e : cross_e) {
      const double* a = &bl[3 * static_cast<std::size_t>(e[0])];
      const double* b = &bl[3 * static_cast<std::size_t>(e[1])];
      if ((a[2] < 0.0) != (b[2] < 0.0)) {
        const double u = a[2] / (a[2] - b[2]);
        add(a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1]));
      }
    }
    return hi >= lo ? hi - lo : 0.0;
  };
  constexpr double kNeck = 0.5;
  bool both = false;
  if (both_below && move_mm * ppm_ > 0.5) {
    const double w0 = width_across(0.0), w1 = width_across(1.0), ends = std::min(w0, w1);
    both = ends < kNeck * std::max(w0, w1);
    for (int k = 1; k < 8 && !both; ++k) both = width_across(k / 8.0) < kNeck * ends;
  }
  const double shift_x = both ? move_x : 0.0, shift_y = both ? move_y : 0.0;
  // each part's extent along the shift and across it (mm): the slid copies of a part leave no
  // gap while they are spaced closer than its extent along the move
  double pext[4] = {1e300, -1e300, 1e300, -1e300}, cext[4] = {1e300, -1e300, 1e300, -1e300};
  if (both) {
    const double len = std::hypot(shift_x, shift_y), ux = shift_x / len, uy = shift_y / len;
    auto extend = [&](double* e, double x, double y) {
      const double a = ux * x + uy * y, b = -uy * x + ux * y;
      e[0] = std::min(e[0], a), e[1] = std::max(e[1], a), e[2] = std::min(e[2], b), e[3] = std::max(e[3], b);
    };
    for (int v = 0; v < V; ++v) {
      if (pc[3 * v + 2] < 0.0) extend(cext, pc[3 * v], pc[3 * v + 1]);
      if (pp[3 * v + 2] < 0.0) extend(pext, pp[3 * v], pp[3 * v + 1]);
    }
  }
  for (int v = 0; v < V; ++v) {
    if (!used[v]) continue;
    const double x = pc[3 * v], y = pc[3 * v + 1];
    const double px = pp[3 * v], py = pp[3 * v + 1];
    bx0 = std::min({bx0, x, px});
    by0 = std::min({by0, y, py});
    bx1 = std::max({bx1, x, px});
    by1 = std::max({by1, y, py});
    if (pc[3 * v + 2] < zcut) {
      cx0 = std::min(cx0, x);
      cy0 = std::min(cy0, y);
      cx1 = std::max(cx1, x);
      cy1 = std::max(cy1, y);
    }
    travel = std::max(travel, std::hypot(x - px, y - py));
  }
  // (the slid surfaces reach at most |shift| beyond the two surfaces' bounds)
  const double pad = std::hypot(shift_x, shift_y);
  const Rect rect = intersect({static_cast<int>(std::floor((bx0 - pad) * ppm_)) - 2,
                               static_cast<int>(std::floor((by0 - pad) * ppm_)) - 2,
                               static_cast<int>(std::ceil((bx1 + pad) * ppm_)) + 2,
                               static_cast<int>(std::ceil((by1 + pad) * ppm_)) + 2},
                              {0, 0, W_, H_});
  stats.rect = empty(rect) ? Rect{0, 0, 0, 0} : rect;

  // sub-steps of the sweep: close enough that consecutive footprints overlap and the
  // scallops between them stay under a quarter pixel (a disc of radius r spaced d apart
  // leaves scallops d^2 / 8r deep); r from the smaller side of this frame's part below
  // (spacing in px for a part whose smaller bounding side is `side_mm`: at most its radius,
  // so the copies overlap, and at most sqrt(2 r) for quarter-pixel scallops; never under 0.75)
  auto spacing_px = [&](double side_mm) {
    const double r_px = 0.5 * std::max(0.0, side_mm) * ppm_;
    return std::max(0.75, std::min(r_px, std::sqrt(2.0 * r_px)));
  };
  // ... and at most kBlendPx: the footprint is no disc but a rounded polygon, and a corner
  // moved in steps of d leaves a staircase up to d/2 deep along an edge slanted to the move
  // (with the disc rule alone, 6 px steps on a 45-degree stroke left 3 px saw teeth at
  // 1024 px; 2.5 px leaves at most ~1 px)
  constexpr double kBlendPx = 2.5;
  const double spacing = std::min(kBlendPx, spacing_px(std::min(cx1 - cx0, cy1 - cy0)));
  const int K = continues ? std::clamp(static_cast<int>(std::ceil(travel * ppm_ / spacing)), 1, 4096) : 1;
  stats.substeps = K;
  // slides: each part slid in copies by the same rule from its own extent (along and across
  // the move), capped at 1.5 px: a thin part (under ~2 px) still gets a copy every 0.75 px
  // and leaves a band, a pressed blob one every 1.5 px.  (Before: every 0.75 px for both.  A
  // wider spacing, up to the 7 px the scallop rule allows a 50 px blob, breaks thin necks
  // between a pressed entry and a fast drag: the 1-px anti-aliased rim of each copy carries
  // the band there.)
  const double shift_px = std::hypot(shift_x, shift_y) * ppm_;
  auto slide_copies = [&](const double* ext) {
    const double side = std::min(ext[1] - ext[0], ext[3] - ext[2]);
    return both ? std::clamp(static_cast<int>(std::ceil(shift_px / std::min(1.5, spacing_px(side)))), 1, 4096) : 0;
  };
  const int slides_prev = slide_copies(pext), slides_cur = slide_copies(cext);
  stats.slides = std::max(slides_prev, slides_cur);

  if (!empty(rect) && !faces.empty()) {
    // vertex data: prev, cur, centre prev, centre cur, uv
    std::vector<float> vb(static_cast<std::size_t>(14) * V);
    for (int v = 0; v < V; ++v) {
      float* o = &vb[14 * static_cast<std::size_t>(v)];
      for (int d = 0; d < 3; ++d) {
        o[d] = prev[3 * v + d];
        o[3 + d] = cur.position[3 * v + d];
        o[6 + d] = prev_c[3 * v + d];
        o[9 + d] = cur.center[3 * v + d];
      }
      o[12] = cur.uv[2 * v];
      o[13] = cur.uv[2 * v + 1];
    }
    FootprintProgram& fp = *program_;
    gl::UseProgram(fp.prog);
    gl::BindVertexArray(fp.vao);
    // (into the buffers' storage when it is large enough, else new storage of the size asked)
    auto upload = [](GLenum target, GLsizeiptr& have, GLsizeiptr bytes, const void* data) {
      if (bytes > have) {
        gl::BufferData(target, bytes, data, GL_DYNAMIC_DRAW);
        have = bytes;
      } else {
        gl::BufferSubData(target, 0, bytes, data);
      }
    };
    gl::BindBuffer(GL_ARRAY_BUFFER, fp.vbo);
    upload(GL_ARRAY_BUFFER, fp.vbo_bytes, static_cast<GLsizeiptr>(vb.size() * sizeof(float)), vb.data());
    // index buffer: the sweep's faces, then the last part's, then this part's
    const std::size_t n_all = faces.size(), n_prev = slides_prev > 0 ? faces_prev.size() : 0,
                      n_cur = slides_cur > 0 ? faces_cur.size() : 0;
    faces.insert(faces.end(), faces_prev.begin(), faces_prev.begin() + n_prev);
    faces.insert(faces.end(), faces_cur.begin(), faces_cur.begin() + n_cur);
    gl::BindBuffer(GL_ELEMENT_ARRAY_BUFFER, fp.ibo);
    upload(GL_ELEMENT_ARRAY_BUFFER, fp.ibo_bytes, static_cast<GLsizeiptr>(faces.size() * sizeof(std::uint32_t)),
           faces.data());

    // per-node wetness (the brush's) and pressure (from the sections)
    float wet[kMaxNodes] = {0}, press[kMaxNodes] = {0};
    const std::vector<float> pr = node_pressure(brush);
    for (int i = 0; i < nodes; ++i) {
      wet[i] = static_cast<float>(std::clamp(brush.wetness()[i], 0.0, 1.0));
      press[i] = pr[i];
    }
    gl::Uniform1i(fp.u_nodes, nodes);
    gl::Uniform1fv(fp.u_wet, nodes, wet);
    gl::Uniform1fv(fp.u_press, nodes, press);
    gl::Uniform4f(fp.u_color, color[0], color[1], color[2], color[3]);
    gl::Uniform1f(fp.u_soak, static_cast<float>(soak));
    gl::Uniform1f(fp.u_soak_shift, static_cast<float>(
        (scene_.soaked_tip && ink != nullptr) ? scene_.soak_shift * ink->excess : 0.0));
    gl::Uniform4f(fp.u_dry_param, static_cast<float>(scene_.dry_onset), static_cast<float>(scene_.dry_pressure),
                  static_cast<float>(scene_.grain_onset), static_cast<float>(scene_.grain_pressure));
    gl::Uniform1f(fp.u_grain_scale, static_cast<float>(1.0 / scene_.grain_period_mm));
    const GLuint units[4] = {split_tex_, dry_tex_, grain_tex_, ramp_tex_};
    const GLint locs[4] = {fp.u_split, fp.u_dry, fp.u_grain, fp.u_ramp};
    if (scene_.color_ramp && ink != nullptr) {
      gl::BindTexture(GL_TEXTURE_2D, ramp_tex_);
      gl::TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, static_cast<GLsizei>(ink->ramp.size()), 1, 0,
                     GL_RGBA, GL_FLOAT, ink->ramp.data());
    }
    for (int u = 0; u < 4; ++u) {
      if (locs[u] < 0 || units[u] == 0) continue;
      gl::ActiveTexture(GL_TEXTURE0 + u);
      gl::BindTexture(GL_TEXTURE_2D, units[u]);
      gl::Uniform1i(locs[u], u);
    }
    gl::ActiveTexture(GL_TEXTURE0);

    std::vector<float> after;

    // draw the sweep into the stroke layer: downward-facing triangles only (seen from below,
    // a face whose outward normal points down is clockwise on the paper), densest wins (max
    // blend, or depth test on 1 - alpha with a colour ramp)
    if (max_blend_) {
      gl::Disable(GL_DEPTH_TEST);
      gl::Enable(GL_BLEND);
      gl::BlendEquation(GL_MAX);
    } else {
      gl::Enable(GL_DEPTH_TEST);
      gl::DepthFunc(GL_LESS);
      gl::DepthMask(GL_TRUE);
      gl::Disable(GL_BLEND);
    }
    gl::Enable(GL_CULL_FACE);
    gl::FrontFace(GL_CCW);
    gl::CullFace(GL_FRONT);
    gl::Enable(GL_SCISSOR_TEST);
    for_tiles(rect, true, [&](PaperTile& t, int x, int y, int w, int h) {
      gl::UseProgram(fp.prog);
      gl::BindVertexArray(fp.vao);
      gl::BindFramebuffer(GL_FRAMEBUFFER, t.layer_fbo);
      gl::Viewport(0, 0, t.w, t.h);
      gl::Scissor(x, y, w, h);
      gl::Uniform4f(fp.u_view, static_cast<float>(t.x0 / ppm_), static_cast<float>(t.y0 / ppm_),
                    static_cast<float>(2.0 * ppm_ / t.w), static_cast<float>(2.0 * ppm_ / t.h));
      // the sweep between the last deposit and this one: the surface blended from one to the
      // other over K sub-steps (right for a tuft that turns or bends on the way), and each of
      // the two parts below the paper slid rigidly along the move of the footprint's centre
      // toward the other (so that a tuft whose shape changes a lot between frames still
      // leaves one unbroken band: the blend alone lifts off the paper halfway between a
      // pressed blob and a thin trailing tip).  The price: where the shape changes abruptly
      // the slid blob paints a little more than the brush touched.
      gl::Uniform1i(fp.u_blends, K);
      gl::Uniform2i(fp.u_slides, slides_prev, slides_cur);
      gl::Uniform2f(fp.u_shift, static_cast<float>(shift_x), static_cast<float>(shift_y));
      // instanced draws: the blends before t = 1 over the near faces, t = 1 over all, the last
      // part slid and this part slid over theirs; u_first numbers the instances on from the
      // draws before
      auto draw = [&](std::size_t offset, std::size_t size, int first, int count) {
        if (count <= 0 || size == 0) return;
        gl::Uniform1i(fp.u_first, first);
        gl::DrawElementsInstanced(GL_TRIANGLES, static_cast<GLsizei>(size), GL_UNSIGNED_INT,
                                  reinterpret_cast<const void*>(offset * sizeof(std::uint32_t)), count);
      };
      draw(0, near_all, 0, K - 1);
      draw(0, n_all, K - 1, 1);
      draw(n_all, n_prev, K, slides_prev);
      draw(n_all + n_prev, n_cur, K + slides_prev, slides_cur);
    });
    gl::Disable(GL_SCISSOR_TEST);
    gl::Disable(GL_CULL_FACE);
    gl::Disable(GL_DEPTH_TEST);
    gl::BlendEquation(GL_FUNC_ADD);
    gl::Disable(GL_BLEND);
    gl::BindVertexArray(0);
    glu::check("footprint pass");

    // depletion: what the layer gained is what the brush lost (seed: "automatically subtract
    // the ink values from the brush"), taken from the pressed nodes that still hold ink
    if (scene_.depletion) {
      // (the layer's alpha before this deposit is the copy kept from the last readback: one
      // readback per frame instead of two; the sum is the same, term for term)
      read_layer_alpha(rect, after);
      if (layer_alpha_.empty()) layer_alpha_.assign(static_cast<std::size_t>(W_) * H_, 0.0f);
      double gained = 0.0;
      const int rw = rect[2] - rect[0], rh = rect[3] - rect[1];
      for (int y = 0; y < rh; ++y) {
        const float* row = &after[static_cast<std::size_t>(y) * rw];
        float* kept = &layer_alpha_[static_cast<std::size_t>(rect[1] + y) * W_ + rect[0]];
        for (int x = 0; x < rw; ++x) {
          gained += static_cast<double>(row[x]) - kept[x];
          kept[x] = row[x];
        }
      }
      gained /= ppm_ * ppm_;  // px -> mm^2
      stats.deposited = gained;
      double remaining = std::min(gained, ink->load.sum());
      for (int pass = 0; pass < 3 && remaining > 1e-15; ++pass) {
        double wsum = 0.0;
        Eigen::VectorXd wgt(nodes);
        for (int i = 0; i < nodes; ++i) wsum += (wgt[i] = (pass == 0 ? press[i] : 1.0) * ink->load[i]);
        if (wsum <= 0.0) continue;
        double taken = 0.0;
        for (int i = 0; i < nodes; ++i) {
          const double take = std::min(ink->load[i], remaining * wgt[i] / wsum);
          ink->load[i] -= take;
          taken += take;
        }
        remaining -= taken;
      }
      ink->deposited += gained;
      // capillary flow inside the tuft: every node's wetness relaxes toward the tuft's mean by
      // the fraction `capillary` per frame; sum(load) is unchanged (load_i += b (w_mean cap_i -
      // load_i) sums to zero), so conservation holds
      const double w_mean = ink->load.sum() / ink->capacity.sum();
      ink->load += scene_.capillary * (w_mean * ink->capacity - ink->load);
      for (int i = 0; i < nodes; ++i) brush.wetness()[i] = std::clamp(ink->load[i] / ink->capacity[i], 0.0, 1.0);
    }
    stroke_rect_ = unite(stroke_rect_, rect);
    stroke_pending_ = true;
  }
  // the soaked tip drains with the distance it travels in contact
  if (scene_.soaked_tip && ink != nullptr) ink->excess *= std::exp(-travel / scene_.soak_drain_mm);

  stroke_open_ = true;
  last_brush_ = &brush;
  last_vertices_ = cur.position;
  last_centers_ = cur.center;
  last_placed_.swap(pc);
  last_soak_ = soak;
  return stats;
}

void Paper::end_stroke() {
  if (!ctx_->closed()) {
    ctx_->make_current();
    flush_stroke();
  }
  stroke_open_ = false;
  last_brush_ = nullptr;
}

void Paper::flush_stroke() {
  if (!stroke_pending_) return;
  const Rect rect = stroke_rect_;
  // keep what the stroke covers, for undo (premultiplied RGBA, row 0 at the bottom)
  const int rw = rect[2] - rect[0], rh = rect[3] - rect[1];
  undo_pixels_.assign(static_cast<std::size_t>(4) * rw * rh, 0.0f);
  std::vector<float> buf;
  for_tiles(rect, false, [&](PaperTile& t, int x, int y, int w, int h) {
    buf.resize(static_cast<std::size_t>(4) * w * h);
    gl::BindFramebuffer(GL_FRAMEBUFFER, t.paper_fbo);
    gl::PixelStorei(GL_PACK_ALIGNMENT, 4);
    gl::ReadPixels(x, y, w, h, GL_RGBA, GL_FLOAT, buf.data());
    for (int j = 0; j < h; ++j)
      std::copy_n(&buf[4 * static_cast<std::size_t>(j) * w], 4 * w,
                  &undo_pixels_[4 * (static_cast<std::size_t>(j + t.y0 + y - rect[1]) * rw + (t.x0 + x - rect[0]))]);
  });
  undo_rect_ = rect;
  undo_available_ = true;

  // composite the layer over the paper (premultiplied over), then clear the layer
  resolve_layer(rect);
  gl::UseProgram(composite_program_);
  gl::BindVertexArray(quad_vao_);
  gl::Enable(GL_SCISSOR_TEST);
  for_tiles(rect, true, [&](PaperTile& t, int x, int y, int w, int h) {
    gl::BindFramebuffer(GL_FRAMEBUFFER, t.paper_fbo);
    gl::Viewport(0, 0, t.w, t.h);
    gl::Scissor(x, y, w, h);
    gl::Enable(GL_BLEND);
    gl::BlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    gl::ActiveTexture(GL_TEXTURE0);
    gl::BindTexture(GL_TEXTURE_2D, t.layer_tex);
    gl::Uniform1i(glu::uniform(composite_program_, "u_layer"), 0);
    const std::array<float, 4> li = layer_ink();
    gl::Uniform4f(glu::uniform(composite_program_, "u_layer_ink"), li[0], li[1], li[2], li[3]);
    gl::DrawArrays(GL_TRIANGLES, 0, 6);
    gl::BindTexture(GL_TEXTURE_2D, 0);  // (with one sample the layer is drawn into that texture)
    gl::Disable(GL_BLEND);
    gl::BindFramebuffer(GL_FRAMEBUFFER, t.layer_fbo);
    gl::DepthMask(GL_TRUE);
    gl::ClearColor(0, 0, 0, 0);
    gl::ClearDepth(1.0);
    gl::Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  });
  gl::Disable(GL_SCISSOR_TEST);
  gl::BindVertexArray(0);
  glu::check("stroke composite");
  forget_layer_alpha(rect);
  stroke_pending_ = false;
  stroke_rect_ = {0, 0, 0, 0};
}

void Paper::forget_layer_alpha(const Rect& rect) {
  // the layer was cleared over `rect`: so is the kept copy of its alpha
  if (layer_alpha_.empty() || empty(rect)) return;
  for (int y = rect[1]; y < rect[3]; ++y)
    std::fill_n(&layer_alpha_[static_cast<std::size_t>(y) * W_ + rect[0]], rect[2] - rect[0], 0.0f);
}

bool Paper::undo() {
  ctx_->make_current();
  if (stroke_pending_) {
    // the stroke in progress (or not yet composited): drop the layer
    gl::Enable(GL_SCISSOR_TEST);
    for_tiles(stroke_rect_, true, [&](PaperTile& t, int x, int y, int w, int h) {
      gl::BindFramebuffer(GL_FRAMEBUFFER, t.layer_fbo);
      gl::Scissor(x, y, w, h);
      gl::DepthMask(GL_TRUE);
      gl::ClearColor(0, 0, 0, 0);
      gl::ClearDepth(1.0);
      gl::Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    });
    gl::Disable(GL_SCISSOR_TEST);
    forget_layer_alpha(stroke_rect_);
    stroke_pending_ = false;
    stroke_open_ = false;
    last_brush_ = nullptr;
    stroke_rect_ = {0, 0, 0, 0};
    return true;
  }
  if (!undo_available_) return false;
  const Rect rect = undo_rect_;
  const int rw = rect[2] - rect[0];
  std::vector<float> buf;
  for_tiles(rect, false, [&](PaperTile& t, int x, int y, int w, int h) {
    buf.resize(static_cast<std::size_t>(4) * w * h);
    for (int j = 0; j < h; ++j)
      std::copy_n(&undo_pixels_[4 * (static_cast<std::size_t>(j + t.y0 + y - rect[1]) * rw + (t.x0 + x - rect[0]))],
                  4 * w, &buf[4 * static_cast<std::size_t>(j) * w]);
    gl::BindTexture(GL_TEXTURE_2D, t.paper_tex);
    gl::PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    gl::TexSubImage2D(GL_TEXTURE_2D, 0, x, y, w, h, GL_RGBA, GL_FLOAT, buf.data());
  });
  undo_available_ = false;
  undo_pixels_.clear();
  glu::check("undo");
  return true;
}

void Paper::clear() {
  ctx_->make_current();
  for (auto& tp : tiles_) {
    gl::BindFramebuffer(GL_FRAMEBUFFER, tp->paper_fbo);
    gl::ClearColor(0, 0, 0, 0);
    gl::Clear(GL_COLOR_BUFFER_BIT);
    if (tp->layer_fbo) {
      gl::BindFramebuffer(GL_FRAMEBUFFER, tp->layer_fbo);
      gl::DepthMask(GL_TRUE);
      gl::ClearDepth(1.0);
      gl::Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    }
  }
  stroke_open_ = stroke_pending_ = undo_available_ = false;
  last_brush_ = nullptr;
  stroke_rect_ = {0, 0, 0, 0};
  undo_pixels_.clear();
  // (the kept copy of the layer's alpha is zeroed, not freed: a batch worker clears one paper per
  // character, and 4 MB freed and allocated again at 1024 px are page-faulted in again)
  std::fill(layer_alpha_.begin(), layer_alpha_.end(), 0.0f);
}

void Paper::read_tiles(const std::function<void(const PaperTile&, const float*)>& f) {
  ctx_->make_current();
  if (stroke_pending_) resolve_layer(stroke_rect_);
  std::vector<float> buf, layer;
  for (auto& tp : tiles_) {
    const PaperTile& t = *tp;
    buf.resize(static_cast<std::size_t>(4) * t.w * t.h);
    gl::BindFramebuffer(GL_FRAMEBUFFER, t.paper_fbo);
    gl::PixelStorei(GL_PACK_ALIGNMENT, 4);
    gl::ReadPixels(0, 0, t.w, t.h, GL_RGBA, GL_FLOAT, buf.data());
    const Rect r = intersect(stroke_rect_, {t.x0, t.y0, t.x0 + t.w, t.y0 + t.h});
    if (stroke_pending_ && t.layer_fbo && !empty(r)) {
      // a stroke still in the layer shows as if composited (premultiplied over)
      const int x = r[0] - t.x0, y = r[1] - t.y0, w = r[2] - r[0], h = r[3] - r[1];
      // (an alpha-only layer's texel a is the ink (r a, g a, b a, a))
      const std::array<float, 4> li = layer_ink();
      const bool single = li[3] > 0.5f;
      const int comps = single ? 1 : 4;
      layer.resize(static_cast<std::size_t>(comps) * w * h);
      gl::BindFramebuffer(GL_FRAMEBUFFER, t.resolve_fbo);
      gl::ReadPixels(x, y, w, h, single ? GL_RED : GL_RGBA, GL_FLOAT, layer.data());
      for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
          const float* T = &layer[comps * (static_cast<std::size_t>(j) * w + i)];
          const float L[4] = {single ? li[0] * T[0] : T[0], single ? li[1] * T[0] : T[1],
                              single ? li[2] * T[0] : T[2], single ? T[0] : T[3]};
          float* P = &buf[4 * (static_cast<std::size_t>(j + y) * t.w + (i + x))];
          for (int c = 0; c < 4; ++c) P[c] = L[c] + P[c] * (1.0f - L[3]);
        }
    }
    f(t, buf.data());
  }
  glu::check("paper readback");
}

void Paper::read_rgba(float* out) {
  // GL rows run bottom-up; numpy's row 0 is the top of the paper: flip once, here
  read_tiles([&](const PaperTile& t, const float* buf) {
    for (int j = 0; j < t.h; ++j)
      std::copy_n(buf + 4 * static_cast<std::size_t>(j) * t.w, 4 * t.w,
                  out + 4 * (static_cast<std::size_t>(H_ - 1 - (t.y0 + j)) * W_ + t.x0));
  });
}

void Paper::read_ink(float* out) {
  read_tiles([&](const PaperTile& t, const float* buf) {
    for (int j = 0; j < t.h; ++j) {
      float* row = out + static_cast<std::size_t>(H_ - 1 - (t.y0 + j)) * W_ + t.x0;
      const float* src = buf + 4 * static_cast<std::size_t>(j) * t.w;
      for (int i = 0; i < t.w; ++i) row[i] = src[4 * i + 3];
    }
  });
}

namespace {

// float -> the nearest integer, ties to even: what np.round (and std::nearbyint in the default
// rounding mode) gives; on x86-64 one cvtss2si instead of a call into libm
inline int round_even(float v) {
#if defined(__SSE2__)
  return _mm_cvt_ss2si(_mm_set_ss(v));
#else
  return static_cast<int>(std::nearbyint(v));
#endif
}

// one row of n RGBA float texels (premultiplied, GL's order) into n pixels of C = 3 (over white)
// or 4 (on transparency) channels of T; kBgr swaps red and blue (OpenCV's order)
template <typename T, bool kWhite, bool kBgr>
void image_row(const float* src, T* dst, int n, float top) {
  constexpr int C = kWhite ? 3 : 4;
  for (int i = 0; i < n; ++i, src += 4, dst += C) {
    float p[4];
    for (int c = 0; c < 4; ++c) p[c] = std::clamp(src[c], 0.0f, 1.0f);
    float v[4];
    for (int c = 0; c < 3; ++c) v[c] = kWhite ? (p[c] - p[3]) + 1.0f : (p[3] > 1e-6f ? p[c] / p[3] : 0.0f);
    v[3] = p[3];
    for (int c = 0; c < C; ++c) {
      // (the product is rounded to float first, as numpy does, then to an integer)
      const float scaled = std::clamp(v[c], 0.0f, 1.0f) * top;
      dst[(kBgr && c < 3) ? 2 - c : c] = static_cast<T>(round_even(scaled));
    }
  }
}

template <typename T, bool kWhite, bool kBgr>
void image_rows(const PaperTile& t, const float* buf, T* out, int W, int H, float top) {
  constexpr int C = kWhite ? 3 : 4;
  for (int j = 0; j < t.h; ++j)
    image_row<T, kWhite, kBgr>(buf + 4 * static_cast<std::size_t>(j) * t.w,
                               out + (static_cast<std::size_t>(H - 1 - (t.y0 + j)) * W + t.x0) * C, t.w, top);
}

}  // namespace

void Paper::read_image(int bits, bool white, bool bgr, void* out) {
  if (bits != 8 && bits != 16) throw std::invalid_argument("bits = " + std::to_string(bits) + ": expected 8 or 16");
  // the arithmetic of numpy in float32, step for step (clip the premultiplied RGBA; over white
  // c + (1 - a), on transparency c / a where a > 1e-6; clip; scale; round half to even), so
  // that an image is the same byte for byte whichever way it is made; one pass over the pixels
  // instead of numpy's temporaries (a 1024 px character's four float planes are 16 MB), each
  // case its own loop without branches or calls (the whole call, readback included, 12 -> 5 ms
  // at 1024 px)
  const float top = bits == 8 ? 255.0f : 65535.0f;
  read_tiles([&](const PaperTile& t, const float* buf) {
    auto* o8 = static_cast<std::uint8_t*>(out);
    auto* o16 = static_cast<std::uint16_t*>(out);
    const int code = (bits == 8 ? 0 : 4) + (white ? 0 : 2) + (bgr ? 1 : 0);
    switch (code) {
      case 0: image_rows<std::uint8_t, true, false>(t, buf, o8, W_, H_, top); break;
      case 1: image_rows<std::uint8_t, true, true>(t, buf, o8, W_, H_, top); break;
      case 2: image_rows<std::uint8_t, false, false>(t, buf, o8, W_, H_, top); break;
      case 3: image_rows<std::uint8_t, false, true>(t, buf, o8, W_, H_, top); break;
      case 4: image_rows<std::uint16_t, true, false>(t, buf, o16, W_, H_, top); break;
      case 5: image_rows<std::uint16_t, true, true>(t, buf, o16, W_, H_, top); break;
      case 6: image_rows<std::uint16_t, false, false>(t, buf, o16, W_, H_, top); break;
      default: image_rows<std::uint16_t, false, true>(t, buf, o16, W_, H_, top); break;
    }
  });
}

void Paper::write_rgba(const float* in) {
  ctx_->make_current();
  for (int i = 0; i < 4 * W_ * H_; ++i)
    if (!std::isfinite(in[i]) || in[i] < 0.0f || in[i] > 1.0f)
      throw std::invalid_argument("paper image: values must be finite and in 0..1");
  clear();
  std::vector<float> buf;
  for (auto& tp : tiles_) {
    const PaperTile& t = *tp;
    buf.resize(static_cast<std::size_t>(4) * t.w * t.h);
    for (int j = 0; j < t.h; ++j)
      std::copy_n(in + 4 * (static_cast<std::size_t>(H_ - 1 - (t.y0 + j)) * W_ + t.x0), 4 * t.w,
                  &buf[4 * static_cast<std::size_t>(j) * t.w]);
    gl::BindTexture(GL_TEXTURE_2D, t.paper_tex);
    gl::PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    gl::TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, t.w, t.h, GL_RGBA, GL_FLOAT, buf.data());
  }
  glu::check("paper upload");
}

std::array<float, 4> Paper::layer_ink() const {
  // how the layer's texels become premultiplied ink: (r, g, b, 1) for an alpha-only layer
  // (texel a -> (r a, g a, b a, a), the ink's alpha already in a), (0, 0, 0, 0) for RGBA
  if (!max_blend_) return {0, 0, 0, 0};
  return {stroke_color_[0], stroke_color_[1], stroke_color_[2], 1.0f};
}

std::vector<Paper::TileRef> Paper::tile_textures() {
  ctx_->make_current();
  if (stroke_pending_) resolve_layer(stroke_rect_);
  std::vector<TileRef> out;
  for (auto& tp : tiles_)
    out.push_back({tp->paper_tex, stroke_pending_ ? tp->layer_tex : 0u, tp->x0, tp->y0, tp->w, tp->h, layer_ink()});
  return out;
}

}  // namespace brushwork
