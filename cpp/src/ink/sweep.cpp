// A tuft's footprint swept between two frames, and the union of loops (Clipper).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "brushwork/ink_geometry.hpp"
#include "clip.hpp"

namespace brushwork {

namespace clip {

ClipperLib::Path to_path(const Eigen::Ref<const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>& loop) {
  ClipperLib::Path p;
  p.reserve(static_cast<std::size_t>(loop.rows()));
  for (Eigen::Index i = 0; i < loop.rows(); ++i)
    p.emplace_back(static_cast<ClipperLib::cInt>(std::llround(loop(i, 0) * kUnitsPerMm)),
                   static_cast<ClipperLib::cInt>(std::llround(loop(i, 1) * kUnitsPerMm)));
  return p;
}

ClipperLib::Paths to_paths(const Loops& loops) {
  ClipperLib::Paths out;
  out.reserve(loops.size());
  for (const auto& l : loops) {
    if (!l.allFinite()) throw std::invalid_argument("loops: coordinates must be finite");
    if (l.cwiseAbs().maxCoeff() > 1e9) throw std::invalid_argument("loops: coordinates beyond 1e9 mm");
    out.push_back(to_path(l));
  }
  return out;
}

Loops to_loops(const ClipperLib::Paths& paths) {
  Loops out;
  out.reserve(paths.size());
  for (const auto& p : paths) {
    if (p.size() < 3) continue;
    Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> m(static_cast<Eigen::Index>(p.size()), 2);
    for (std::size_t i = 0; i < p.size(); ++i)
      m.row(static_cast<Eigen::Index>(i)) << p[i].X / kUnitsPerMm, p[i].Y / kUnitsPerMm;
    out.push_back(std::move(m));
  }
  return out;
}

ClipperLib::Paths unite(const ClipperLib::Paths& paths) {
  ClipperLib::Clipper c;
  c.AddPaths(paths, ClipperLib::ptSubject, true);
  ClipperLib::Paths out;
  c.Execute(ClipperLib::ctUnion, out, ClipperLib::pftPositive, ClipperLib::pftPositive);
  return out;
}

namespace {

// paths offset by d mm, corners rounded
ClipperLib::Paths offset(const ClipperLib::Paths& paths, double d_mm) {
  ClipperLib::ClipperOffset co;
  co.ArcTolerance = 0.05 * std::abs(d_mm) * kUnitsPerMm;  // the rounded corners' chords stray d / 20 from the arc
  co.AddPaths(paths, ClipperLib::jtRound, ClipperLib::etClosedPolygon);
  ClipperLib::Paths out;
  co.Execute(out, d_mm * kUnitsPerMm);
  return out;
}

}  // namespace

ClipperLib::Paths clean(const ClipperLib::Paths& paths, double r_mm) {
  // closing (grow, shrink), then opening (shrink, grow)
  ClipperLib::Paths out = offset(offset(offset(paths, r_mm), -2.0 * r_mm), r_mm);
  // points within r / 5 of their neighbours' chord add nothing the tolerance can see
  ClipperLib::CleanPolygons(out, 0.2 * r_mm * kUnitsPerMm);
  return out;
}

}  // namespace clip

namespace {

using Rows3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

constexpr double kStill = 1e-9;  // mm: a footprint whose centroid moves less sweeps no band

// the part of two meshes of one topology that can meet the paper at some blend: the faces with a
// vertex below it in either (z is linear in t, so a vertex below at some t is below at an end),
// their vertices renumbered; blend() fills `mesh` with (1 - t) a + t b of those vertices
struct NearPart {
  std::vector<int> vertex;  // original index of each kept vertex
  SurfaceMesh mesh;         // the kept faces over the kept vertices
  Rows3 a, b;               // (kept, 3) the two ends

  void blend(double t) { mesh.vertices = (1.0 - t) * a + t * b; }
};

NearPart near_part(const SurfaceMesh& last, const SurfaceMesh& cur) {
  const Eigen::Index V = cur.vertices.rows();
  std::vector<char> low(static_cast<std::size_t>(V));
  for (Eigen::Index v = 0; v < V; ++v) low[v] = std::min(last.vertices(v, 2), cur.vertices(v, 2)) < 0.0;
  std::vector<int> index(static_cast<std::size_t>(V), -1);
  std::vector<int> faces;
  NearPart p;
  for (Eigen::Index f = 0; f < cur.faces.rows(); ++f) {
    const int* fv = &cur.faces(f, 0);
    if (!low[fv[0]] && !low[fv[1]] && !low[fv[2]]) continue;
    for (int e = 0; e < 3; ++e) {
      if (index[fv[e]] < 0) {
        index[fv[e]] = static_cast<int>(p.vertex.size());
        p.vertex.push_back(fv[e]);
      }
      faces.push_back(index[fv[e]]);
    }
  }
  const Eigen::Index K = static_cast<Eigen::Index>(p.vertex.size());
  p.a.resize(K, 3);
  p.b.resize(K, 3);
  for (Eigen::Index k = 0; k < K; ++k) {
    p.a.row(k) = last.vertices.row(p.vertex[k]);
    p.b.row(k) = cur.vertices.row(p.vertex[k]);
  }
  p.mesh.faces = Eigen::Map<Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      faces.data(), static_cast<Eigen::Index>(faces.size() / 3), 3);
  return p;
}

// blends needed between the two ends: each kept vertex's move on the paper departs from the
// mean move (a translation, which the slid band follows exactly) by at most 2 tol a blend, so a
// point of the outline strays at most tol from the chord the band takes
int blends_needed(const NearPart& p, const SweepTolerance& tol) {
  const Eigen::Index K = p.a.rows();
  if (K == 0) return 0;
  const Eigen::Matrix<double, Eigen::Dynamic, 2> d = (p.b - p.a).leftCols<2>();
  const Eigen::RowVector2d mean = d.colwise().mean();
  const double dev = (d.rowwise() - mean).rowwise().norm().maxCoeff();
  const int k = static_cast<int>(std::ceil(dev / (2.0 * tol.tol_mm)));
  return std::clamp(k, 1, tol.max_samples);
}

using LoopMat = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

// a closed polygon from its points, turned counter-clockwise
LoopMat ccw_polygon(const std::vector<Eigen::Vector2d>& pts) {
  LoopMat m(static_cast<Eigen::Index>(pts.size()), 2);
  for (std::size_t j = 0; j < pts.size(); ++j) m.row(static_cast<Eigen::Index>(j)) = pts[j].transpose();
  if (loops_area({m}) < 0.0) m.colwise().reverseInPlace();
  return m;
}

// the loop's points furthest right (first) and left (second) across a move along `dir` (unit)
std::pair<Eigen::Vector2d, Eigen::Vector2d> support(const LoopMat& L, const Eigen::Vector2d& dir) {
  const Eigen::Vector2d across(-dir.y(), dir.x());
  const Eigen::VectorXd s = L * across;
  Eigen::Index lo = 0, hi = 0;
  s.minCoeff(&lo);
  s.maxCoeff(&hi);
  return {L.row(lo).transpose(), L.row(hi).transpose()};
}

// the area centroid of one loop (mm), or its first point when it has no area
Eigen::Vector2d loop_centre(const LoopMat& L) {
  const FootprintSpan s = footprint_span({L}, 0.0);
  return s.valid ? s.centroid : Eigen::Vector2d(L.row(0).transpose());
}

// between two footprints of several loops: each loop of `a` and the loop of `b` whose centre is
// nearest its own, joined by the band of their support points across the move between them
void pair_bands(const Loops& a, const Loops& b, Loops& out) {
  if (b.empty()) return;
  std::vector<Eigen::Vector2d> cb;
  for (const auto& L : b) cb.push_back(loop_centre(L));
  for (const auto& L : a) {
    const Eigen::Vector2d ca = loop_centre(L);
    std::size_t j = 0;
    for (std::size_t i = 1; i < cb.size(); ++i)
      if ((cb[i] - ca).squaredNorm() < (cb[j] - ca).squaredNorm()) j = i;
    const Eigen::Vector2d move = cb[j] - ca;
    if (move.norm() <= kStill) continue;
    const auto [ra, la] = support(L, move.normalized());
    const auto [rb, lb] = support(b[j], move.normalized());
    out.push_back(ccw_polygon({ra, rb, lb, la}));
  }
}

// the band a sweep of one-loop footprints covers between its two ends, moving along `dir` (unit):
// the path of each footprint's rightmost point across the move, then back along the path of
// their leftmost points.  For a footprint that translates this, with the two ends, is the sweep
// exactly (the sides of a translated region are the paths of its support points); the blends'
// count keeps the motion close enough to a translation between two of them
void support_band(const std::vector<Loops>& loops, const Eigen::Vector2d& dir, Loops& out) {
  std::vector<Eigen::Vector2d> right, left;
  for (const Loops& ls : loops) {
    const auto [r, l] = support(ls.front(), dir);
    right.push_back(r);
    left.push_back(l);
  }
  std::vector<Eigen::Vector2d> pts(right);
  pts.insert(pts.end(), left.rbegin(), left.rend());
  out.push_back(ccw_polygon(pts));
}

}  // namespace

Loops swept_footprint(const SurfaceMesh& last, const SurfaceMesh& cur, const SweepTolerance& tol, int* samples) {
  if (last.vertices.rows() != cur.vertices.rows() || last.faces.rows() != cur.faces.rows())
    throw std::invalid_argument("swept_footprint: the two meshes differ in topology");
  if (!(tol.tol_mm > 0.0) || tol.max_samples < 1)
    throw std::invalid_argument("swept_footprint: tol_mm must be > 0 and max_samples >= 1");
  NearPart p = near_part(last, cur);
  const int K = blends_needed(p, tol);
  if (samples != nullptr) *samples = K;
  Loops out;
  if (K == 0) return out;
  // footprints at t = 0, 1/K, .., 1, each slid toward the next along its centroid's move
  std::vector<Loops> loops(K + 1);
  std::vector<FootprintSpan> spans(K + 1);
  for (int k = 0; k <= K; ++k) {
    p.blend(static_cast<double>(k) / K);
    loops[k] = footprint_loops(p.mesh);
    spans[k] = footprint_span(loops[k], 0.0);
  }
  // the two ends, and between them the support band of one-loop footprints, or (a footprint
  // of several loops, or none) every footprint and the bands of its runs facing its move
  out = loops[0];
  out.insert(out.end(), loops[K].begin(), loops[K].end());
  bool single = true;
  for (const Loops& l : loops) single = single && l.size() == 1;
  if (single) {
    const Eigen::Vector2d move = spans[K].centroid - spans[0].centroid;
    if (move.norm() > kStill) support_band(loops, move.normalized(), out);
    return out;
  }
  // several loops: each loop's band to the loop of the next footprint nearest it, and every
  // footprint whose count of loops differs from the last one's (a loop appears, splits or goes)
  for (int k = 0; k < K; ++k) {
    if (k > 0 && loops[k].size() != loops[k - 1].size()) out.insert(out.end(), loops[k].begin(), loops[k].end());
    pair_bands(loops[k], loops[k + 1], out);
  }
  return out;
}

Loops union_loops(const Loops& loops) { return clip::to_loops(clip::unite(clip::to_paths(loops))); }

}  // namespace brushwork
