// A tuft's footprint swept between two frames, and the union of loops (Clipper).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
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
  std::vector<double> sa, sb, s;  // the vertex normals' z at the two ends, and at the blend

  void blend(double t) {
    mesh.vertices = (1.0 - t) * a + t * b;
    s.resize(sa.size());
    for (std::size_t v = 0; v < s.size(); ++v) s[v] = (1.0 - t) * sa[v] + t * sb[v];
  }
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
  // each end's vertex normals, once: a blend takes theirs with its vertices
  p.mesh.vertices = p.a;
  p.sa = vertex_normal_z(p.mesh);
  p.mesh.vertices = p.b;
  p.sb = vertex_normal_z(p.mesh);
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
// count keeps the motion close enough to a translation between two of them.  Where the footprint
// turns back along `dir` the band would fold over itself and its two lobes wind against each other
// (the union keeps only the counter-clockwise one), so the band is cut there into pieces that
// each move one way, and the footprint where it turns (its cap, which no band covers) is kept
void support_band(const std::vector<Loops>& loops, const Eigen::Vector2d& dir, double tol_mm, Loops& out) {
  std::vector<Eigen::Vector2d> right, left;
  for (const Loops& ls : loops) {
    const auto [r, l] = support(ls.front(), dir);
    right.push_back(r);
    left.push_back(l);
  }
  // the sense in which the quad between blends k and k + 1 winds: + forward along dir, - back; a
  // step of less than tol either way keeps the sense before it (its fold is within tol)
  auto step = [&](std::size_t k) { return 0.5 * (right[k + 1] + left[k + 1] - right[k] - left[k]).dot(dir); };
  auto piece = [&](std::size_t a, std::size_t b) {  // the band from blend a to blend b
    std::vector<Eigen::Vector2d> pts(right.begin() + a, right.begin() + b + 1);
    pts.insert(pts.end(), left.rbegin() + (left.size() - 1 - b), left.rend() - a);
    out.push_back(ccw_polygon(pts));
  };
  std::size_t a = 0;
  int sense = 0;
  for (std::size_t k = 0; k + 1 < loops.size(); ++k) {
    const double s = step(k);
    const int now = s > tol_mm ? 1 : s < -tol_mm ? -1 : sense;
    if (sense != 0 && now != sense) {
      piece(a, k);
      out.push_back(loops[k].front());
      a = k;
    }
    sense = now;
  }
  piece(a, loops.size() - 1);
}

// the points of a closed loop a Douglas-Peucker pass keeps: every dropped point lies within eps
// of the chord that replaces it.  The loop is split at its first point and the point furthest
// from it, and each half simplified
LoopMat simplify_loop(const LoopMat& L, double eps) {
  const Eigen::Index n = L.rows();
  if (n <= 4) return L;
  std::vector<char> keep(static_cast<std::size_t>(n) + 1, 0);
  Eigen::Index far = 0;
  (L.rowwise() - L.row(0)).rowwise().squaredNorm().maxCoeff(&far);
  auto point = [&](Eigen::Index i) { return Eigen::Vector2d(L.row(i % n).transpose()); };
  std::vector<std::pair<Eigen::Index, Eigen::Index>> stack{{0, far}, {far, n}};
  keep[0] = keep[far] = 1;
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    const Eigen::Vector2d a = point(i), ab = point(j) - a;
    const double len = ab.norm();
    double worst = -1.0;
    Eigen::Index w = -1;
    for (Eigen::Index k = i + 1; k < j; ++k) {
      const Eigen::Vector2d ak = point(k) - a;
      const double d = len > 0.0 ? std::abs(ab.x() * ak.y() - ab.y() * ak.x()) / len : ak.norm();
      if (d > worst) worst = d, w = k;
    }
    if (w < 0 || worst <= eps) continue;
    keep[w] = 1;
    stack.push_back({i, w});
    stack.push_back({w, j});
  }
  std::vector<Eigen::Index> idx;
  for (Eigen::Index k = 0; k < n; ++k)
    if (keep[k]) idx.push_back(k);
  if (idx.size() < 3) return L;
  LoopMat out(static_cast<Eigen::Index>(idx.size()), 2);
  for (std::size_t k = 0; k < idx.size(); ++k) out.row(static_cast<Eigen::Index>(k)) = L.row(idx[k]);
  return out;
}

Loops simplified(Loops loops, double eps) {
  for (auto& L : loops) L = simplify_loop(L, eps);
  return loops;
}

// the support function of one loop in `dirs` (unit): how far it reaches along each
std::array<double, 8> reach(const LoopMat& L, const std::array<Eigen::Vector2d, 8>& dirs) {
  std::array<double, 8> h{};
  for (std::size_t d = 0; d < dirs.size(); ++d) h[d] = (L * dirs[d]).maxCoeff();
  return h;
}

// one blend of the adaptive sweep: its t, its footprint (one loop or none) and the loop's reach
struct Blend {
  double t;
  Loops loops;
  std::array<double, 8> h{};
};

// how far the midpoint blend m departs from the region the band between a and b gives, by its
// reach in eight directions (infinite where a loop appears or goes between them, zero where none
// of the three has a footprint)
double departure(const Blend& a, const Blend& m, const Blend& b) {
  if (a.loops.size() != m.loops.size() || m.loops.size() != b.loops.size())
    return std::numeric_limits<double>::infinity();
  if (m.loops.empty()) return 0.0;
  // across the move (directions 2 and 6) the band's sides are chords of the support points'
  // paths: m's support must lie within tol of the chord, either way; in the other directions the
  // region reaches as far as the further of a and b, which m must not pass by more than tol
  double err = 0.0;
  for (std::size_t d = 0; d < m.h.size(); ++d) {
    const double gap = d % 4 == 2 ? std::abs(m.h[d] - 0.5 * (a.h[d] + b.h[d])) : m.h[d] - std::max(a.h[d], b.h[d]);
    err = std::max(err, gap);
  }
  return err;
}

// the footprints of a sweep at the blends an error estimate asks for: between two blends a and
// b the midpoint m is taken, and the interval is split again unless m departs from the linear
// sweep between a and b by at most tol (then the support band between a and b follows m's sides
// to within tol, and m is kept as a blend of it).  No interval is split finer than 1 / K (K the
// bound of blends_needed), so where a footprint appears or goes the blends close in on that t.
// Empty when a footprint on the way is of several loops.
std::vector<Blend> adaptive_blends(NearPart& p, Loops l0, Loops l1, int K, const SweepTolerance& tol) {
  // eight directions, two of them across the move between the ends where both have a footprint
  double a0 = 0.0;
  if (l0.size() == 1 && l1.size() == 1) {
    const Eigen::Vector2d move = loop_centre(l1.front()) - loop_centre(l0.front());
    if (move.norm() > kStill) a0 = std::atan2(move.y(), move.x());
  }
  std::array<Eigen::Vector2d, 8> dirs;
  for (int d = 0; d < 8; ++d) {
    const double a = a0 + d * 3.14159265358979323846 / 4.0;
    dirs[d] = Eigen::Vector2d(std::cos(a), std::sin(a));
  }
  auto make = [&](double t, Loops loops) {
    Blend b{t, std::move(loops), {}};
    b.h.fill(-std::numeric_limits<double>::infinity());
    for (const auto& L : b.loops) {
      const auto h = reach(L, dirs);
      for (std::size_t d = 0; d < h.size(); ++d) b.h[d] = std::max(b.h[d], h[d]);
    }
    return b;
  };
  std::vector<Blend> done{make(0.0, std::move(l0))}, todo{make(1.0, std::move(l1))};
  // todo: a stack of the blends right of done.back(), the nearest on top
  while (!todo.empty()) {
    if ((todo.back().t - done.back().t) * K > 1.0 + 1e-9) {
      const double tm = 0.5 * (done.back().t + todo.back().t);
      p.blend(tm);
      Blend m = make(tm, footprint_projection(p.mesh, p.s));
      const bool split = departure(done.back(), m, todo.back()) > tol.tol_mm;
      (split ? todo : done).push_back(std::move(m));
      if (split) continue;
    }
    done.push_back(std::move(todo.back()));
    todo.pop_back();
  }
  return done;
}

// the region between the blends, the two ends left out: each run of one-loop footprints, its
// first and last footprints (where it starts or ends on the way) and the support band across
// its move; between blends of several loops, each loop's band to the nearest loop of the next,
// and every such footprint on the way
void blend_bands(const std::vector<Blend>& bs, double tol_mm, Loops& out) {
  const std::size_t n = bs.size();
  for (std::size_t i = 0; i < n;) {
    if (bs[i].loops.size() != 1) {
      if (i > 0 && i + 1 < n) out.insert(out.end(), bs[i].loops.begin(), bs[i].loops.end());
      if (i + 1 < n && !bs[i].loops.empty()) pair_bands(bs[i].loops, bs[i + 1].loops, out);
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j + 1 < n && bs[j + 1].loops.size() == 1) ++j;
    if (i > 0) out.push_back(bs[i].loops.front());
    if (j + 1 < n) {
      out.push_back(bs[j].loops.front());
      pair_bands(bs[j].loops, bs[j + 1].loops, out);
    }
    const Eigen::Vector2d move = loop_centre(bs[j].loops.front()) - loop_centre(bs[i].loops.front());
    if (j > i) {
      std::vector<Loops> run;
      for (std::size_t k = i; k <= j; ++k) run.push_back(bs[k].loops);
      support_band(run, move.norm() > kStill ? move.normalized() : Eigen::Vector2d(1.0, 0.0), tol_mm, out);
    }
    i = j + 1;
  }
}

}  // namespace

Loops swept_footprint(const SurfaceMesh& last, const SurfaceMesh& cur, const SweepTolerance& tol, int* samples,
                      bool with_start) {
  if (last.vertices.rows() != cur.vertices.rows() || last.faces.rows() != cur.faces.rows())
    throw std::invalid_argument("swept_footprint: the two meshes differ in topology");
  if (!(tol.tol_mm > 0.0) || tol.max_samples < 1)
    throw std::invalid_argument("swept_footprint: tol_mm must be > 0 and max_samples >= 1");
  NearPart p = near_part(last, cur);
  const int K = blends_needed(p, tol);
  if (samples != nullptr) *samples = K;
  Loops out;
  if (K == 0) return out;
  p.blend(0.0);
  Loops l0 = footprint_projection(p.mesh, p.s);
  p.blend(1.0);
  Loops l1 = footprint_projection(p.mesh, p.s);
  // the two ends
  if (with_start) out = l0;
  out.insert(out.end(), l1.begin(), l1.end());
  // the footprints at the blends the error estimate asks for and the bands between them
  const std::vector<Blend> bs = adaptive_blends(p, std::move(l0), std::move(l1), K, tol);
  if (samples != nullptr) *samples = static_cast<int>(bs.size()) - 1;
  blend_bands(bs, tol.tol_mm, out);
  // points within tol of their chord go, as the stroke's clean-up drops them (clip::clean)
  return simplified(std::move(out), tol.tol_mm);
}

Loops union_loops(const Loops& loops) { return clip::to_loops(clip::unite(clip::to_paths(loops))); }

}  // namespace brushwork
