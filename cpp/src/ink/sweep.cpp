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

}  // namespace clip

namespace {

using Rows3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

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

using Run = std::vector<Eigen::Vector2d>;
using LoopMat = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

// the runs of edges of the loops facing a move by `shift` mm (outward normal (dy, -dx), the region
// on the left of travel, with a positive component along the shift), each as its points in order.
// Such a run is monotone across the shift, so it and its slid copy bound a simple band
std::vector<Run> facing_runs(const Loops& loops, const Eigen::Vector2d& shift) {
  std::vector<Run> runs;
  if (shift.squaredNorm() < 1e-18) return runs;
  for (const auto& L : loops) {
    const Eigen::Index k = L.rows();
    auto facing = [&](Eigen::Index i) {
      const Eigen::Vector2d e = L.row(i + 1 == k ? 0 : i + 1) - L.row(i);
      return e.y() * shift.x() - e.x() * shift.y() > 0.0;
    };
    // start after an edge that does not face the move (a loop facing it all round has no band)
    Eigen::Index start = -1;
    for (Eigen::Index i = 0; i < k && start < 0; ++i)
      if (!facing(i)) start = (i + 1) % k;
    if (start < 0) continue;
    Run run;
    for (Eigen::Index n = 0; n <= k; ++n) {
      const Eigen::Index i = (start + n) % k;
      if (n < k && facing(i)) {
        if (run.empty()) run.push_back(L.row(i).transpose());
        run.push_back(L.row(i + 1 == k ? 0 : i + 1).transpose());
        continue;
      }
      if (run.size() >= 2) runs.push_back(run);
      run.clear();
    }
  }
  return runs;
}

// a closed polygon from its points, turned counter-clockwise
LoopMat ccw_polygon(const std::vector<Eigen::Vector2d>& pts) {
  LoopMat m(static_cast<Eigen::Index>(pts.size()), 2);
  for (std::size_t j = 0; j < pts.size(); ++j) m.row(static_cast<Eigen::Index>(j)) = pts[j].transpose();
  if (loops_area({m}) < 0.0) m.colwise().reverseInPlace();
  return m;
}

// the band each run sweeps when slid by `shift`: the run, then the run slid and walked back
void slid_band(const std::vector<Run>& runs, const Eigen::Vector2d& shift, Loops& out) {
  for (const Run& run : runs) {
    std::vector<Eigen::Vector2d> pts(run);
    for (auto it = run.rbegin(); it != run.rend(); ++it) pts.push_back(*it + shift);
    out.push_back(ccw_polygon(pts));
  }
}

// the bands of a sweep whose every footprint has one run facing its move, as one polygon: the
// first run, the path of the runs' last points (each slid), the last run slid and walked back,
// the path of the runs' first points (each slid) back to the start.  The intermediate runs lie
// inside it while the footprint moves much as it translates, which the blends' count keeps
void envelope(const std::vector<Run>& runs, const std::vector<Eigen::Vector2d>& shifts, Loops& out) {
  std::vector<Eigen::Vector2d> pts(runs.front());
  const std::size_t K = runs.size();
  for (std::size_t k = 0; k < K; ++k) pts.push_back(runs[k].back() + shifts[k]);
  for (auto it = runs[K - 1].rbegin() + 1; it != runs[K - 1].rend(); ++it) pts.push_back(*it + shifts[K - 1]);
  for (std::size_t k = K; k-- > 0;) pts.push_back(runs[k].front() + shifts[k]);
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
  std::vector<std::vector<Run>> runs(K);
  std::vector<Eigen::Vector2d> shifts(K, Eigen::Vector2d::Zero());
  bool single = true;  // every footprint one loop with one run facing its move
  for (int k = 0; k < K; ++k) {
    if (spans[k].valid && spans[k + 1].valid) shifts[k] = spans[k + 1].centroid - spans[k].centroid;
    runs[k] = facing_runs(loops[k], shifts[k]);
    single = single && loops[k].size() == 1 && runs[k].size() == 1;
  }
  // the two ends, and between them the envelope of the bands, or (a footprint of several loops,
  // or of several runs) every footprint and its band
  out = loops[0];
  out.insert(out.end(), loops[K].begin(), loops[K].end());
  if (single) {
    std::vector<Run> one(K);
    for (int k = 0; k < K; ++k) one[k] = std::move(runs[k][0]);
    envelope(one, shifts, out);
    return out;
  }
  for (int k = 0; k < K; ++k) {
    if (k > 0) out.insert(out.end(), loops[k].begin(), loops[k].end());
    slid_band(runs[k], shifts[k], out);
  }
  return out;
}

Loops union_loops(const Loops& loops) { return clip::to_loops(clip::unite(clip::to_paths(loops))); }

}  // namespace brushwork
