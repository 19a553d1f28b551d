#include "render_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace brushwork {

namespace {

constexpr float kMinNormal = 1e-20f;  // mm^2: a summed normal this short has no direction (up is used)

// The render layout's uv and faces depend on the ring count, the vertices around and the winding
// alone, not on the rest of the pose: the footprint pass builds a mesh every frame, so they are
// made once per (rings, around, winding) and copied (re-indexing the faces took about half of a
// 1024 px frame's mesh time).  sweep_surface turns every face over when a pose's frame is
// left-handed (its winding test), so the first face it gave is kept and compared.
struct Topology {
  int NR = -1, A = -1;
  std::array<int, 3> first{{-1, -1, -1}};  // the first face of the core's mesh it was made from
  std::vector<float> uv;             // (RV, 2)
  std::vector<std::uint32_t> faces;  // (F, 3)
};

// (NR * (A + 1) + 2, 2) uv: rings along the spine (0 .. 1), columns around (0 .. 1, the first
// repeated at 1), then the root cap (0, 0.5) and the tip apex (1, 0.5)
void ring_uv(int NR, int A, std::vector<float>& uv) {
  const int cols = A + 1;
  const int R_root = NR * cols, R_apex = NR * cols + 1;
  uv.assign(2 * static_cast<std::size_t>(NR * cols + 2), 0.0f);
  for (int j = 0; j < NR; ++j) {
    const double along = NR > 1 ? static_cast<double>(j) / (NR - 1) : 0.0;
    for (int k = 0; k <= A; ++k) {
      uv[2 * (j * cols + k)] = static_cast<float>(along);
      uv[2 * (j * cols + k) + 1] = static_cast<float>(k) / A;
    }
  }
  uv[2 * R_root] = 0.0f, uv[2 * R_root + 1] = 0.5f;
  uv[2 * R_apex] = 1.0f, uv[2 * R_apex + 1] = 0.5f;
}

// the core's faces re-indexed; a triangle spanning the seam (columns A-1 and 0) uses the
// repeated column
void reindex_faces(const SurfaceMesh& m, int NR, int A, std::vector<std::uint32_t>& faces) {
  const int cols = A + 1;
  const int root_cap = NR * A, apex = NR * A + 1;
  const int R_root = NR * cols, R_apex = NR * cols + 1;  // their render indices
  faces.clear();
  faces.reserve(3 * m.faces.rows());
  for (int f = 0; f < m.faces.rows(); ++f) {
    int idx[3];
    bool has_last = false;
    for (int e = 0; e < 3; ++e) {
      idx[e] = m.faces(f, e);
      if (idx[e] < root_cap && idx[e] % A == A - 1) has_last = true;
    }
    for (int e = 0; e < 3; ++e) {
      const int v = idx[e];
      if (v == root_cap) faces.push_back(R_root);
      else if (v == apex) faces.push_back(R_apex);
      else faces.push_back(static_cast<std::uint32_t>(v / A * cols + ((v % A == 0 && has_last) ? A : v % A)));
    }
  }
}

const Topology& topology(const SurfaceMesh& m, int NR, int A) {
  static thread_local Topology t;
  const std::array<int, 3> first{{m.faces(0, 0), m.faces(0, 1), m.faces(0, 2)}};
  if (t.NR == NR && t.A == A && t.first == first && t.faces.size() == 3 * static_cast<std::size_t>(m.faces.rows()))
    return t;
  t.NR = NR, t.A = A, t.first = first;
  ring_uv(NR, A, t.uv);
  reindex_faces(m, NR, A, t.faces);
  return t;
}

}  // namespace

RenderMesh build_render_mesh(const std::vector<Section>& sections, const MeshOptions& opt, bool with_normals) {
  const SurfaceMesh m = sweep_surface(sections, opt);
  const int A = opt.around;
  const int V = static_cast<int>(m.vertices.rows());
  const int NR = (V - 2) / A;  // rings: n * rings_per_segment + 1
  const int cols = A + 1;
  const int root_cap = NR * A, apex = NR * A + 1;
  const int R_root = NR * cols, R_apex = NR * cols + 1;  // their render indices
  const Topology& topo = topology(m, NR, A);

  RenderMesh r;
  const int RV = NR * cols + 2;
  r.position.resize(3 * RV);
  r.center.resize(3 * RV);
  r.uv = topo.uv;
  r.faces = topo.faces;
  auto put3 = [](float* o, double x, double y, double z) {
    o[0] = static_cast<float>(x);
    o[1] = static_cast<float>(y);
    o[2] = static_cast<float>(z);
  };
  const double* mv = m.vertices.data();  // (V, 3) row-major
  for (int j = 0; j < NR; ++j) {
    // ring centre: mean of the ring (the spine point up to the a+/a- asymmetry)
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < A; ++k) c += m.vertices.row(j * A + k).transpose();
    c /= A;
    for (int k = 0; k <= A; ++k) {
      const double* src = mv + 3 * static_cast<std::ptrdiff_t>(j * A + (k == A ? 0 : k));
      const int dst = j * cols + k;
      put3(&r.position[3 * dst], src[0], src[1], src[2]);
      put3(&r.center[3 * dst], c.x(), c.y(), c.z());
    }
  }
  for (auto [src, dst] : {std::pair<int, int>{root_cap, R_root}, std::pair<int, int>{apex, R_apex}}) {
    put3(&r.position[3 * dst], m.vertices(src, 0), m.vertices(src, 1), m.vertices(src, 2));
    put3(&r.center[3 * dst], m.vertices(src, 0), m.vertices(src, 1), m.vertices(src, 2));
  }

  if (!with_normals) return r;
  // area-weighted vertex normals (for the brush view's shading and outline)
  r.normal.assign(3 * RV, 0.0f);
  for (std::size_t f = 0; f < r.faces.size(); f += 3) {
    const std::uint32_t a = r.faces[f], b = r.faces[f + 1], c = r.faces[f + 2];
    const Eigen::Vector3f pa(&r.position[3 * a]), pb(&r.position[3 * b]), pc(&r.position[3 * c]);
    const Eigen::Vector3f nrm = (pb - pa).cross(pc - pa);
    for (std::uint32_t v : {a, b, c})
      for (int d = 0; d < 3; ++d) r.normal[3 * v + d] += nrm[d];
  }
  // the seam column and its twin share one normal
  for (int j = 0; j < NR; ++j)
    for (int d = 0; d < 3; ++d) {
      const float s = r.normal[3 * (j * cols) + d] + r.normal[3 * (j * cols + A) + d];
      r.normal[3 * (j * cols) + d] = r.normal[3 * (j * cols + A) + d] = s;
    }
  for (int v = 0; v < RV; ++v) {
    Eigen::Map<Eigen::Vector3f> nv(&r.normal[3 * v]);
    const float len = nv.norm();
    if (len > kMinNormal) nv /= len;
    else nv = Eigen::Vector3f::UnitZ();
  }
  return r;
}

}  // namespace brushwork
