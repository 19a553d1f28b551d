// Child tufts (seed "Simulation with multiple tufts"): the sprouting score, where a child's root
// lies on its parent node's section, and the state a new child starts from.
#include "brushwork/tufts.hpp"

#include <algorithm>
#include <cmath>

#include "internal.hpp"

namespace brushwork {

using detail::kDeg;
using detail::kPi;

namespace {

constexpr double kMaxTiltDeg = 89.9;  // deg: Pose's bound; a child frame past it is held there
constexpr double kMajorReach = 0.85;  // -, |r_xj| of the outermost children
constexpr double kMinorOffset = 0.1;  // -, |r_yj|: children alternate above and below the major axis
// rad, how far the outermost children lean out from the parent's spine (the fan of seed
// Figure 6b): child j turns toward +-u_i by kSplay r_xj
constexpr double kSplay = 0.15;
// -, weight of the bend below N_i (in quarter turns) against the mean spread in the score
constexpr double kBendWeight = 0.25;

// (a_i + b_i) / 2 r_i - 1 with a_i = d_i^+ + r_lat: the fractional widening of section Omega_i
double widening(const Tuft& t, const Workspace& w, int i) {
  return 0.5 * (w.d_plus[i] + w.d_minus[i]) / t.r0[i] + t.rlat[i] / t.r0[i] - 1.0;
}

// 1 - wetness of node i, in [0, 1]
double node_dryness(const BrushState& s, int i) {
  return 1.0 - (i < s.wetness.size() ? std::clamp(s.wetness[i], 0.0, 1.0) : 1.0);
}

}  // namespace

double sprout_score(const Tuft& t, const BrushState& s, const Workspace& w, int node) {
  double spread = 0.0, bend = 0.0, wet = 0.0;
  for (int i = node; i < t.n; ++i) {
    spread += widening(t, w, i);
    bend += std::abs(s.x[2 * i]);
  }
  for (int i = node; i <= t.n; ++i) wet += i < s.wetness.size() ? std::clamp(s.wetness[i], 0.0, 1.0) : 1.0;
  const double dryness = 1.0 - wet / (t.n - node + 1);
  return (spread / (t.n - node) + kBendWeight * bend / (0.5 * kPi)) * (1.0 + dryness);
}

double tuft_clearance(const Tuft& t, const Workspace& w) {
  double low = detail::kHuge;
  for (int i = 1; i <= t.n; ++i) low = std::min(low, w.O[i].z() - detail::section_reach(t, w, i));
  return low;
}

double split_reach(const Tuft& t, const BrushState& s, const Workspace& w, int node) {
  return widening(t, w, node) * (1.0 + node_dryness(s, node));
}

Vec2 child_displacement(int j, int k, bool even) {
  const double rx = k > 1 ? kMajorReach * (2.0 * j / (k - 1) - 1.0) : 0.0;
  const double ry = even ? 0.0 : (j % 2 == 0 ? -1.0 : 1.0) * kMinorOffset;
  return Vec2(rx, ry);
}

Pose child_pose(const Tuft& t, const BrushState& s, const Workspace& w, int node, const Vec2& r) {
  // root: O_ij + r_x (a or b, + r_lat) u_i + r_y c_i w_i, on the bisecting plane of N_i
  const double major = (r.x() >= 0.0 ? w.d_plus[node] : w.d_minus[node]) + t.rlat[node];
  Pose p;
  p.position = w.O[node] + r.x() * major * w.u[node] + r.y() * w.c[node] * w.w[node];
  // that frame as (tilt, azimuth, twist): e3 = -(handle axis), e1 in the handle's
  // vertical plane turned by the twist about e3 (frame.cpp, set_root_frame)
  // root frame: F_{i-1} (R_0 at the root) leaned toward the child's side of the lateral line
  // by kSplay r_x
  const Mat3& above = node == 0 ? s.R0 : w.F[node - 1];
  const Vec3 axis = above.col(2).cross(w.u[node]);
  const Mat3 F = (axis.norm() > 0.0 ? Eigen::AngleAxisd(kSplay * r.x(), axis.normalized()).toRotationMatrix()
                                    : Mat3::Identity()) * above;
  const Vec3 e3 = F.col(2);
  const double tl = std::min(std::acos(std::clamp(-e3.z(), -1.0, 1.0)), kMaxTiltDeg * kDeg);
  const double az = std::atan2(-e3.y(), -e3.x());
  const Vec3 e1(-std::cos(tl) * std::cos(az), -std::cos(tl) * std::sin(az), std::sin(tl));
  const Vec3 e3c(-std::sin(tl) * std::cos(az), -std::sin(tl) * std::sin(az), -std::cos(tl));
  const Vec3 e2 = e3c.cross(e1);
  p.tilt_deg = tl / kDeg;
  p.azimuth_deg = az / kDeg;
  p.twist_deg = std::atan2(F.col(0).dot(e2), F.col(0).dot(e1)) / kDeg;
  return p;
}

void seed_child(const Tuft& parent, const BrushState& ps, int node, const Tuft& child, BrushState& cs) {
  const int n = parent.n, nc = child.n;
  for (int k = 0; k < nc; ++k) {
    // theta_k, phi_k of the child = theta_{i+k}, phi_{i+k} of the parent; rest angles alike
    for (int a = 0; a < 2; ++a) {
      cs.x[2 * k + a] = ps.x[2 * (node + k) + a];
      cs.rest[2 * k + a] = ps.rest[2 * (node + k) + a];
    }
    // psi of the child's node k+1 = psi of the parent's node i+k+1
    cs.x[2 * nc + 3 * k] = ps.x[2 * n + 3 * (node + k)];
  }
  cs.x_prev = cs.x;
  cs.wetness = ps.wetness.tail(nc + 1);
  if (ps.ink.loaded()) {
    cs.ink = ps.ink;
    cs.ink.load = ps.ink.load.tail(nc + 1) * (child.r0.squaredNorm() / parent.r0.tail(nc + 1).squaredNorm());
    cs.ink.capacity = ps.ink.capacity.tail(nc + 1) * (child.r0.squaredNorm() / parent.r0.tail(nc + 1).squaredNorm());
    cs.ink.deposited = 0.0;
  }
}

void grow_child(const Tuft& parent, const BrushState& ps, int node, const BrushState& old, const Tuft& child,
                BrushState& cs) {
  const int n = parent.n, nc = child.n, no = nc - 1;
  // theta_0, phi_0 (and rest angles) of the parent's joint at N_node; joint k+1 = old joint k
  cs.x.head(2) = ps.x.segment(2 * node, 2);
  cs.rest.head(2) = ps.rest.segment(2 * node, 2);
  cs.x.segment(2, 2 * no) = old.x.head(2 * no);
  cs.rest.segment(2, 2 * no) = old.rest.head(2 * no);
  // psi of node 1 = psi of the parent's N_{node+1} (a child's stretches stay 0); node k+1 = old node k
  cs.x[2 * nc] = ps.x[2 * n + 3 * node];
  cs.x.segment(2 * nc + 3, 3 * no) = old.x.segment(2 * no, 3 * no);
  cs.x_prev = cs.x;
  cs.wetness << ps.wetness[node], old.wetness;
  if (old.ink.loaded() && ps.ink.loaded()) {
    // the new root node holds the parent's ink at N_node in proportion to the section areas
    const double share = child.r0[0] * child.r0[0] / (parent.r0[node] * parent.r0[node]);
    cs.ink = old.ink;
    cs.ink.load.resize(nc + 1);
    cs.ink.capacity.resize(nc + 1);
    cs.ink.load << share * ps.ink.load[node], old.ink.load;
    cs.ink.capacity << share * ps.ink.capacity[node], old.ink.capacity;
  }
}

}  // namespace brushwork
