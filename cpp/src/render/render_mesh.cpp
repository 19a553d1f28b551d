#include "render_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace brushwork {

RenderMesh build_render_mesh(const Brush& brush, const MeshOptions& opt, bool with_normals) {
  const SurfaceMesh m = brush.surface_mesh(opt);
  const int A = opt.around;
  const int V = static_cast<int>(m.vertices.rows());
  const int NR = (V - 2) / A;  // rings: n * rings_per_segment + 1
  const int cols = A + 1;
  const int root_cap = NR * A, apex = NR * A + 1;
  const int R_root = NR * cols, R_apex = NR * cols + 1;  // their render indices

  RenderMesh r;
  const int RV = NR * cols + 2;
  r.position.resize(3 * RV);
  r.center.resize(3 * RV);
  r.uv.resize(2 * RV);
  auto put3 = [](std::vector<float>& v, int i, double x, double y, double z) {
    v[3 * i] = static_cast<float>(x);
    v[3 * i + 1] = static_cast<float>(y);
    v[3 * i + 2] = static_cast<float>(z);
  };
  for (int j = 0; j < NR; ++j) {
    // ring centre: mean of the ring (the spine point up to the a+/a- asymmetry)
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < A; ++k) c += m.vertices.row(j * A + k).transpose();
    c /= A;
    const double along = NR > 1 ? static_cast<double>(j) / (NR - 1) : 0.0;
    for (int k = 0; k <= A; ++k) {
      const int src = j * A + (k == A ? 0 : k), dst = j * cols + k;
      put3(r.position, dst, m.vertices(src, 0), m.vertices(src, 1), m.vertices(src, 2));
      put3(r.center, dst, c.x(), c.y(), c.z());
      r.uv[2 * dst] = static_cast<float>(along);
      r.uv[2 * dst + 1] = static_cast<float>(k) / A;
    }
  }
  for (auto [src, dst, along] : {std::tuple<int, int, double>{root_cap, R_root, 0.0},
                                 std::tuple<int, int, double>{apex, R_apex, 1.0}}) {
    put3(r.position, dst, m.vertices(src, 0), m.vertices(src, 1), m.vertices(src, 2));
    put3(r.center, dst, m.vertices(src, 0), m.vertices(src, 1), m.vertices(src, 2));
    r.uv[2 * dst] = static_cast<float>(along);
    r.uv[2 * dst + 1] = 0.5f;
  }

  // faces: re-index; a triangle spanning the seam (columns A-1 and 0) uses the repeated column
  r.faces.reserve(3 * m.faces.rows());
  for (int f = 0; f < m.faces.rows(); ++f) {
    int idx[3];
    bool has_last = false;
    for (int e = 0; e < 3; ++e) {
      idx[e] = m.faces(f, e);
      if (idx[e] < root_cap && idx[e] % A == A - 1) has_last = true;
    }
    for (int e = 0; e < 3; ++e) {
      const int v = idx[e];
      std::uint32_t out;
      if (v == root_cap) out = R_root;
      else if (v == apex) out = R_apex;
      else {
        const int j = v / A, k = v % A;
        out = static_cast<std::uint32_t>(j * cols + ((k == 0 && has_last) ? A : k));
      }
      r.faces.push_back(out);
    }
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
    if (len > 1e-20f) nv /= len;
    else nv = Eigen::Vector3f::UnitZ();
  }
  return r;
}

std::vector<float> node_pressure(const Brush& brush) {
  const auto secs = brush.sections();
  std::vector<float> p(secs.size(), 0.0f);
  constexpr int kSamples = 32;
  for (std::size_t i = 0; i < secs.size(); ++i) {
    const Section& s = secs[i];
    // lowest point of the two half ellipses, sampled around
    double zmin = s.center.z();
    for (int k = 0; k < kSamples; ++k) {
      const double t = 2.0 * 3.14159265358979323846 * k / kSamples;
      const double ct = std::cos(t), st = std::sin(t);
      const double z = s.center.z() + (ct >= 0 ? s.a_plus : s.a_minus) * ct * s.u.z() +
                       s.c * st * s.w.z();
      zmin = std::min(zmin, z);
    }
    p[i] = static_cast<float>(std::clamp(-zmin / std::max(s.c, 1e-3), 0.0, 1.0));
  }
  return p;
}

}  // namespace brushwork
