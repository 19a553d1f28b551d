// The sweep plan (seed "Ink depositing"): which faces the footprint pass draws between the last
// deposit and this one, how many blends, which parts slide, and the pixels touched.
#include "brushwork/sweep_plan.hpp"

#include <algorithm>
#include <cmath>

#include "render_mesh.hpp"

namespace brushwork {

PartCentre part_centre(const std::vector<double>& p) {
  PartCentre c;
  for (std::size_t v = 0; v < p.size() / 3; ++v) {
    const double z = p[3 * v + 2];
    if (z >= 0.0) continue;
    c.w -= z;
    c.x -= z * p[3 * v];
    c.y -= z * p[3 * v + 1];
  }
  return c;
}

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kFar = 1e300;       // mm: sentinel of an empty extent (min starts here, max at -kFar)
constexpr double kReachPx = 1.0;     // px: a face lower than this above the paper can reach it
                                     // (half a pixel of antialiasing above the paper included)
constexpr double kInnerPx = 3.0;     // px: a face this deep below the paper in both deposits is inner
                                     // (a band this deep is wider than a blend's step; see sort_faces)
constexpr double kMeshMinPx = 3.0;   // px: the render mesh's edges are no shorter on the paper
constexpr double kNeck = 0.5;        // fraction of the width a blend keeps without slides
constexpr int kNeckSamples = 8;      // the blend's width is checked at t = 1/8 .. 7/8
constexpr double kMinMovePx = 0.5;   // px: a footprint's centre moving less needs no slides
constexpr double kMinSpacingPx = 0.75;  // px: the closest sub-steps or slid copies are spaced
constexpr double kBlendPx = 0.9;     // px: the farthest apart blends are spaced (a plain deposit)
constexpr double kTexturedBlendPx = 2.5;  // px: the same for a deposit that draws the split, dry or grain map
constexpr double kSlidePx = 1.5;     // px: the farthest apart slid copies are spaced
constexpr int kMaxCopies = 4096;     // most blends, or slid copies of one part, in one deposit
constexpr int kRectMarginPx = 2;     // px added around the sweep's bounds (antialiasing, rounding)

// `pos` moved out from its ring centres `ctr` by the soaked tip's growth at s = uv.x:
// 1 + soak smoothstep((s - 0.5) / 0.5), as the footprint shader does; (V, 3) mm
void place(const std::vector<float>& pos, const std::vector<float>& ctr, const std::vector<float>& uv,
           double soak, std::vector<double>& out) {
  const int V = static_cast<int>(pos.size() / 3);
  out.resize(3 * static_cast<std::size_t>(V));
  for (int v = 0; v < V; ++v) {
    const double s = uv[2 * v];
    const double t = std::clamp((s - 0.5) / 0.5, 0.0, 1.0);
    const double grow = 1.0 + soak * t * t * (3.0 - 2.0 * t);
    for (int d = 0; d < 3; ++d) out[3 * v + d] = ctr[3 * v + d] + (pos[3 * v + d] - ctr[3 * v + d]) * grow;
  }
}

// The faces that can reach the paper at some point of the sweep, sorted
//
// The sweep's list puts first the faces near the paper, then the inner ones: wholly below
// it by more than kInnerPx in both deposits.  An inner face is inked all over at every blend
// (its z is a mix of negative values) and lies inside the footprint, whose outline runs
// through the faces near the paper (below the paper the surface does not fold: a section's
// widest points are at its centre's height, above the paper).  The union of the footprints
// over a continuous blend is the two end footprints and the band their outline sweeps, so the
// blends in between draw the near faces only and the last (t = 1) all of them (t = 0 is the
// last deposit's t = 1, drawn then).  The blends are discrete, though: between two of them the
// outline moves up to kBlendPx, and the near band must be wider than that on the paper or the
// footprint's inside shows through between the blends.  At the tuft's steep sides a band half
// a pixel deep is a fraction of a pixel wide, and on the inner side of a turn, where the
// blended footprint reaches past both ends, it left saw teeth a frame apart (a 35 mm arc at
// 10 px/mm, one sample a pixel: edge roughness 0.44 px; 0.22 with a band 3 px deep, the same as
// every face drawn at every blend, whose deposit takes ~8% longer: `brushwork bench batch`).
// A textured deposit spaces its blends wider (kTexturedBlendPx): where a flattened tuft's
// blended surface bulges past the outline of both ends, the deep faces the band now holds show
// that spacing as teeth 1-2 px deep along the side (the gallery's panel h).
// The slid copies draw all their faces: there the near band, steep at the tuft's sides, is
// thinner than the 1.5 px between copies, and the slid parts' inner faces alone filled 1-px
// lines along the stroke's edges.
struct FaceSets {
  std::vector<std::uint32_t> sweep;  // near faces, then inner ones (3 indices a face)
  std::size_t near = 0;              // indices of the near faces
  std::vector<std::uint32_t> prev;   // faces reaching the paper in the last deposit
  std::vector<std::uint32_t> cur;    // ... and in this one
  std::vector<char> used;            // (V) a vertex of some face of the sweep
};

FaceSets sort_faces(const SweepFrame& last, const SweepFrame& cur, const std::vector<double>& pp,
                    double px_per_mm) {
  const std::vector<double>& pc = cur.placed;
  const double zcut = kReachPx / px_per_mm, inner = kInnerPx / px_per_mm;
  FaceSets fs;
  std::vector<std::uint32_t> inner_all;
  for (auto* list : {&fs.sweep, &fs.prev, &fs.cur, &inner_all}) list->reserve(cur.faces.size());
  fs.used.assign(cur.vertices(), 0);
  auto zlo = [](const std::vector<double>& p, const std::uint32_t* fv) {
    return std::min({p[3 * fv[0] + 2], p[3 * fv[1] + 2], p[3 * fv[2] + 2]});
  };
  auto zhi = [](const std::vector<double>& p, const std::uint32_t* fv) {
    return std::max({p[3 * fv[0] + 2], p[3 * fv[1] + 2], p[3 * fv[2] + 2]});
  };
  for (std::size_t f = 0; f < cur.faces.size(); f += 3) {
    const std::uint32_t* fv = &cur.faces[f];
    const double lo_cur = zlo(pc, fv), lo_prev = zlo(pp, fv);
    if (std::min(lo_cur, lo_prev) >= zcut) continue;  // (most of the tuft is above: those faces end here)
    double ring_lo = kFar;
    for (int e = 0; e < 3; ++e)
      ring_lo = std::min({ring_lo, static_cast<double>(cur.center[3 * fv[e] + 2]),
                          static_cast<double>(last.center[3 * fv[e] + 2])});
    for (int e = 0; e < 3; ++e) fs.used[fv[e]] = 1;
    // (the premise above holds for a ring whose centre is above the paper; one whose centre
    // is below it has its widest points there too, and its faces can carry the outline, so
    // they stay near.  Spread sections rest their centres on the paper (Brush::sections),
    // but a ring's centre is the mean of its vertices, off the spine where a+ != a-, and the
    // apex is its own centre: without this, 永和九年 at 1024 px without depletion differs on
    // 3,851 px, saw teeth a frame apart along the edges)
    const bool inner_face = std::max(zhi(pc, fv), zhi(pp, fv)) < -inner && ring_lo > -inner;
    std::vector<std::uint32_t>& sweep = inner_face ? inner_all : fs.sweep;
    sweep.insert(sweep.end(), fv, fv + 3);
    if (lo_prev < zcut) fs.prev.insert(fs.prev.end(), fv, fv + 3);
    if (lo_cur < zcut) fs.cur.insert(fs.cur.end(), fv, fv + 3);
  }
  // (near faces first, then the inner ones: a draw of the first `near` indices is the band)
  fs.near = fs.sweep.size();
  fs.sweep.insert(fs.sweep.end(), inner_all.begin(), inner_all.end());
  return fs;
}

// Widths across the move of the footprint's centre (mm) of the surface blended between the two
// deposits: the extent, across the move, of the blended near faces' vertices below the paper
// and of the points where their edges cross it (the inner faces lie inside that outline; a
// lifted blend has no width).
//
// (Each t blends only what can add to the width: the near faces' vertices below the paper at
// either end, and their edges whose two ends can lie on the two sides of it at some t.  A blend
// (1 - t) a + t b of two depths of one sign keeps that sign, so a vertex above the paper in
// both deposits is above it at every t, and an edge whose ends stay on one side never crosses:
// the points added, and so the width, are those of all the near faces'.  Listed once; each
// directed edge as often as the faces have it.)
class BlendWidth {
 public:
  BlendWidth(const std::vector<double>& pp, const std::vector<double>& pc, const FaceSets& fs, double ux,
             double uy)
      : pp_(pp), pc_(pc), ux_(ux), uy_(uy) {
    const std::size_t V = pc.size() / 3;
    bl_.resize(3 * V);
    seen_.assign(V, 0);
    for (std::size_t f = 0; f < fs.near; f += 3)
      for (int e = 0; e < 3; ++e) {
        const std::uint32_t a = fs.sweep[f + e], b = fs.sweep[f + (e + 1) % 3];
        if ((below(a) && above(b)) || (below(b) && above(a))) cross_e_.push_back({a, b}), keep(a), keep(b);
      }
    std::vector<char> dipped(V, 0);
    for (std::size_t f = 0; f < fs.near; ++f) {
      const std::uint32_t v = fs.sweep[f];
      if (!dipped[v] && below(v)) dipped[v] = 1, dip_v_.push_back(static_cast<int>(v)), keep(v);
    }
  }

  // the width at t in [0, 1] (0: the last deposit, 1: this one), mm
  double at(double t) {
    for (const int v : blend_v_)
      for (int d = 0; d < 3; ++d) bl_[3 * v + d] = (1.0 - t) * pp_[3 * v + d] + t * pc_[3 * v + d];
    lo_ = kFar, hi_ = -kFar;
    depth_ = 0.0;
    for (const int v : dip_v_)
      if (bl_[3 * v + 2] < 0.0) add(bl_[3 * v], bl_[3 * v + 1]), depth_ -= bl_[3 * v + 2];
    for (const auto& e : cross_e_) {
      const double* a = &bl_[3 * static_cast<std::size_t>(e[0])];
      const double* b = &bl_[3 * static_cast<std::size_t>(e[1])];
      if ((a[2] < 0.0) != (b[2] < 0.0)) {
        const double u = a[2] / (a[2] - b[2]);
        add(a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1]));
      }
    }
    return hi_ >= lo_ ? hi_ - lo_ : 0.0;
  }
  // mm: the summed depth below the paper of the last at()'s dipped vertices
  double depth() const { return depth_; }

 private:
  bool below(std::uint32_t v) const { return pp_[3 * v + 2] < 0.0 || pc_[3 * v + 2] < 0.0; }
  bool above(std::uint32_t v) const { return pp_[3 * v + 2] >= 0.0 || pc_[3 * v + 2] >= 0.0; }
  void keep(std::uint32_t v) {
    if (!seen_[v]) seen_[v] = 1, blend_v_.push_back(static_cast<int>(v));
  }
  void add(double x, double y) {
    const double b = -uy_ * x + ux_ * y;
    lo_ = std::min(lo_, b), hi_ = std::max(hi_, b);
  }
  const std::vector<double>& pp_;
  const std::vector<double>& pc_;
  double ux_, uy_;                   // unit vector along the move
  std::vector<int> dip_v_, blend_v_;
  std::vector<std::array<std::uint32_t, 2>> cross_e_;
  std::vector<char> seen_;
  std::vector<double> bl_;           // (V, 3) mm, the blend at t of the vertices in blend_v_
  double lo_ = kFar, hi_ = -kFar;    // mm across the move
  double depth_ = 0.0;               // mm, summed depth of the blend's dipped vertices
};

// The slides are needed only where the blend breaks: where one end's part is much narrower than
// the other's (a pressed blob and a thin trailing tip), or the surface blended between the two
// deposits lifts off the paper or pinches to a neck on the way: widths at t = 0 and 1, and at
// t = 1/8 .. 7/8 against the narrower end's, and the same for the summed depth of the surface
// below the paper (a blend that keeps its width across but rises toward the paper along the
// move, a pressed belly blended into a dragged one, thins to a neck that the width misses).  A blend that keeps at least kNeck of the width
// leaves an unbroken band by itself: its copies are spaced no farther apart than this frame's
// part is wide.  A centre that moves under half a pixel needs no slides.  Returns the shift
// (mm), zero when the parts do not slide.
std::array<double, 2> slide_shift(const std::vector<double>& pp, const std::vector<double>& pc,
                                  const FaceSets& fs, double px_per_mm) {
  const PartCentre p = part_centre(pp), c = part_centre(pc);
  if (!(p.w > 0.0 && c.w > 0.0)) return {0.0, 0.0};
  const double move_x = c.x / c.w - p.x / p.w, move_y = c.y / c.w - p.y / p.w;
  const double move_mm = std::hypot(move_x, move_y);
  if (!(move_mm * px_per_mm > kMinMovePx)) return {0.0, 0.0};
  BlendWidth width(pp, pc, fs, move_x / move_mm, move_y / move_mm);
  const double w0 = width.at(0.0), d0 = width.depth(), w1 = width.at(1.0), d1 = width.depth();
  const double ends = std::min(w0, w1), deep = std::min(d0, d1);
  bool both = ends < kNeck * std::max(w0, w1);
  for (int k = 1; k < kNeckSamples && !both; ++k)
    both = width.at(k / static_cast<double>(kNeckSamples)) < kNeck * ends || width.depth() < kNeck * deep;
  return both ? std::array<double, 2>{move_x, move_y} : std::array<double, 2>{0.0, 0.0};
}

// a part's extent along the shift and across it (mm): min, max along; min, max across
std::array<double, 4> part_extent(const std::vector<double>& p, double shift_x, double shift_y) {
  std::array<double, 4> e{{kFar, -kFar, kFar, -kFar}};
  const double len = std::hypot(shift_x, shift_y), ux = shift_x / len, uy = shift_y / len;
  for (std::size_t v = 0; v < p.size() / 3; ++v) {
    if (p[3 * v + 2] >= 0.0) continue;
    const double x = p[3 * v], y = p[3 * v + 1];
    const double a = ux * x + uy * y, b = -uy * x + ux * y;
    e[0] = std::min(e[0], a), e[1] = std::max(e[1], a), e[2] = std::min(e[2], b), e[3] = std::max(e[3], b);
  }
  return e;
}

// bounds (mm) of the sweep's vertices at both ends, of this deposit's part within reach of the
// paper, and the largest move of a vertex (mm)
struct SweepBounds {
  std::array<double, 4> all{{kFar, kFar, -kFar, -kFar}};  // x0, y0, x1, y1
  std::array<double, 4> cur{{kFar, kFar, -kFar, -kFar}};  // x0, y0, x1, y1
  double travel = 0.0;
};

SweepBounds sweep_bounds(const std::vector<double>& pp, const std::vector<double>& pc,
                         const std::vector<char>& used, double zcut) {
  SweepBounds s;
  auto& b = s.all;
  auto& c = s.cur;
  for (std::size_t v = 0; v < used.size(); ++v) {
    if (!used[v]) continue;
    const double x = pc[3 * v], y = pc[3 * v + 1];
    const double px = pp[3 * v], py = pp[3 * v + 1];
    b[0] = std::min({b[0], x, px});
    b[1] = std::min({b[1], y, py});
    b[2] = std::max({b[2], x, px});
    b[3] = std::max({b[3], y, py});
    if (pc[3 * v + 2] < zcut) {
      c[0] = std::min(c[0], x);
      c[1] = std::min(c[1], y);
      c[2] = std::max(c[2], x);
      c[3] = std::max(c[3], y);
    }
    s.travel = std::max(s.travel, std::hypot(x - px, y - py));
  }
  return s;
}

// the pixels of bounds `b` (mm) grown by `pad` mm and kRectMarginPx, clipped to the paper
PixelRect pixel_rect(const std::array<double, 4>& b, double pad, double px_per_mm, int W, int H) {
  const PixelRect r{{std::max(static_cast<int>(std::floor((b[0] - pad) * px_per_mm)) - kRectMarginPx, 0),
                     std::max(static_cast<int>(std::floor((b[1] - pad) * px_per_mm)) - kRectMarginPx, 0),
                     std::min(static_cast<int>(std::ceil((b[2] + pad) * px_per_mm)) + kRectMarginPx, W),
                     std::min(static_cast<int>(std::ceil((b[3] + pad) * px_per_mm)) + kRectMarginPx, H)}};
  if (r[2] <= r[0] || r[3] <= r[1]) return {{0, 0, 0, 0}};
  return r;
}

// Sub-steps of the sweep: close enough that consecutive footprints overlap and the scallops
// between them stay under a quarter pixel (a disc of radius r spaced d apart leaves scallops
// d^2 / 8r deep).  Spacing in px for a part whose smaller bounding side is `side_mm`: at most
// its radius, so the copies overlap, and at most sqrt(2 r) for quarter-pixel scallops; never
// under kMinSpacingPx.
double spacing_px(double side_mm, double px_per_mm) {
  const double r_px = 0.5 * std::max(0.0, side_mm) * px_per_mm;
  return std::max(kMinSpacingPx, std::min(r_px, std::sqrt(2.0 * r_px)));
}

// copies a part of extent `ext` (part_extent) needs to slide `shift_px` px: spaced by the
// rule above from its smaller side, at most kSlidePx apart (a thin part, under ~2 px, still
// gets a copy every 0.75 px and leaves a band, a pressed blob one every 1.5 px; wider spacing,
// up to the 7 px the scallop rule allows a 50 px blob, breaks thin necks between a pressed
// entry and a fast drag: the 1-px anti-aliased rim of each copy carries the band there)
int slide_copies(const std::array<double, 4>& ext, double shift_px, double px_per_mm) {
  const double side = std::min(ext[1] - ext[0], ext[3] - ext[2]);
  return std::clamp(static_cast<int>(std::ceil(shift_px / std::min(kSlidePx, spacing_px(side, px_per_mm)))), 1,
                    kMaxCopies);
}

// the counts of `plan`: blends, slides and the pixel rectangle from the faces `fs`
void count_copies(SweepPlan& plan, const std::vector<double>& pp, const std::vector<double>& pc,
                  const FaceSets& fs, double px_per_mm, int W, int H, bool textured) {
  const std::array<double, 2> shift = slide_shift(pp, pc, fs, px_per_mm);
  const bool slides = shift[0] != 0.0 || shift[1] != 0.0;
  plan.shift_x = shift[0], plan.shift_y = shift[1];
  const SweepBounds b = sweep_bounds(pp, pc, fs.used, kReachPx / px_per_mm);
  plan.travel = b.travel;
  // (the slid surfaces reach at most |shift| beyond the two surfaces' bounds)
  const double shift_mm = std::hypot(shift[0], shift[1]);
  plan.rect = pixel_rect(b.all, shift_mm, px_per_mm, W, H);
  // the blends' spacing: by the scallop rule from this part's smaller side, and at most
  // kBlendPx: the footprint is no disc but a rounded polygon, and a corner moved in steps of d
  // leaves a staircase up to d/2 deep along an edge slanted to the move (with the disc rule
  // alone, 6 px steps on a 45-degree stroke left 3 px saw teeth at 1024 px), and its widest
  // point a ripple of period d along the stroke's sides: copies 2.5 px apart ink the rim pixels
  // of a straight stroke one column in two, a 1-px comb after the mask's 0.5 threshold; under a
  // pixel every column along a side meets a copy's widest point and the sides stay straight
  // (`bench glyphs` at 512 px, excess edge roughness: 0.105 px, with 2.5 px 0.125 px), for
  // ~40% more CPU a kai character at 1024 px.  A textured deposit keeps
  // kTexturedBlendPx: each copy takes its maps' coverage and the densest wins, so denser copies
  // fill the dry streaks and the grain, and the maps break its edges anyway
  const double cap = textured ? kTexturedBlendPx : kBlendPx;
  const double spacing = std::min(cap, spacing_px(std::min(b.cur[2] - b.cur[0], b.cur[3] - b.cur[1]), px_per_mm));
  plan.blends = plan.continues
                    ? std::clamp(static_cast<int>(std::ceil(b.travel * px_per_mm / spacing)), 1, kMaxCopies)
                    : 1;
  if (!slides) return;
  plan.slides_prev = slide_copies(part_extent(pp, shift[0], shift[1]), shift_mm * px_per_mm, px_per_mm);
  plan.slides_cur = slide_copies(part_extent(pc, shift[0], shift[1]), shift_mm * px_per_mm, px_per_mm);
}

}  // namespace

MeshOptions mesh_options_for(const BrushModel& model, double px_per_mm, double mesh_mm, int rings, int around) {
  return mesh_options_for(model.segment_lengths().maxCoeff(), model.belly_radius, px_per_mm, mesh_mm, rings, around);
}

MeshOptions mesh_options_for(double segment_mm, double belly_mm, double px_per_mm, double mesh_mm, int rings,
                             int around) {
  // a software rasteriser pays per triangle more than per pixel: a footprint drawn from 48 x 6
  // rings' 3-4 px triangles costs ~3x what 6 px ones do.  So the mesh is made only as fine as
  // mesh_mm: the longest spine segment and the belly's circumference 2 pi r (the widest ring,
  // unpressed) over mesh_mm, around rounded up to a multiple of 4.  The chords of a ring of
  // radius r with A vertices lie up to r pi^2 / (2 A^2) inside it (0.02 mm for the small
  // brush's belly at 0.6 mm); sweep_frame() moves the vertices out so that each ring keeps its
  // section's area.  The choice is made in millimetres, not pixels: a mesh that coarsened with
  // the output would draw a different surface at each size (at 512 px per 100 mm the small
  // brush's ring would have 12 vertices, at 2048 px 48, and the strokes' sides move by a
  // tenth of a pixel between the two).  Only on paper coarser than 3 px to mesh_mm (5 px/mm at
  // the default, 512 px for a 100 mm em) does the mesh coarsen, its edges kept at kMeshMinPx:
  // triangles under 3 px add nothing a pixel shows there, and cost a batch of 256 px
  // characters a fifth of its speed (2 jobs, single-threaded llvmpipe).
  // (A brush keeps its mesh for a whole stroke: the sweep pairs last and this deposit's
  // vertices, so the choice depends on nothing that changes from frame to frame.)
  MeshOptions opt;
  opt.rings_per_segment = rings;
  opt.around = around;
  if (mesh_mm > 0.0) {
    mesh_mm = std::max(mesh_mm, kMeshMinPx / px_per_mm);
    const double ring_mm = 2.0 * kPi * belly_mm;
    opt.rings_per_segment = std::clamp(static_cast<int>(std::ceil(segment_mm / mesh_mm)), 1, rings);
    opt.around = std::clamp(4 * static_cast<int>(std::ceil(ring_mm / mesh_mm / 4.0)), 8, around);
  }
  return opt;
}

SweepFrame sweep_frame(const std::vector<Section>& sections, const MeshOptions& opt, double soak) {
  RenderMesh m = build_render_mesh(sections, opt, false);
  // a ring of A vertices is a polygon inscribed in its section: its area falls short by the
  // factor A sin(2 pi / A) / (2 pi) (1.1% at A = 24), and so would the ink.  Each vertex is
  // moved out from its ring's centre by the square root of the inverse, so that the polygon
  // has its section's area (vertices a little outside the surface, chord middles a little
  // inside)
  const double A = opt.around, k = std::sqrt(2.0 * kPi / (A * std::sin(2.0 * kPi / A)));
  for (std::size_t i = 0; i < m.position.size(); ++i)
    m.position[i] = static_cast<float>(m.center[i] + k * (m.position[i] - m.center[i]));
  SweepFrame f;
  f.position = std::move(m.position);
  f.center = std::move(m.center);
  f.uv = std::move(m.uv);
  f.faces = std::move(m.faces);
  f.soak = soak;
  place(f.position, f.center, f.uv, soak, f.placed);
  return f;
}

SweepPlan plan_sweep(const SweepFrame* last, const SweepFrame& cur, double px_per_mm, int width_px,
                     int height_px, bool textured) {
  SweepPlan plan;
  const std::vector<double>& pc = cur.placed;
  double zmin = kFar;
  for (std::size_t v = 0; v < pc.size() / 3; ++v) zmin = std::min(zmin, pc[3 * v + 2]);
  plan.contact = zmin < 0.0;
  if (!plan.contact) return plan;  // the brush left the paper
  plan.continues = last != nullptr;
  const SweepFrame& from = last != nullptr ? *last : cur;
  // the last deposit's surface placed with this one's growth: the copy kept from then unless
  // the soaked tip drained since
  std::vector<double> replaced;
  if (from.soak != cur.soak || from.placed.size() != pc.size()) place(from.position, from.center, cur.uv, cur.soak, replaced);
  const std::vector<double>& pp = replaced.empty() ? from.placed : replaced;

  FaceSets fs = sort_faces(from, cur, pp, px_per_mm);
  count_copies(plan, pp, pc, fs, px_per_mm, width_px, height_px, textured);
  // the index runs: the sweep's faces, then the slid parts' (see SweepPlan::indices)
  plan.near = fs.near;
  plan.all = fs.sweep.size();
  plan.prev = plan.slides_prev > 0 ? fs.prev.size() : 0;
  plan.cur = plan.slides_cur > 0 ? fs.cur.size() : 0;
  plan.indices = std::move(fs.sweep);
  plan.indices.insert(plan.indices.end(), fs.prev.begin(), fs.prev.begin() + plan.prev);
  plan.indices.insert(plan.indices.end(), fs.cur.begin(), fs.cur.begin() + plan.cur);
  return plan;
}

}  // namespace brushwork
