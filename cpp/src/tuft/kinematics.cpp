// The tuft's constants, its forward kinematics (seed Figure 2) and the maps from node-level
// gradients to the variables; the sections Omega_i and their lowest points.
#include <algorithm>
#include <cmath>

#include "internal.hpp"

namespace brushwork {

using detail::kTiny;

namespace {

// the lateral line's own rotation psi_i gets a weak restoring spring, this fraction of the twist
// spring at the same joint (-), so it stays determined in free air (in contact the constraints
// and lateral bend springs decide it)
constexpr double kPsiSpringFraction = 0.1;
// -, floor of the twist : bend ratio used for that spring (a model without twist springs still
// holds its lateral lines)
constexpr double kPsiTwistFloor = 0.1;
// -, a section's minor axis w_i counts as at least this far from horizontal when its centre
// is moved down onto the paper (sections())
constexpr double kMinAxisTilt = 1e-12;

// A Rz(a) and A Ry(a) for a frame A, with c = cos a, s = sin a: a rotation about a frame axis
// mixes the other two columns and keeps that one
inline void turn_z(const Mat3& A, double c, double s, Mat3& out) {
  out.col(0) = c * A.col(0) + s * A.col(1);
  out.col(1) = c * A.col(1) - s * A.col(0);
  out.col(2) = A.col(2);
}
inline void turn_y(const Mat3& A, double c, double s, Mat3& out) {
  out.col(0) = c * A.col(0) - s * A.col(2);
  out.col(1) = A.col(1);
  out.col(2) = s * A.col(0) + c * A.col(2);
}

// the variables the solver moves: everything but the stretches when lateral spreading is off
std::vector<int> active_variables(const BrushModel& m) {
  const int n = m.n_segments;
  std::vector<int> active;
  for (int j = 0; j < 2 * n; ++j) active.push_back(j);
  for (int i = 1; i <= n; ++i) {
    const int b = 2 * n + 3 * (i - 1);
    active.push_back(b);
    if (m.lateral_spreading) {
      active.push_back(b + 1);
      active.push_back(b + 2);
    }
  }
  return active;
}

// rest shape of the lateral polylines (the tuft profile bends them even when unstrained):
// t_i - t_{i-1} of the straight brush, in each node's lateral frame
void lateral_rest_shape(Tuft& t) {
  const int n = t.n;
  BrushState s;
  Workspace w(t);
  kinematics(t, s, VecX::Zero(t.nx), w);
  for (int side = 0; side < 2; ++side) {
    const double sg = side == 0 ? 1.0 : -1.0;
    t.lb_rest[side].assign(n + 1, Vec3::Zero());
    for (int i = 1; i < n; ++i) {
      const VecX& d = side == 0 ? w.d_plus : w.d_minus;
      const Vec3 t0 = (w.O[i] + sg * d[i] * w.u[i] - w.O[i - 1] - sg * d[i - 1] * w.u[i - 1]).normalized();
      const Vec3 t1 = (w.O[i + 1] + sg * d[i + 1] * w.u[i + 1] - w.O[i] - sg * d[i] * w.u[i]).normalized();
      const Vec3 v = t1 - t0;
      t.lb_rest[side][i] = Vec3(v.dot(w.w[i]), v.dot(w.u[i]), v.dot(w.nrm[i]));
    }
  }
}

}  // namespace

Tuft::Tuft(const BrushModel& m) : model(m) {
  model.validate();
  n = model.n_segments;
  nx = 5 * n;
  m_exp = model.exponent;
  shrink = model.collision_shrink;
  f_scale = model.bend_stiffness;
  mmax = n + 1;

  // lengths l_j, radii r_i and r_lat, spring constants kappa (root stiffer than tip)
  len = model.segment_lengths();
  r0 = model.node_radii();
  rlat = model.lateral_radius_fraction * r0;
  kb = model.bend_kappa();
  kt = model.twist_stiffness * kb;
  kpsi.resize(n + 1);
  for (int i = 0; i <= n; ++i)
    kpsi[i] = kPsiSpringFraction * std::max(model.twist_stiffness, kPsiTwistFloor) * kb[std::min(i, n - 1)];
  ks = model.stretch_stiffness;
  // lateral bend springs follow the bend springs' hair-count law (model.cpp, stiffness_profile):
  // the spring at node i stiffens the tuft's sides like joint i's spring its spine
  const VecX prof = model.stiffness_profile();
  klb.resize(n + 1);
  for (int i = 0; i <= n; ++i) klb[i] = model.lateral_bend_stiffness * prof[std::min(i, n - 1)];
  eta = model.internal_friction;
  active = active_variables(model);
  lateral_rest_shape(*this);
}

Workspace::Workspace(const Tuft& t) {
  const int n = t.n, na = t.na(), mmax = t.mmax;
  O.assign(n + 1, Vec3::Zero());
  u = w = nrm = gO = gu = tau = O;
  aphi.assign(n, Vec3::Zero());
  ath = aphi;
  F.assign(n, Mat3::Identity());
  Q = F;
  for (VecX* v : {&d_plus, &d_minus, &c, &gdp, &gdm}) v->resize(n + 1);
  for (VecX* v : {&xf_trial, &gf, &gf_new, &x_eval}) v->resize(t.nx);
  for (VecX* v : {&za, &zt, &gact, &gact_new, &s, &yv, &r, &Hr, &Bs, &tmp, &step}) v->resize(na);
  for (VecX* v : {&g, &g_new, &gtrial, &q, &lam, &lam_f, &rhs}) v->resize(mmax);
  J.resize(mmax, t.nx);
  Jact.resize(mmax, na);
  Jact_new.resize(mmax, na);
  HJt.resize(na, mmax);
  M.resize(mmax, mmax);
  Mff.resize(mmax, mmax);
  qp_state.assign(mmax, 0);
}

// ---------------------------------------------------------------------------------------------
// forward kinematics (seed Figure 2): F_j = F_{j-1} Rz(phi_j) Ry(theta_j) is the frame of
// segment j (its z axis the segment direction), O_{j+1} = O_j + l_j F_j e_z.  The section
// Omega_i lies in the joint-bisecting plane, frame G_i = F_{i-1} Rz(phi_i) Ry(theta_i / 2); its
// lateral line u_i = G_i Rz(psi_i) e_y starts perpendicular to both segments.
namespace {

void spine_frames(const Tuft& t, const BrushState& s, const VecX& x, Workspace& w) {
  w.O[0] = s.root;
  for (int j = 0; j < t.n; ++j) {
    const Mat3& prev = j == 0 ? s.R0 : w.F[j - 1];
    w.aphi[j] = prev.col(2);
    turn_z(prev, std::cos(x[2 * j + 1]), std::sin(x[2 * j + 1]), w.Q[j]);
    turn_y(w.Q[j], std::cos(x[2 * j]), std::sin(x[2 * j]), w.F[j]);
    w.ath[j] = w.Q[j].col(1);
    w.O[j + 1] = w.O[j] + t.len[j] * w.F[j].col(2);
  }
}

void section_frame(const Tuft& t, const VecX& x, Workspace& w, int i) {
  const int n = t.n;
  Mat3 G;
  if (i < n) turn_y(w.Q[i], std::cos(0.5 * x[2 * i]), std::sin(0.5 * x[2 * i]), G);
  else G = w.F[n - 1];
  double cp = 1.0, sp = 0.0;  // psi_0 = 0: the root's lateral line is G_0 e_y
  if (i > 0) {
    const double psi = x[2 * n + 3 * (i - 1)];
    cp = std::cos(psi);
    sp = std::sin(psi);
  }
  w.u[i] = cp * G.col(1) - sp * G.col(0);
  w.w[i] = cp * G.col(0) + sp * G.col(1);
  w.nrm[i] = G.col(2);
  // lateral distances a = r_i - r_lat + delta^2 (so that the unstretched section is the
  // circle of radius r_i) and the minor radius from area conservation c = r^2 / ((a+b)/2 + r_lat)
  double dp = t.r0[i] - t.rlat[i], dm = dp;
  if (i > 0) {
    const double ep = x[2 * n + 3 * (i - 1) + 1], em = x[2 * n + 3 * (i - 1) + 2];
    dp += ep * ep;
    dm += em * em;
  }
  w.d_plus[i] = dp;
  w.d_minus[i] = dm;
  w.c[i] = t.r0[i] * t.r0[i] / (0.5 * (dp + dm) + t.rlat[i]);
}

}  // namespace

void kinematics(const Tuft& t, const BrushState& s, const VecX& x, Workspace& w) {
  w.x_eval = x;
  spine_frames(t, s, x, w);
  for (int i = 0; i <= t.n; ++i) section_frame(t, x, w, i);
}

namespace detail {

double section_reach(const Tuft& t, const Workspace& w, int i) {
  const double uz = w.u[i].z();
  const double A = (uz < 0.0 ? w.d_plus[i] : w.d_minus[i]) + t.rlat[i], c = w.c[i];
  return std::sqrt(std::max(A * A * uz * uz + c * c * (1.0 - uz * uz), kTiny));
}

void clear_node_grads(const Tuft& t, Workspace& w) {
  for (int i = 0; i <= t.n; ++i) w.gO[i].setZero(), w.gu[i].setZero(), w.tau[i].setZero();
  w.gdp.setZero();
  w.gdm.setZero();
}

// Turn node-level gradients (d/dO_i, d/du_i, d/da_i, d/db_i) into d/dx.  A joint angle rotates
// everything below it about an axis a through O_k, so d/dq = a . sum_j [(O_j - O_k) x gO_j +
// u_j x gu_j]; suffix sums make the whole map O(n).  theta_k turns its own section's frame by
// half its angle (the bisecting plane), phi_k by all of it.
void chain(const Tuft& t, const Workspace& w, VecX& gx) {
  const int n = t.n;
  Vec3 T = Vec3::Zero(), Gs = Vec3::Zero();
  for (int k = n - 1; k >= 0; --k) {
    const int j = k + 1;
    T += w.O[j].cross(w.gO[j]) + w.u[j].cross(w.gu[j]) + w.tau[j];
    Gs += w.gO[j];
    const Vec3 base = T - w.O[k].cross(Gs);
    const Vec3 lat = w.u[k].cross(w.gu[k]) + w.tau[k];
    gx[2 * k + 1] += w.aphi[k].dot(base + lat);
    gx[2 * k] += w.ath[k].dot(base + 0.5 * lat);
  }
  for (int i = 1; i <= n; ++i) {
    const int b = 2 * n + 3 * (i - 1);
    gx[b] += w.nrm[i].dot(w.u[i].cross(w.gu[i]) + w.tau[i]);  // dv/dpsi = n x v for v in the lateral frame
    gx[b + 1] += w.gdp[i] * 2.0 * w.x_eval[b + 1];
    gx[b + 2] += w.gdm[i] * 2.0 * w.x_eval[b + 2];
  }
}

// One row of the constraint Jacobian, for a constraint that depends on node i alone (through
// gO = d/dO_i, gu = d/du_i, gdp, gdm = d/da_i, d/db_i): chain() with every other node's
// gradient zero.  The joints below node i do not move it, so their entries are zero; a joint
// k < i turns O_i and u_i about its axis through O_k (base = O_i x gO + u_i x gu - O_k x gO),
// the joint k = i turns u_i by half its bend (the bisecting plane) and all of its turn.  O(i).
void constraint_row(const Tuft& t, const Workspace& w, int i, const Vec3& gO, const Vec3& gu, double gdp,
                    double gdm, MatX& J, int row) {
  const int n = t.n;
  J.row(row).setZero();
  const Vec3 lat = w.u[i].cross(gu);
  if (i < n) {
    J(row, 2 * i + 1) = w.aphi[i].dot(lat);
    J(row, 2 * i) = w.ath[i].dot(0.5 * lat);
  }
  const Vec3 T = w.O[i].cross(gO) + lat;
  for (int k = i - 1; k >= 0; --k) {
    const Vec3 base = T - w.O[k].cross(gO);
    J(row, 2 * k + 1) = w.aphi[k].dot(base);
    J(row, 2 * k) = w.ath[k].dot(base);
  }
  if (i > 0) {
    const int b = 2 * n + 3 * (i - 1);
    J(row, b) = w.nrm[i].dot(lat);
    J(row, b + 1) = gdp * 2.0 * w.x_eval[b + 1];
    J(row, b + 2) = gdm * 2.0 * w.x_eval[b + 2];
  }
}

void gather(const Tuft& t, const VecX& full, VecX& act) {
  for (size_t k = 0; k < t.active.size(); ++k) act[k] = full[t.active[k]];
}
void scatter(const Tuft& t, const VecX& act, VecX& full) {
  for (size_t k = 0; k < t.active.size(); ++k) full[t.active[k]] = act[k];
}

}  // namespace detail

// ---------------------------------------------------------------------------------------------
// geometry at the workspace's kinematics
VecX section_heights(const Tuft& t, const Workspace& w) {
  VecX h(t.n);
  for (int i = 1; i <= t.n; ++i) h[i - 1] = w.O[i].z() - t.shrink * detail::section_reach(t, w, i);
  return h;
}

std::vector<Section> sections(const Tuft& t, const Workspace& w) {
  std::vector<Section> out(t.n + 1);
  for (int i = 0; i <= t.n; ++i) {
    Section& s = out[i];
    // A spread section flattens onto the paper rather than lifting off it.  The seed centres
    // both half-ellipses on the spine node, so a section that spreads (c = r^2 / (mean major
    // radius), smaller) lifts its underside off the paper: between 0.26 and 0.36 L of press a
    // small brush's belly section spread from 4.0 to 7.5 mm while the footprint kept the 4.7 mm
    // of the next one, and stroke widths jumped between such plateaus.  So the centre moves
    // toward the paper along w by what the minor radius lost, r_i - c_i, times how far w points
    // down, but never below the paper: the widest points rest on it (where the cross-section
    // at the paper is the footprint, and the renderer's ink matches it).  The solver's
    // constraints and contacts keep the seed's geometry (the shrunk sections about O_i).
    const double wz = w.w[i].z();
    double shift = (t.r0[i] - w.c[i]) * std::abs(wz);  // mm along the downward w
    if (shift * std::abs(wz) > w.O[i].z())
      shift = std::max(0.0, w.O[i].z()) / std::max(std::abs(wz), kMinAxisTilt);
    s.center = w.O[i] - (wz >= 0.0 ? 1.0 : -1.0) * shift * w.w[i];
    s.u = w.u[i];
    s.w = w.w[i];
    s.n = w.nrm[i];
    s.a_plus = w.d_plus[i] + t.rlat[i];  // major radii a + r_lat, b + r_lat
    s.a_minus = w.d_minus[i] + t.rlat[i];
    s.c = w.c[i];
  }
  return out;
}

}  // namespace brushwork
