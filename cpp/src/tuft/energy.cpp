// The incremental potential (seed "Energy Functions") and the constraints (seed "Brush
// dynamics", "Pore resistance") at a full variable vector x, with analytic derivatives.
// Every term adds to E in the same order, and its gradient to the node-level gradients that
// chain() maps to x.
#include <algorithm>
#include <cmath>

#include "../power.hpp"
#include "internal.hpp"

namespace brushwork {

using power::dpow_half;
using power::dpowm;
using power::pow_half;
using power::powm;

namespace {

// rad^2: the bend term of the spread heuristic S saturates at this (see stretch_springs)
constexpr double kSpreadBend2 = 4.0;
// mm, edges of the lateral polylines shorter than this count as this long
constexpr double kMinEdge = 1e-12;

// bend and twist springs kappa_i |theta_i - rho_i|^m with the plastic rest shift rho, no twist
// spring at the root; internal friction: the same form on the change since the last frame
void spine_springs(const Tuft& t, const BrushState& s, const VecX& x, VecX* gx, double& E) {
  const double m = t.m_exp, eta = t.eta;
  for (int j = 0; j < t.n; ++j) {
    const int it = 2 * j, ip = 2 * j + 1;
    const double eb = x[it] - s.rest[it], fb = x[it] - s.x_prev[it];
    E += t.kb[j] * (powm(eb, m) + eta * powm(fb, m));
    if (gx) (*gx)[it] += t.kb[j] * (dpowm(eb, m) + eta * dpowm(fb, m));
    const double ft = x[ip] - s.x_prev[ip];
    E += t.kt[j] * eta * powm(ft, m);
    if (gx) (*gx)[ip] += t.kt[j] * eta * dpowm(ft, m);
    if (j > 0) {
      const double et = x[ip] - s.rest[ip];
      E += t.kt[j] * powm(et, m);
      if (gx) (*gx)[ip] += t.kt[j] * dpowm(et, m);
    }
  }
}

// stretch springs of node i: kappa |delta^2 - S(theta_i, p_i)|^m with S = spread_gain r_i p_i
// (1 + spread_bend_gain b(theta_i)) growing as the segment is pressed and bent (the seed leaves
// S a heuristic of theta_i and p_i).  b = t^2 tanh(theta^2 / t^2) with t = 2 rad: theta^2 within
// 2% up to 0.9 rad and 17% at 1.8 (a deep press folds a tip joint that far), never more than
// 4 rad^2.  With b = theta^2 the spread had no bound: a stretch spring longer than S pulled its
// joint to bend further, which raised S further, and over capped frames after a lift tip joints
// wound to 3-11 rad (11% of kai's frames in the air past 1.5 rad) and a lateral line to 83 rad
void stretch_springs(const Tuft& t, const BrushState& s, const VecX& x, VecX* gx, int i, double& E) {
  const BrushModel& md = t.model;
  const double m = t.m_exp, eta = t.eta;
  const int b = 2 * t.n + 3 * (i - 1);
  const int jt = 2 * std::min(i, t.n - 1);
  const double th = x[jt];
  const double Sbase = md.spread_gain * t.r0[i] * s.p[i];
  const double sat = std::tanh(th * th / kSpreadBend2);
  const double bend = kSpreadBend2 * sat;               // b(theta), rad^2
  const double dbend = 2.0 * th * (1.0 - sat * sat);    // db/dtheta, rad
  const double S = Sbase * (1.0 + md.spread_bend_gain * bend);
  for (int k = 1; k <= 2; ++k) {
    const double dl = x[b + k], dlp = s.x_prev[b + k];
    const double e = dl * dl - S, f = dl * dl - dlp * dlp;
    E += t.ks * (powm(e, m) + eta * powm(f, m));
    if (gx) {
      (*gx)[b + k] += t.ks * (dpowm(e, m) + eta * dpowm(f, m)) * 2.0 * dl;
      (*gx)[jt] -= t.ks * dpowm(e, m) * Sbase * md.spread_bend_gain * dbend;
    }
  }
}

// lateral line springs on psi_i, then node i's stretch springs
void lateral_springs(const Tuft& t, const BrushState& s, const VecX& x, VecX* gx, double& E) {
  const double m = t.m_exp, eta = t.eta;
  for (int i = 1; i <= t.n; ++i) {
    const int b = 2 * t.n + 3 * (i - 1);
    const double ep = x[b], fp = x[b] - s.x_prev[b];
    E += t.kpsi[i] * (powm(ep, m) + eta * powm(fp, m));
    if (gx) (*gx)[b] += t.kpsi[i] * (dpowm(ep, m) + eta * dpowm(fp, m));
    if (t.model.lateral_spreading) stretch_springs(t, s, x, gx, i, E);
  }
}

// one side's bend spring at lateral node i (sg = +1 on the +u side): v = t_i - t_{i-1} - r_i,
// energy kappa_lb |v|^m; te, le: the edge e_i = P_{i+1} - P_i's unit direction and length, tp,
// lp those of e_{i-1}
struct Edge {
  Vec3 t;
  double len;
};
void lateral_bend_at(const Tuft& t, Workspace& w, int side, int i, const Edge& e, const Edge& ep,
                     bool grad, double& E) {
  const double sg = side == 0 ? 1.0 : -1.0;
  const VecX& d = side == 0 ? w.d_plus : w.d_minus;
  VecX& gd = side == 0 ? w.gdp : w.gdm;
  const Vec3& rl = t.lb_rest[side][i];
  const Vec3 rv = rl.x() * w.w[i] + rl.y() * w.u[i] + rl.z() * w.nrm[i];
  const Vec3 v = e.t - ep.t - rv;
  const double vv = v.squaredNorm();
  E += t.klb[i] * pow_half(vv, t.m_exp);
  if (!grad) return;
  const Vec3 dv = t.klb[i] * dpow_half(vv, t.m_exp) * v;
  // dt/de = (I - t t^T) / |e|
  const Vec3 ge = (dv - e.t * e.t.dot(dv)) / e.len;
  const Vec3 gep = -(dv - ep.t * ep.t.dot(dv)) / ep.len;
  // e_i = P_{i+1} - P_i, e_{i-1} = P_i - P_{i-1}; P = O + sg d u
  auto add_point = [&](int k, const Vec3& gP) {
    w.gO[k] += gP;
    w.gu[k] += sg * d[k] * gP;
    gd[k] += sg * gP.dot(w.u[k]);
  };
  add_point(i + 1, ge);
  add_point(i, gep - ge);
  add_point(i - 1, -gep);
  w.tau[i] += rv.cross(-dv);  // r_i turns with node i's lateral frame
}

// bend springs between consecutive lateral nodes P_i = O_i +- d_i u_i, on each side:
// kappa_lb |(t_i - t_{i-1}) - r_i|^m with t the unit edge directions (|t_i - t_{i-1}| ~ the
// angle between them) and r_i their rest difference carried in node i's lateral frame
void lateral_bends(const Tuft& t, Workspace& w, bool grad, double& E) {
  if (!(t.model.lateral_bend_stiffness > 0.0)) return;
  for (int side = 0; side < 2; ++side) {
    const double sg = side == 0 ? 1.0 : -1.0;
    const VecX& d = side == 0 ? w.d_plus : w.d_minus;
    Edge prev{Vec3::Zero(), 1.0};
    for (int i = 0; i < t.n; ++i) {
      const Vec3 Pa = w.O[i] + sg * d[i] * w.u[i], Pb = w.O[i + 1] + sg * d[i + 1] * w.u[i + 1];
      const Vec3 e = Pb - Pa;
      const double le = std::max(e.norm(), kMinEdge);
      const Edge cur{e / le, le};
      if (i > 0) lateral_bend_at(t, w, side, i, cur, prev, grad, E);
      prev = cur;
    }
  }
}

// a gradient gP (3,) at touching point k of node i, carried to O_i and, for a lateral node, to
// u_i and a_i or b_i
void add_touch_gradient(Workspace& w, int i, int k, const Vec3& gP) {
  w.gO[i] += gP;
  if (k == 0) return;
  const double sg = k == 1 ? 1.0 : -1.0;
  const double dk = k == 1 ? w.d_plus[i] : w.d_minus[i];
  w.gu[i] += sg * dk * gP;
  (k == 1 ? w.gdp : w.gdm)[i] += sg * gP.dot(w.u[i]);
}

// external friction mu R_i x_i for the frozen contact set, x_i the dragged distance on the
// paper since the last frame, mu modulated by the hair direction: x_i = sqrt(D^T A D + eps^2)
// - eps with A = mu_side^2 I + (mu_along^2 - mu_side^2) t t^T, t the unnormalised horizontal
// projection of the segment above the node (a vertical segment drags isotropically)
void friction(const Tuft& t, const BrushState& s, Workspace& w, bool grad, double& E) {
  const BrushModel& md = t.model;
  const double ma2 = md.friction_along * md.friction_along;
  const double ms2 = md.friction_side * md.friction_side;
  const double eps = md.friction_smoothing;
  for (int i = 1; i <= t.n; ++i) {
    const Vec2& tx = s.txy[i];
    for (int k = 0; k < 3; ++k) {
      const double R = s.R[3 * i + k];
      if (R <= 0.0) continue;
      const Vec2 D = (detail::touch_point(w, i, k) - s.prev_pts[3 * i + k]).head<2>();
      const Vec2 AD = ms2 * D + (ma2 - ms2) * tx * tx.dot(D);
      const double root = std::sqrt(D.dot(AD) + eps * eps);
      E += R * (root - eps);
      if (grad) add_touch_gradient(w, i, k, Vec3(R * AD.x() / root, R * AD.y() / root, 0.0));
    }
  }
}

// wet adhesion (seed "wet adhesion") as a pull toward the paper: A_i z_i for the nodes of the
// frozen contact set, A_i = wet_adhesion p_i wetness_i shared by node i's touching points; the
// contact force that holds the node up then carries it, and friction through it
void adhesion(const Tuft& t, const BrushState& s, Workspace& w, bool grad, double& E) {
  for (int i = 1; i <= t.n; ++i)
    for (int k = 0; k < 3; ++k) {
      const double A = s.pull[3 * i + k];
      if (A <= 0.0) continue;
      E += A * detail::touch_point(w, i, k).z();
      if (grad) add_touch_gradient(w, i, k, Vec3(0.0, 0.0, A));
    }
}

// g_i = lowest point of the shrunk section Phi_i's ellipsoid (Omega_i turned about its major
// axis, scaled by collision_shrink) >= 0, mm, and its Jacobian row
void section_constraint(const Tuft& t, const Workspace& w, int i, int row, VecX& g, MatX* J) {
  const double sh = t.shrink;
  const double uz = w.u[i].z();
  const bool plus = uz < 0.0;  // the +u half reaches down when u points down
  const double A = (plus ? w.d_plus[i] : w.d_minus[i]) + t.rlat[i], c = w.c[i];
  const double h = detail::section_reach(t, w, i);
  g[row] = w.O[i].z() - sh * h;
  if (!J) return;
  const double gA = -sh * A * uz * uz / h;
  const double gc = -sh * c * (1.0 - uz * uz) / h;
  const double dc = -0.5 * c * c / (t.r0[i] * t.r0[i]);  // dc/da = dc/db
  detail::constraint_row(t, w, i, Vec3(0.0, 0.0, 1.0), Vec3(0.0, 0.0, -sh * (A * A - c * c) * uz / h),
                         gc * dc + (plus ? gA : 0.0), gc * dc + (plus ? 0.0 : gA), *J, row);
}

// the sections' constraints, then the pore plane's
void constraints(const Tuft& t, const BrushState& s, const Workspace& w, VecX& g, MatX* J) {
  int row = 0;
  if (t.model.collision)
    for (int i = 1; i <= t.n; ++i, ++row) section_constraint(t, w, i, row, g, J);
  if (!s.pore_on) return;
  // the blocking plane: pore_dir . O_n <= offset, i.e. offset - pore_dir . O_n >= 0
  g[row] = s.pore_offset - s.pore_dir.dot(w.O[t.n].head<2>());
  if (J)
    detail::constraint_row(t, w, t.n, Vec3(-s.pore_dir.x(), -s.pore_dir.y(), 0.0), Vec3::Zero(), 0.0, 0.0,
                           *J, row);
}

}  // namespace

double evaluate(const Tuft& t, const BrushState& s, Workspace& w, const VecX& x, VecX* grad, VecX* g,
                MatX* J) {
  // the accepted trial point comes back here with its derivatives asked for: its geometry is
  // still the last kinematics() (root and root frame only change in prepare_frame, which
  // recomputes it)
  if (x != w.x_eval) kinematics(t, s, x, w);
  double E = 0.0;
  if (grad) {
    grad->setZero();
    detail::clear_node_grads(t, w);
  }
  spine_springs(t, s, x, grad, E);
  lateral_springs(t, s, x, grad, E);
  lateral_bends(t, w, grad != nullptr, E);
  friction(t, s, w, grad != nullptr, E);
  adhesion(t, s, w, grad != nullptr, E);
  if (grad) detail::chain(t, w, *grad);
  if (g) constraints(t, s, w, *g, J);
  return E;
}

}  // namespace brushwork
