// The paper whose ink is geometry: strokes as unioned contours (mm), rasterised on readback.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "../render/checks.hpp"
#include "../render/pixels.hpp"
#include "../render/wet_area.hpp"
#include "brushwork/ink_geometry.hpp"
#include "clip.hpp"

namespace brushwork {

namespace {

constexpr double kWetCellMm = 0.1;    // mm: the cells the spent ink is measured in (as a Paper's)
constexpr int kMaxPaperPx = 32768;    // px: the longest side of a paper
// the sweep mesh: as fine as this on the paper, up to these caps (sweep_surface's ring radii are
// smooth, so the outline's chords are what stays of the mesh: 0.004 mm on the small brush's belly)
constexpr double kMeshMm = 0.25;
constexpr int kMeshRings = 8, kMeshAround = 96;
constexpr double kResolutionFree = 1e6;  // px/mm handed to mesh_options_for: no pixel floor

constexpr double kCleanTol = 5.0;  // the strokes' clean-up radius, in sweep tolerances

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// the brush's surface as the sweep takes it: each ring moved out from its centre so that the
// polygon of A vertices has its section's area (as sweep_frame does for the footprint pass)
SurfaceMesh sweep_mesh(const TuftFrame& tuft, const MeshOptions& opt) {
  SurfaceMesh m = sweep_surface(tuft.sections, opt);
  const int A = opt.around;
  const int NR = static_cast<int>((m.vertices.rows() - 2) / A);
  const double k = std::sqrt(2.0 * 3.14159265358979323846 / (A * std::sin(2.0 * 3.14159265358979323846 / A)));
  for (int j = 0; j < NR; ++j) {
    auto ring = m.vertices.middleRows(static_cast<Eigen::Index>(j) * A, A);
    const Eigen::RowVector3d c = ring.colwise().mean();
    ring = (ring.rowwise() - c) * k;
    ring.rowwise() += c;
  }
  return m;
}

bool below_paper(const SurfaceMesh& m) { return m.vertices.rows() > 0 && m.vertices.col(2).minCoeff() < 0.0; }

}  // namespace

// a run of deposits at one density and their region.  Clipper's sweep line pays for every pair
// of edges it holds at once, so the region is built as a binary counter: each deposit's pieces
// are a run of level 0, and two runs of one level are unioned into one of the next.  A union then
// holds two regions of like size, and a stroke of n deposits costs O(n log n) edges, not the
// O(n^2) of uniting each deposit with the whole region so far.
struct Group {
  double density = 1.0;
  ClipperLib::Paths paths;                          // the region (unioned) when `runs` is empty
  std::vector<std::pair<int, ClipperLib::Paths>> runs;  // (level, region) not yet in `paths`
  void add(const Loops& loops) {
    runs.emplace_back(0, clip::to_paths(loops));
    while (runs.size() >= 2 && runs[runs.size() - 2].first == runs.back().first) {
      auto top = std::move(runs.back());
      runs.pop_back();
      auto& below = runs.back();
      below.second.insert(below.second.end(), top.second.begin(), top.second.end());
      below.second = clip::unite(below.second);
      ++below.first;
    }
  }
  // `paths` the union of everything added
  void compact() {
    for (auto& r : runs) paths.insert(paths.end(), r.second.begin(), r.second.end());
    runs.clear();
    paths = clip::unite(paths);
  }
};

struct VectorPaper::Stroke {
  std::array<float, 4> color{{0, 0, 0, 1}};
  std::vector<Group> groups;
};

struct VectorPaper::Layer {
  std::array<float, 4> color{{0, 0, 0, 1}};
  std::vector<Group> groups;  // unioned; the layer's ink is the densest group over a pixel
};

struct VectorPaper::Wet {
  WetLedger ledger{kWetCellMm};
  std::vector<float> cov, alpha;  // the rasteriser's planes, kept between readbacks (no page faults)
  // up to a 4096 px square paper's; a larger paper's planes go back after each readback
  void release_large() {
    constexpr std::size_t kKeep = std::size_t{4096} * 4096;
    for (auto* v : {&cov, &alpha})
      if (v->capacity() > kKeep) std::vector<float>().swap(*v);
  }
};

VectorPaper::VectorPaper(double width_mm, double height_mm, double px_per_mm, const SceneFeatures& scene,
                         const SweepTolerance& tol)
    : scene_(scene), tol_(tol), width_mm_(width_mm), height_mm_(height_mm), ppm_(px_per_mm),
      wet_(std::make_unique<Wet>()) {
  scene_.validate();
  if (scene_.split_map || scene_.dry_map || scene_.grain || scene_.soaked_tip || scene_.color_ramp)
    throw std::invalid_argument(
        "ink geometry: the scene uses a split, dry or grain map, a soaked tip or a colour ramp; those need the GL "
        "footprint pass (ink='gl')");
  if (!(tol_.tol_mm > 0.0) || tol_.max_samples < 1)
    throw std::invalid_argument("ink geometry: tol_mm must be > 0 and max_samples >= 1");
  // the pixel size a Paper of these millimetres has
  const auto [w, h] = checks::paper_pixels(width_mm, height_mm, px_per_mm, kMaxPaperPx);
  W_ = w;
  H_ = h;
}

VectorPaper::~VectorPaper() = default;

MeshOptions VectorPaper::mesh_options(const BrushModel& model) const {
  return mesh_options_for(model, kResolutionFree, kMeshMm, kMeshRings, kMeshAround);
}

void VectorPaper::check_deposit(const BrushFrame& brush, const Ink* ink) const {
  if (ink != nullptr) ink->validate(brush.nodes);
  if (scene_.depletion && ink == nullptr)
    throw std::invalid_argument("this scene depletes ink: pass the brush's Ink to deposit()");
}

void VectorPaper::open_stroke(const Ink* ink, bool starts, DepositStats& stats) {
  if (starts) {
    flush_stroke();
    stats.new_stroke = true;
    wet_->ledger.clear();
  }
  // one colour a stroke: a new colour starts another (as the alpha-only layer of a Paper does)
  const auto color = ink != nullptr ? ink->ramp.front() : std::array<float, 4>{0, 0, 0, 1};
  if (open_ && color != open_->color) flush_stroke();
  if (!open_) {
    open_ = std::make_unique<Stroke>();
    open_->color = color;
  }
  stroke_color_ = color;
}

void VectorPaper::deposit_tuft(const TuftFrame& tuft, const SurfaceMesh* last, const SurfaceMesh& cur, std::size_t k,
                               DepositStats& stats) {
  // the region swept since the last deposit (a still footprint when the tuft starts here), at
  // the density its wetness gives
  int samples = 0;
  const Loops region = swept_footprint(last != nullptr ? *last : cur, cur, tol_, &samples, last == nullptr);
  if (k == 0) stats.substeps = samples;
  const double density = scene_.depletion ? ink_density(tuft) : 1.0;
  if (!region.empty()) {
    if (open_->groups.empty() || open_->groups.back().density != density) open_->groups.push_back(Group{density, {}, {}});
    open_->groups.back().add(region);
    stats.drawn = true;
  }
  if (scene_.depletion) stats.deposited += wet_->ledger.add(tuft, last != nullptr, k, density * stroke_color_[3]);
}

DepositStats VectorPaper::deposit(const BrushFrame& brush, const Ink* ink) {
  check_deposit(brush, ink);
  const auto t0 = std::chrono::steady_clock::now();
  DepositStats stats;
  const std::vector<TuftFrame>& tufts = brush.tufts;
  std::vector<SurfaceMesh> cur;
  for (const TuftFrame& t : tufts) {
    cur.push_back(sweep_mesh(t, mesh_options_for(t.segment_mm, t.belly_mm, kResolutionFree, kMeshMm, kMeshRings,
                                                 kMeshAround)));
    stats.contact = stats.contact || below_paper(cur.back());
  }
  if (!stats.contact) {
    end_stroke();
    return stats;
  }
  // each tuft sweeps from its own last deposit while the stroke goes on and it was there
  const bool same = stroke_open_ && last_brush_ == brush.brush;
  auto last = [&](std::size_t k) -> const SurfaceMesh* {
    const bool was = same && k < last_.size() && last_tufts_[k] == tufts[k].tuft &&
                     last_[k].vertices.rows() == cur[k].vertices.rows();
    return was ? &last_[k] : nullptr;
  };
  open_stroke(ink, last(0) == nullptr, stats);
  for (std::size_t k = 0; k < tufts.size(); ++k) deposit_tuft(tufts[k], last(k), cur[k], k, stats);
  if (stats.drawn) stats.pressure = brush.pressure;
  stroke_open_ = true;
  last_brush_ = brush.brush;
  last_ = std::move(cur);
  last_tufts_.clear();
  for (const TuftFrame& t : tufts) last_tufts_.push_back(t.tuft);
  sweep_s_ += seconds_since(t0);
  return stats;
}

void VectorPaper::end_stroke() {
  flush_stroke();
  stroke_open_ = false;
  last_brush_ = 0;
}

void VectorPaper::flush_stroke() {
  if (!open_) return;
  if (!open_->groups.empty()) {
    // where a footprint's support point jumps from one blend or deposit to the next, the bands
    // and the footprints meet in slits and spikes a few hundredths of a mm thick: features the
    // brush does not make, which a closing and opening by kCleanTol tol take off (the corners
    // round to that radius, 0.25 px at 10 px/mm)
    for (Group& g : open_->groups) {
      g.compact();
      g.paths = clip::clean(g.paths, kCleanTol * tol_.tol_mm);
    }
    strokes_.push_back(std::move(*open_));
  }
  open_.reset();
}

bool VectorPaper::undo() {
  flush_stroke();
  if (strokes_.empty()) return false;
  strokes_.pop_back();
  stroke_open_ = false;
  last_brush_ = 0;
  wet_->ledger.clear();
  return true;
}

void VectorPaper::clear() {
  strokes_.clear();
  open_.reset();
  stroke_open_ = false;
  last_brush_ = 0;
  last_.clear();
  last_tufts_.clear();
  wet_->ledger.clear();
}

std::vector<VectorPaper::Layer> VectorPaper::layers() {
  // consecutive strokes of one colour at full density are one layer, their union; any other
  // stroke is a layer of its own
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<Layer> out;
  auto solid = [](const Stroke& s) { return s.groups.size() == 1 && s.groups[0].density >= 1.0; };
  bool open_solid = false;
  auto add = [&](const Stroke& s) {
    if (solid(s) && open_solid && out.back().color == s.color) {
      ClipperLib::Paths& p = out.back().groups[0].paths;
      p.insert(p.end(), s.groups[0].paths.begin(), s.groups[0].paths.end());
      return;
    }
    out.push_back(Layer{s.color, s.groups});
    open_solid = solid(s);
  };
  for (const Stroke& s : strokes_) add(s);
  if (open_ && !open_->groups.empty()) {
    for (Group& g : open_->groups) g.compact();
    add(*open_);
  }
  for (Layer& l : out)
    for (Group& g : l.groups) g.compact();
  union_s_ = seconds_since(t0);
  return out;
}

Loops VectorPaper::outlines() {
  ClipperLib::Paths all;
  for (const Layer& l : layers())
    for (const Group& g : l.groups) all.insert(all.end(), g.paths.begin(), g.paths.end());
  return clip::to_loops(clip::unite(all));
}

namespace {

// the pixels a group's region can cover: [x0, x1) x [y0, y1), y from the bottom, within W x H
std::array<int, 4> pixel_box(const ClipperLib::Paths& paths, double ppm, int W, int H) {
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (const auto& p : paths)
    for (const auto& q : p) {
      lo[0] = std::min(lo[0], static_cast<double>(q.X)), hi[0] = std::max(hi[0], static_cast<double>(q.X));
      lo[1] = std::min(lo[1], static_cast<double>(q.Y)), hi[1] = std::max(hi[1], static_cast<double>(q.Y));
    }
  const double k = ppm / clip::kUnitsPerMm;
  auto px = [&](double v, int n, bool up) {
    return std::clamp(static_cast<int>(up ? std::ceil(v * k) + 1 : std::floor(v * k) - 1), 0, n);
  };
  return {px(lo[0], W, false), px(hi[0], W, true), px(lo[1], H, false), px(hi[1], H, true)};
}

// the box of pixels [x0, x1) x [y0, y1) (y from the bottom) that any of the groups can cover;
// empty (x1 <= x0 or y1 <= y0) when none covers any
std::array<int, 4> groups_box(const std::vector<Group>& groups, double ppm, int W, int H) {
  std::array<int, 4> box{W, 0, H, 0};
  for (const Group& g : groups) {
    const auto [x0, x1, y0, y1] = pixel_box(g.paths, ppm, W, H);
    if (x1 <= x0 || y1 <= y0) continue;
    box = {std::min(box[0], x0), std::max(box[1], x1), std::min(box[2], y0), std::max(box[3], y1)};
  }
  return box;
}

// a layer's ink over the pixels of `box` ([x0, x1) x [y0, y1), y from the bottom), row by row
// from the box's top: the densest of its groups' coverage at each pixel, each group rasterised
// over its own box of pixels only (the loops moved by whole pixels, so the grid is the paper's;
// what lies left or right of the paper is clamped to its side as on the whole paper)
void layer_alpha(const std::vector<Group>& groups, double ppm, int W, int H, const std::array<int, 4>& box,
                 std::vector<float>& cov, std::vector<float>& alpha) {
  const int bw = box[1] - box[0], by1 = box[3];
  alpha.assign(static_cast<std::size_t>(std::max(bw, 0)) * std::max(box[3] - box[2], 0), 0.0f);
  for (const Group& g : groups) {
    const auto [x0, x1, y0, y1] = pixel_box(g.paths, ppm, W, H);
    if (x1 <= x0 || y1 <= y0) continue;
    Loops loops = clip::to_loops(g.paths);
    for (auto& L : loops) L.rowwise() -= Eigen::RowVector2d(x0 / ppm, y0 / ppm);
    const int w = x1 - x0, h = y1 - y0;
    cov.resize(static_cast<std::size_t>(w) * h);
    coverage(loops, ppm, w, h, cov.data());
    const float d = static_cast<float>(g.density);
    // the group's row r (0 at its top) is the layer box's row by1 - y1 + r
    for (int r = 0; r < h; ++r) {
      float* a = &alpha[static_cast<std::size_t>(by1 - y1 + r) * bw + (x0 - box[0])];
      const float* c = &cov[static_cast<std::size_t>(r) * w];
      for (int i = 0; i < w; ++i) a[i] = std::max(a[i], d * c[i]);
    }
  }
}

// one row of a single layer's premultiplied RGBA: its straight colour times its alpha
void layer_row(const std::array<float, 4>& color, const float* a, int W, float* row) {
  for (int x = 0; x < W; ++x) {
    const float s = a[x] * color[3];
    for (int c = 0; c < 3; ++c) row[4 * x + c] = color[c] * s;
    row[4 * x + 3] = s;
  }
}

}  // namespace

void VectorPaper::composite(const std::function<void(int row, const float* rgba, int x0, int x1)>& put) {
  // each layer's ink composited over the last, premultiplied: P = L + P (1 - L_a); one layer (a
  // paper of one ink) goes out row by row without the RGBA plane, worked over its box of pixels
  // only (the rest of the paper is clear)
  const std::vector<Layer> ls = layers();
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t N = static_cast<std::size_t>(W_) * H_;
  std::vector<float>&cov = wet_->cov, &alpha = wet_->alpha;
  std::vector<float> rgba, row(4 * static_cast<std::size_t>(W_), 0.0f), clear(row);
  if (ls.size() <= 1) {
    const std::array<int, 4> box = ls.empty() ? std::array<int, 4>{} : groups_box(ls[0].groups, ppm_, W_, H_);
    const int x0 = box[0], bw = box[1] - box[0], top = H_ - box[3];  // the box's first row from the top
    if (bw > 0 && box[3] > box[2]) layer_alpha(ls[0].groups, ppm_, W_, H_, box, cov, alpha);
    for (int y = 0; y < H_; ++y) {
      if (bw > 0 && y >= top && y < H_ - box[2]) {
        const float* a = &alpha[static_cast<std::size_t>(y - top) * bw];
        layer_row(ls[0].color, a, bw, &row[4 * static_cast<std::size_t>(x0)]);
        put(y, row.data(), x0, box[1]);
      } else {
        put(y, clear.data(), 0, 0);
      }
    }
    wet_->release_large();
    raster_s_ = seconds_since(t0);
    return;
  }
  rgba.assign(4 * N, 0.0f);
  for (const Layer& l : ls) {
    layer_alpha(l.groups, ppm_, W_, H_, {0, W_, 0, H_}, cov, alpha);
    for (std::size_t i = 0; i < N; ++i) {
      const float s = alpha[i] * l.color[3];
      float* P = &rgba[4 * i];
      for (int c = 0; c < 3; ++c) P[c] = l.color[c] * s + P[c] * (1.0f - s);
      P[3] = s + P[3] * (1.0f - s);
    }
  }
  for (int y = 0; y < H_; ++y) put(y, &rgba[4 * static_cast<std::size_t>(y) * W_], 0, W_);
  wet_->release_large();
  raster_s_ = seconds_since(t0);
}

void VectorPaper::read_ink(float* out) {
  composite([&](int y, const float* rgba, int, int) {
    float* dst = out + static_cast<std::size_t>(y) * W_;
    for (int x = 0; x < W_; ++x) dst[x] = rgba[4 * x + 3];
  });
}

void VectorPaper::read_rgba(float* out) {
  composite([&](int y, const float* rgba, int, int) {
    std::copy_n(rgba, 4 * W_, out + 4 * static_cast<std::size_t>(y) * W_);
  });
}

void VectorPaper::read_image(int bits, bool white, bool bgr, void* out) {
  if (bits != 8 && bits != 16) throw std::invalid_argument("bits = " + std::to_string(bits) + ": expected 8 or 16");
  const std::size_t pixel = (white ? 3 : 4) * (bits == 8 ? 1 : 2), px = static_cast<std::size_t>(W_) * pixel;
  // a clear row's pixels, converted once; each row converts only the pixels of its ink's span
  std::vector<std::uint8_t> clear(px);
  const std::vector<float> none(4 * static_cast<std::size_t>(W_), 0.0f);
  image_row_any(none.data(), clear.data(), W_, bits, white, bgr);
  composite([&](int y, const float* rgba, int x0, int x1) {
    auto* dst = static_cast<std::uint8_t*>(out) + static_cast<std::size_t>(y) * px;
    std::copy_n(clear.data(), x0 * pixel, dst);
    image_row_any(rgba + 4 * static_cast<std::size_t>(x0), dst + x0 * pixel, x1 - x0, bits, white, bgr);
    std::copy(clear.begin() + static_cast<std::ptrdiff_t>(x1 * pixel), clear.end(), dst + x1 * pixel);
  });
}

}  // namespace brushwork
