// The paper: float ink in tiles, the footprint pass, strokes, undo and readback
// (seed "Ink depositing", "System prototype": stroke undo, image saving and loading).
#include <algorithm>
#include <array>
#if defined(__SSE2__)
#endif
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "brushwork/render.hpp"
#include "checks.hpp"
#include "footprint_pass.hpp"
#include "gl_util.hpp"
#include "shaders.hpp"
#include "stroke_frame.hpp"
#include "pixels.hpp"
#include "wet_area.hpp"

namespace brushwork {

// one tile of the canvas: the paper and, allocated on first use, the stroke layer
struct PaperTile {
  int x0 = 0, y0 = 0, w = 0, h = 0;  // px, y up
  GlTexture paper_tex;
  GlFramebuffer paper_fbo;
  // the stroke layer: multisampled colour and depth (drawn into), and a single-sample
  // texture it resolves into (composited and read back)
  GlRenderbuffer layer_color_ms, layer_depth_ms;
  GlFramebuffer layer_fbo;
  GlTexture layer_tex;
  GlFramebuffer resolve_fbo;  // 0 with one sample: the layer is drawn straight into layer_tex
  GLuint resolved() const { return resolve_fbo ? resolve_fbo : layer_fbo; }  // holds layer_tex
};

namespace {

// mm: side of the cells the ink a deposit spends is measured in (WetArea): fixed on the paper,
// so that the brush's ink and motion do not depend on the output's resolution
constexpr double kWetCellMm = 0.1;

constexpr int kMaxPaperPx = 32768;  // px: the longest side of a paper
constexpr int kMinTilePx = 16;      // px: the smallest tile side asked for
constexpr int kMaxTilePx = 16384;   // px: the largest tile side asked for
constexpr int kAutoTilePx = 4096;   // px: the tile side when none is asked (or the GL's limit)
constexpr int kMinMapPx = 2;        // texels: the shortest side of a map image
constexpr int kMaxMapPx = 8192;     // texels: the longest side of a map image

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


}  // namespace

Paper::Paper(double width_mm, double height_mm, double px_per_mm, const SceneFeatures& scene,
             int tile_px)
    : scene_(scene), width_mm_(width_mm), height_mm_(height_mm), ppm_(px_per_mm) {
  const auto [w, h] = checks::paper_pixels(width_mm, height_mm, px_per_mm, kMaxPaperPx);
  scene_.validate();
  W_ = w;
  H_ = h;
  if (tile_px != 0 && (tile_px < kMinTilePx || tile_px > kMaxTilePx))
    throw std::invalid_argument("tile_px = " + std::to_string(tile_px) + ": expected 0 (auto) or " +
                                std::to_string(kMinTilePx) + ".." + std::to_string(kMaxTilePx));

  ctx_ = RenderContext::acquire();
  ctx_->make_current();
  GLint max_rb = 0, max_vp[2] = {0, 0};
  gl::GetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_rb);
  gl::GetIntegerv(GL_MAX_VIEWPORT_DIMS, max_vp);
  const int limit = std::min({ctx_->info().max_texture_size, static_cast<int>(max_rb), max_vp[0], max_vp[1]});
  T_ = std::min(tile_px > 0 ? tile_px : kAutoTilePx, limit);
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
      t->paper_tex.reset(ctx_.get(), glu::texture(GL_RGBA32F, t->w, t->h, GL_RGBA, GL_FLOAT, nullptr, false, GL_CLAMP_TO_EDGE));
      t->paper_fbo.generate(ctx_.get());
      gl::BindFramebuffer(GL_FRAMEBUFFER, t->paper_fbo);
      gl::FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->paper_tex, 0);
      glu::check_framebuffer("paper tile");
      gl::Disable(GL_SCISSOR_TEST);
      gl::ClearColor(0, 0, 0, 0);
      gl::Clear(GL_COLOR_BUFFER_BIT);
      tiles_.push_back(std::move(t));
    }

  // one ink colour (no ramp): premultiplied (c a, a) grows with a in every component, so the
  // per-component maximum (blend equation MAX) keeps the densest deposit exactly as the depth
  // test on 1 - a does, without a depth buffer or a shader-written depth
  max_blend_ = !scene_.color_ramp;
  // the footprint program with this scene's features compiled in, nothing else
  program_ = std::make_unique<FootprintPass>(*ctx_, scene_, max_blend_);
  wet_ = std::make_unique<WetLedger>(kWetCellMm);

  // composite: a full-tile triangle pair
  composite_program_ = ctx_->program(shaders::kQuadVertex, shaders::kCompositeFragment, {});
  const float quad[12] = {-1, -1, 1, -1, 1, 1, -1, -1, 1, 1, -1, 1};
  quad_vao_.generate(ctx_.get());
  quad_vbo_.generate(ctx_.get());
  gl::BindVertexArray(quad_vao_);
  gl::BindBuffer(GL_ARRAY_BUFFER, quad_vbo_);
  gl::BufferData(GL_ARRAY_BUFFER, sizeof(quad), quad, GL_STATIC_DRAW);
  gl::EnableVertexAttribArray(0);
  gl::VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 2 * sizeof(float), nullptr);
  gl::BindVertexArray(0);

  // the split, dry and grain fields are procedural (in the footprint shader) until an image
  // replaces one (set_map)
  if (scene_.color_ramp)
    ramp_tex_.reset(ctx_.get(), glu::texture(GL_RGBA32F, 1, 1, GL_RGBA, GL_FLOAT, nullptr, true, GL_CLAMP_TO_EDGE));
  glu::check("paper set-up");
}

Paper::~Paper() = default;  // the GL objects delete themselves (GlName)

void Paper::set_map(const std::string& which, const float* data, int rows, int cols) {
  if (rows < kMinMapPx || cols < kMinMapPx || rows > kMaxMapPx || cols > kMaxMapPx)
    throw std::invalid_argument(which + " map of " + std::to_string(rows) + " x " + std::to_string(cols) +
                                ": each side must be " + std::to_string(kMinMapPx) + ".." + std::to_string(kMaxMapPx));
  for (long i = 0; i < static_cast<long>(rows) * cols; ++i)
    if (!std::isfinite(data[i]) || data[i] < 0.0f || data[i] > 1.0f)
      throw std::invalid_argument(which + " map: values must be in 0..1");
  GlTexture* tex = nullptr;
  bool on = false;
  if (which == "split") tex = &split_tex_, on = scene_.split_map;
  else if (which == "dry") tex = &dry_tex_, on = scene_.dry_map;
  else if (which == "grain") tex = &grain_tex_, on = scene_.grain;
  else throw std::invalid_argument("map '" + which + "': expected split, dry or grain");
  if (!on)
    throw std::invalid_argument("the " + which + " map is not part of this paper's scene; "
                                "create the paper with it switched on");
  ctx_->make_current();
  tex->reset(ctx_.get(), glu::texture(GL_R32F, cols, rows, GL_RED, GL_FLOAT, data, true, GL_REPEAT));
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
      t.layer_tex.reset(ctx_.get(), glu::texture(layer_format, t.w, t.h, max_blend_ ? GL_RED : GL_RGBA, GL_FLOAT,
                                                 nullptr, false, GL_CLAMP_TO_EDGE));
      if (!max_blend_) {
        t.layer_depth_ms.generate(ctx_.get());
        gl::BindRenderbuffer(GL_RENDERBUFFER, t.layer_depth_ms);
        gl::RenderbufferStorageMultisample(GL_RENDERBUFFER, samples_ > 1 ? samples_ : 0, GL_DEPTH_COMPONENT32F, t.w, t.h);
      }
      t.layer_fbo.generate(ctx_.get());
      gl::BindFramebuffer(GL_FRAMEBUFFER, t.layer_fbo);
      if (samples_ > 1) {
        t.layer_color_ms.generate(ctx_.get());
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
        t.resolve_fbo.generate(ctx_.get());
        gl::BindFramebuffer(GL_FRAMEBUFFER, t.resolved());
        gl::FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t.layer_tex, 0);
        glu::check_framebuffer("stroke layer resolve");
        gl::Clear(GL_COLOR_BUFFER_BIT);
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

MeshOptions Paper::mesh_options(const BrushModel& model) const {
  return mesh_options_for(model, ppm_, scene_.mesh_mm, scene_.mesh_rings, scene_.mesh_around);
}

void Paper::check_deposit(const BrushFrame& brush, const Ink* ink) const {
  const int nodes = brush.nodes;
  if (nodes > kMaxNodes)
    throw std::invalid_argument("the renderer supports at most " + std::to_string(kMaxNodes - 1) + " spine segments");
  if (ink != nullptr) ink->validate(nodes);
  if (scene_.depletion && ink == nullptr)
    throw std::invalid_argument("this scene depletes ink: pass the brush's Ink to deposit()");
}

namespace {

// the fields' seed of tuft k: the scene's for the main tuft, offset for each child so that
// its streaks differ from its neighbours'
constexpr std::uint32_t kTuftSeedStride = 7919;


// every tuft's surface now (the main tuft first), and its sweep from its own last deposit when
// the stroke goes on (`same`) and that tuft was there (`was`: a child sprouted since, or even
// tufts in place of the main one, start one)
struct TuftSweeps {
  std::vector<SweepFrame> cur;
  std::vector<SweepPlan> plans;
  std::vector<bool> swept;
  bool contact = false;
};

TuftSweeps plan_tufts(const Paper& paper, const std::vector<TuftFrame>& tufts,
                      const std::vector<SweepFrame>& last, const std::vector<int>& was, bool same, double soak) {
  TuftSweeps t;
  const SceneFeatures& scene = paper.scene();
  for (std::size_t k = 0; k < tufts.size(); ++k) {
    const MeshOptions opt = mesh_options_for(tufts[k].segment_mm, tufts[k].belly_mm, paper.px_per_mm(),
                                             scene.mesh_mm, scene.mesh_rings, scene.mesh_around);
    t.cur.push_back(sweep_frame(tufts[k].sections, opt, soak));
    t.swept.push_back(same && k < last.size() && was[k] == tufts[k].tuft &&
                      last[k].position.size() == t.cur[k].position.size());
    t.plans.push_back(plan_sweep(t.swept[k] ? &last[k] : nullptr, t.cur[k], paper.px_per_mm(),
                                 paper.width_px(), paper.height_px(),
                                 paper.scene().split_map || paper.scene().dry_map || paper.scene().grain));
    t.contact = t.contact || t.plans[k].contact;
  }
  return t;
}

// the deposit's figures: the main tuft's blends and slides, the rectangle and travel of all
void plan_stats(const std::vector<SweepPlan>& plans, DepositStats& stats) {
  stats.substeps = plans[0].blends;
  stats.slides = std::max(plans[0].slides_prev, plans[0].slides_cur);
  for (const SweepPlan& p : plans) {
    stats.rect = unite(stats.rect, p.rect);
    stats.travel = std::max(stats.travel, p.travel);
  }
}

}  // namespace

DepositStats Paper::deposit(const BrushFrame& brush, const Ink* ink) {
  ctx_->make_current();
  check_deposit(brush, ink);
  DepositStats stats;
  const double excess = (scene_.soaked_tip && ink != nullptr) ? ink->excess : 0.0;
  const std::vector<TuftFrame>& tufts = brush.tufts;
  TuftSweeps t = plan_tufts(*this, tufts, last_, last_tufts_, stroke_open_ && last_brush_ == brush.brush,
                            scene_.soak_expand * excess);
  stats.contact = t.contact;
  if (!stats.contact) {
    // the brush left the paper: the stroke ends here
    end_stroke();
    return stats;
  }
  // continue the stroke from the last deposit, or start one; each tuft new to the stroke
  // starts its own stroke frame
  if (!t.swept[0]) {
    flush_stroke();
    stats.new_stroke = true;
    stroke_rect_ = {0, 0, 0, 0};
    wet_->clear();
  }
  start_frames(t.swept);
  set_stroke_color(ink);
  plan_stats(t.plans, stats);
  for (std::size_t k = 0; k < tufts.size(); ++k)
    if (t.plans[k].draws())
      deposit_tuft(t.plans[k], t.swept[k] ? last_[k] : t.cur[k], t.cur[k], t.swept[k], tufts[k], ink, excess, k,
                   stats);
  // the ink leaves the main tuft's nodes (spend_ink) by its pressure, whichever tuft drew
  if (stats.drawn && stats.pressure.empty()) stats.pressure = brush.pressure;
  stroke_open_ = true;
  last_brush_ = brush.brush;
  last_ = std::move(t.cur);
  last_tufts_.clear();
  for (const TuftFrame& f : tufts) last_tufts_.push_back(f.tuft);
  return stats;
}

void Paper::set_stroke_color(const Ink* ink) {
  // the alpha-only layer takes one colour per stroke: a new colour composites the layer first
  // (the sweep goes on from the last deposit)
  const auto color = ink != nullptr ? ink->ramp.front() : std::array<float, 4>{0, 0, 0, 1};
  if (max_blend_ && stroke_pending_ && color != stroke_color_) flush_stroke();
  stroke_color_ = color;
}

void Paper::deposit_tuft(const SweepPlan& plan, const SweepFrame& last, const SweepFrame& cur, bool swept,
                         const TuftFrame& tuft, const Ink* ink, double excess, std::size_t k, DepositStats& stats) {
  const double density = scene_.depletion ? ink_density(tuft) : 1.0;
  const double cover = draw_plan(plan, last, cur, tuft, ink, excess, density, k, stats);
  if (scene_.depletion) stats.deposited += wet_gain(tuft, swept, k, density * cover);
}

double Paper::wet_gain(const TuftFrame& tuft, bool swept, std::size_t k, double density) {
  // what tuft k gave the paper, at the density the footprint pass drew with (and the ink's alpha)
  return wet_->add(tuft, swept, k, density * stroke_color_[3]);
}

void Paper::start_frames(const std::vector<bool>& swept) {
  frames_.resize(std::max(frames_.size(), swept.size()));
  for (std::size_t k = 0; k < swept.size(); ++k) {
    if (!frames_[k]) frames_[k] = std::make_unique<StrokeFrame>();
    if (!swept[k]) frames_[k]->start();
  }
}

double Paper::draw_plan(const SweepPlan& plan, const SweepFrame& last, const SweepFrame& cur, const TuftFrame& tuft,
                      const Ink* ink, double excess, double density, std::size_t k, DepositStats& stats) {
  FootprintInputs in;
  in.density = density;
  in.pressure = node_pressure(tuft.sections);
  in.wet.resize(in.pressure.size());
  for (std::size_t i = 0; i < in.wet.size(); ++i) in.wet[i] = static_cast<float>(std::clamp(tuft.wetness[i], 0.0, 1.0));
  in.color = stroke_color_;
  in.ramp = (scene_.color_ramp && ink != nullptr) ? &ink->ramp : nullptr;
  in.soak = cur.soak;
  in.soak_shift = scene_.soak_shift * excess;
  in.maps = {split_tex_, dry_tex_, grain_tex_, ramp_tex_};
  in.seed = scene_.seed + static_cast<std::uint32_t>(k) * kTuftSeedStride;
  StrokeFrame& frame = *frames_[k];
  frame.advance(cur.placed, tuft.root.x(), tuft.root.y());
  in.frame = {static_cast<float>(frame.cx), static_cast<float>(frame.cy), static_cast<float>(frame.dx),
              static_cast<float>(frame.dy)};
  in.frame_s = frame.s;
  in.speed = frame.speed;
  program_->begin(plan, last, cur, in, ppm_);
  for_tiles(plan.rect, true, [&](PaperTile& t, int x, int y, int w, int h) {
    program_->draw(plan, LayerTile{t.layer_fbo, t.x0, t.y0, t.w, t.h, x, y, w, h});
  });
  program_->end();
  stats.drawn = true;
  const double cover = texture_coverage(scene_, in);
  if (k == 0) stats.pressure = std::move(in.pressure);
  stroke_rect_ = unite(stroke_rect_, plan.rect);
  stroke_pending_ = true;
  return cover;
}

void Paper::end_stroke() {
  if (!ctx_->closed()) {
    ctx_->make_current();
    flush_stroke();
  }
  stroke_open_ = false;
  last_brush_ = 0;
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
  stroke_pending_ = false;
  stroke_rect_ = {0, 0, 0, 0};
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
    wet_->clear();
    stroke_pending_ = false;
    stroke_open_ = false;
    last_brush_ = 0;
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
  last_brush_ = 0;
  stroke_rect_ = {0, 0, 0, 0};
  undo_pixels_.clear();
  wet_->clear();
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
      gl::BindFramebuffer(GL_FRAMEBUFFER, t.resolved());
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
