// The tuft: forward kinematics, incremental potential, constraints and their analytic
// derivatives (seed "Brush geometry", "Brush dynamics", "Energy Functions", "Pore resistance").
// The SQP solver that minimises it lives in sqp.cpp.
#include "brushwork/brush.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "power.hpp"

namespace brushwork {

using power::dpow_half;
using power::dpowm;
using power::pow_half;
using power::powm;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
// rad^2: the bend term of the spread heuristic S saturates at this (see energy(), stretch springs)
constexpr double kSpreadBend2 = 4.0;
constexpr double kPlasticDeadband = 1e-4;  // rad
constexpr double kThetaEps = 1e-3;  // rad: the straight-skeleton trick (seed "Energy minimization problems")

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

std::string num(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}

void check_finite(const char* field, double v, double lo, double hi) {
  if (!std::isfinite(v) || v < lo || v > hi)
    throw std::invalid_argument(std::string("Pose.") + field + " = " + num(v) +
                                " is out of range [" + num(lo) + ", " + num(hi) + "]");
}

}  // namespace

void Pose::validate() const {
  check_finite("position[0] (x, mm)", position.x(), -1e6, 1e6);
  check_finite("position[1] (y, mm)", position.y(), -1e6, 1e6);
  check_finite("position[2] (z, mm)", position.z(), -1e6, 1e6);
  check_finite("tilt_deg", tilt_deg, 0.0, 89.9);
  check_finite("azimuth_deg", azimuth_deg, -1e6, 1e6);
  check_finite("twist_deg", twist_deg, -1e6, 1e6);
}

Brush::Brush(const BrushModel& model) : model_(model) {
  model_.validate();
  n_ = model_.n_segments;
  nx_ = 5 * n_;
  m_exp_ = model_.exponent;
  shrink_ = model_.collision_shrink;
  f_scale_ = model_.bend_stiffness;
  mmax_ = n_ + 1;

  // constants: lengths l_j, radii r_i and r_lat, spring constants kappa (root stiffer than tip)
  len_ = model_.segment_lengths();
  r0_ = model_.node_radii();
  rlat_ = model_.lateral_radius_fraction * r0_;
  kb_ = model_.bend_kappa();
  kt_ = model_.twist_stiffness * kb_;
  // the lateral line's own rotation psi_i gets a weak restoring spring so it stays determined in
  // free air (in contact the constraints and lateral bend springs decide it)
  kpsi_.resize(n_ + 1);
  for (int i = 0; i <= n_; ++i)
    kpsi_[i] = 0.1 * std::max(model_.twist_stiffness, 0.1) * kb_[std::min(i, n_ - 1)];
  ks_ = model_.stretch_stiffness;
  // lateral bend springs follow the bend springs' hair-count law (model.cpp, stiffness_profile):
  // the spring at node i stiffens the tuft's sides like joint i's spring its spine.  (n+1,) N*mm
  {
    const VecX prof = model_.stiffness_profile();
    klb_.resize(n_ + 1);
    for (int i = 0; i <= n_; ++i) klb_[i] = model_.lateral_bend_stiffness * prof[std::min(i, n_ - 1)];
  }
  eta_ = model_.internal_friction;

  // active variables: everything but the stretches when lateral spreading is off
  for (int j = 0; j < 2 * n_; ++j) active_.push_back(j);
  for (int i = 1; i <= n_; ++i) {
    const int b = 2 * n_ + 3 * (i - 1);
    active_.push_back(b);
    if (model_.lateral_spreading) {
      active_.push_back(b + 1);
      active_.push_back(b + 2);
    }
  }
  const int na = static_cast<int>(active_.size());

  // size every workspace once
  O_.assign(n_ + 1, Vec3::Zero());
  u_ = w_ = nrm_ = gO_ = gu_ = tau_ = O_;
  aphi_.assign(n_, Vec3::Zero());
  ath_ = aphi_;
  F_.assign(n_, Mat3::Identity());
  Q_ = F_;
  d_plus_.resize(n_ + 1);
  d_minus_.resize(n_ + 1);
  c_.resize(n_ + 1);
  gdp_.resize(n_ + 1);
  gdm_.resize(n_ + 1);
  prev_pts_.assign(3 * (n_ + 1), Vec3::Zero());
  R_.assign(3 * (n_ + 1), 0.0);
  txy_.assign(n_ + 1, Eigen::Vector2d::Zero());
  p_ = VecX::Zero(n_ + 1);
  c_prev_ = r0_;
  wetness = VecX::Ones(n_ + 1);
  lambda_ = VecX::Zero(mmax_);
  R_relaxed_ = VecX::Zero(n_);
  save_.x = save_.x_prev = save_.rest = VecX::Zero(nx_);
  save_.lambda = VecX::Zero(mmax_);

  for (VecX* v : {&xf_trial_, &gf_, &gf_new_, &x_eval_}) v->resize(nx_);
  for (VecX* v : {&za_, &zt_, &gact_, &gact_new_, &s_, &yv_, &r_, &Hr_, &Bs_, &tmp_, &h0_})
    v->resize(na);
  step_.resize(na);
  for (VecX* v : {&g_, &g_new_, &gtrial_, &q_, &lam_, &lam_f_, &lam_old_, &qp_grad_, &rhs_})
    v->resize(mmax_);
  J_.resize(mmax_, nx_);
  Jact_.resize(mmax_, na);
  Jact_new_.resize(mmax_, na);
  HJt_.resize(na, mmax_);
  M_.resize(mmax_, mmax_);
  Mff_.resize(mmax_, mmax_);
  qp_state_.assign(mmax_, 0);
  H_ = MatX::Identity(na, na);

  // rest shape of the lateral polylines (the tuft profile bends them even when unstrained):
  // t_i - t_{i-1} of the straight brush, in each node's lateral frame
  kinematics(VecX::Zero(nx_));
  for (int side = 0; side < 2; ++side) {
    const double sg = side == 0 ? 1.0 : -1.0;
    lb_rest_[side].assign(n_ + 1, Vec3::Zero());
    for (int i = 1; i < n_; ++i) {
      const VecX& d = side == 0 ? d_plus_ : d_minus_;
      const Vec3 t0 = (O_[i] + sg * d[i] * u_[i] - O_[i - 1] - sg * d[i - 1] * u_[i - 1]).normalized();
      const Vec3 t1 = (O_[i + 1] + sg * d[i + 1] * u_[i + 1] - O_[i] - sg * d[i] * u_[i]).normalized();
      const Vec3 v = t1 - t0;
      lb_rest_[side][i] = Vec3(v.dot(w_[i]), v.dot(u_[i]), v.dot(nrm_[i]));
    }
  }
  reset();
}

void Brush::reset() {
  // straight and unstrained: zero angles and stretches, rest shifts forgotten; then the
  // straight-skeleton trick gives the bend angles a minimal value so gradients exist
  x_ = VecX::Zero(nx_);
  x_prev_ = x_;
  rest_ = VecX::Zero(nx_);
  have_hessian_ = false;
  have_h_touching_ = false;
  hessian_contacts_ = -1;
  touched_since_reset_ = false;
  have_prev_positions_ = false;
  pore_on_prev_ = false;
  lambda_.setZero();
  R_relaxed_.setZero();
  p_.setZero();
  c_prev_ = r0_;
  nu_ = 0.0;
  kinematics(x_);
  stats_ = StepStats();
  // per-step traces keep their capacity, so solve() does not allocate after this
  stats_.merit_before.reserve(model_.q_max + 8);
  stats_.merit_after.reserve(model_.q_max + 8);
  stats_.step_sizes.reserve(model_.q_max + 8);
  stats_.kkt_trace.reserve(model_.q_max + 8);
}

// ---------------------------------------------------------------------------------------------
// forward kinematics (seed Figure 2): F_j = F_{j-1} Rz(phi_j) Ry(theta_j) is the frame of
// segment j (its z axis the segment direction), O_{j+1} = O_j + l_j F_j e_z.  The section
// Omega_i lies in the joint-bisecting plane, frame G_i = F_{i-1} Rz(phi_i) Ry(theta_i / 2); its
// lateral line u_i = G_i Rz(psi_i) e_y starts perpendicular to both segments.
void Brush::kinematics(const VecX& x) {
  x_eval_ = x;
  O_[0] = root_;
  for (int j = 0; j < n_; ++j) {
    const Mat3& prev = j == 0 ? R0_ : F_[j - 1];
    aphi_[j] = prev.col(2);
    turn_z(prev, std::cos(x[2 * j + 1]), std::sin(x[2 * j + 1]), Q_[j]);
    turn_y(Q_[j], std::cos(x[2 * j]), std::sin(x[2 * j]), F_[j]);
    ath_[j] = Q_[j].col(1);
    O_[j + 1] = O_[j] + len_[j] * F_[j].col(2);
  }
  Mat3 G;
  for (int i = 0; i <= n_; ++i) {
    if (i < n_) turn_y(Q_[i], std::cos(0.5 * x[2 * i]), std::sin(0.5 * x[2 * i]), G);
    else G = F_[n_ - 1];
    double cp = 1.0, sp = 0.0;  // psi_0 = 0: the root's lateral line is G_0 e_y
    if (i > 0) {
      const double psi = x[2 * n_ + 3 * (i - 1)];
      cp = std::cos(psi);
      sp = std::sin(psi);
    }
    u_[i] = cp * G.col(1) - sp * G.col(0);
    w_[i] = cp * G.col(0) + sp * G.col(1);
    nrm_[i] = G.col(2);
    // lateral distances a = r_i - r_lat + delta^2 (so that the unstretched section is the
    // circle of radius r_i) and the minor radius from area conservation c = r^2 / ((a+b)/2 + r_lat)
    double dp = r0_[i] - rlat_[i], dm = dp;
    if (i > 0) {
      const double ep = x[2 * n_ + 3 * (i - 1) + 1], em = x[2 * n_ + 3 * (i - 1) + 2];
      dp += ep * ep;
      dm += em * em;
    }
    d_plus_[i] = dp;
    d_minus_[i] = dm;
    c_[i] = r0_[i] * r0_[i] / (0.5 * (dp + dm) + rlat_[i]);
  }
}

void Brush::clear_node_grads() {
  for (int i = 0; i <= n_; ++i) gO_[i].setZero(), gu_[i].setZero(), tau_[i].setZero();
  gdp_.setZero();
  gdm_.setZero();
}

// Turn node-level gradients (d/dO_i, d/du_i, d/da_i, d/db_i) into d/dx.  A joint angle rotates
// everything below it about an axis a through O_k, so d/dq = a . sum_j [(O_j - O_k) x gO_j +
// u_j x gu_j]; suffix sums make the whole map O(n).  theta_k turns its own section's frame by
// half its angle (the bisecting plane), phi_k by all of it.
void Brush::chain(VecX& gx) const {
  Vec3 T = Vec3::Zero(), Gs = Vec3::Zero();
  for (int k = n_ - 1; k >= 0; --k) {
    const int j = k + 1;
    T += O_[j].cross(gO_[j]) + u_[j].cross(gu_[j]) + tau_[j];
    Gs += gO_[j];
    const Vec3 base = T - O_[k].cross(Gs);
    const Vec3 lat = u_[k].cross(gu_[k]) + tau_[k];
    gx[2 * k + 1] += aphi_[k].dot(base + lat);
    gx[2 * k] += ath_[k].dot(base + 0.5 * lat);
  }
  for (int i = 1; i <= n_; ++i) {
    const int b = 2 * n_ + 3 * (i - 1);
    gx[b] += nrm_[i].dot(u_[i].cross(gu_[i]) + tau_[i]);  // dv/dpsi = n x v for v in the lateral frame
    gx[b + 1] += gdp_[i] * 2.0 * x_eval_[b + 1];
    gx[b + 2] += gdm_[i] * 2.0 * x_eval_[b + 2];
  }
}

// One row of the constraint Jacobian, for a constraint that depends on node i alone (through
// gO = d/dO_i, gu = d/du_i, gdp, gdm = d/da_i, d/db_i): chain() with every other node's
// gradient zero.  The joints below node i do not move it, so their entries are zero; a joint
// k < i turns O_i and u_i about its axis through O_k (base = O_i x gO + u_i x gu - O_k x gO),
// the joint k = i turns u_i by half its bend (the bisecting plane) and all of its turn.  O(i).
void Brush::constraint_row(int i, const Vec3& gO, const Vec3& gu, double gdp, double gdm,
                           MatX& J, int row) const {
  J.row(row).setZero();
  const Vec3 lat = u_[i].cross(gu);
  if (i < n_) {
    J(row, 2 * i + 1) = aphi_[i].dot(lat);
    J(row, 2 * i) = ath_[i].dot(0.5 * lat);
  }
  const Vec3 T = O_[i].cross(gO) + lat;
  for (int k = i - 1; k >= 0; --k) {
    const Vec3 base = T - O_[k].cross(gO);
    J(row, 2 * k + 1) = aphi_[k].dot(base);
    J(row, 2 * k) = ath_[k].dot(base);
  }
  if (i > 0) {
    const int b = 2 * n_ + 3 * (i - 1);
    J(row, b) = nrm_[i].dot(lat);
    J(row, b + 1) = gdp * 2.0 * x_eval_[b + 1];
    J(row, b + 2) = gdm * 2.0 * x_eval_[b + 2];
  }
}

// ---------------------------------------------------------------------------------------------
// the incremental potential (seed "Energy Functions") and the constraints at the full vector x.
// grad: (5n,) dE/dx; g: (m,) constraint values in mm; J: (m, 5n) their Jacobian.
double Brush::evaluate(const VecX& x, VecX* grad, VecX* g, MatX* J) {
  // the accepted trial point comes back here with its derivatives asked for: its geometry is
  // still the last kinematics() (root and root frame only change in begin_frame, which
  // recomputes it)
  if (x != x_eval_) kinematics(x);
  const double m = m_exp_;
  double E = 0.0;
  if (grad) {
    grad->setZero();
    clear_node_grads();
  }
  VecX* gx = grad;

  // bend and twist springs kappa_i |theta_i - rho_i|^m with the plastic rest shift rho, no twist
  // spring at the root; internal friction: the same form on the change since the last frame
  for (int j = 0; j < n_; ++j) {
    const int it = 2 * j, ip = 2 * j + 1;
    const double eb = x[it] - rest_[it], fb = x[it] - x_prev_[it];
    E += kb_[j] * (powm(eb, m) + eta_ * powm(fb, m));
    if (gx) (*gx)[it] += kb_[j] * (dpowm(eb, m) + eta_ * dpowm(fb, m));
    const double ft = x[ip] - x_prev_[ip];
    E += kt_[j] * eta_ * powm(ft, m);
    if (gx) (*gx)[ip] += kt_[j] * eta_ * dpowm(ft, m);
    if (j > 0) {
      const double et = x[ip] - rest_[ip];
      E += kt_[j] * powm(et, m);
      if (gx) (*gx)[ip] += kt_[j] * dpowm(et, m);
    }
  }

  // lateral line springs on psi_i, and stretch springs kappa |delta^2 - S(theta_i, p_i)|^m with
  // S = spread_gain r_i p_i (1 + spread_bend_gain b(theta_i)) growing as the segment is pressed
  // and bent (the seed leaves S a heuristic of theta_i and p_i).  b = t^2 tanh(theta^2 / t^2)
  // with t = 2 rad: theta^2 within 2% up to 0.9 rad and 17% at 1.8 (a deep press folds a tip
  // joint that far), never more than 4 rad^2.  With b = theta^2 the spread had no bound: a
  // stretch spring longer than S pulled its joint to bend further, which raised S further, and
  // over capped frames after a lift tip joints wound to 3-11 rad (11% of kai's frames in the
  // air past 1.5 rad) and a lateral line to 83 rad
  for (int i = 1; i <= n_; ++i) {
    const int b = 2 * n_ + 3 * (i - 1);
    const double ep = x[b], fp = x[b] - x_prev_[b];
    E += kpsi_[i] * (powm(ep, m) + eta_ * powm(fp, m));
    if (gx) (*gx)[b] += kpsi_[i] * (dpowm(ep, m) + eta_ * dpowm(fp, m));
    if (!model_.lateral_spreading) continue;
    const int jt = 2 * std::min(i, n_ - 1);
    const double th = x[jt];
    const double Sbase = model_.spread_gain * r0_[i] * p_[i];
    const double sat = std::tanh(th * th / kSpreadBend2);
    const double bend = kSpreadBend2 * sat;                                  // b(theta), rad^2
    const double dbend = 2.0 * th * (1.0 - sat * sat);                       // db/dtheta, rad
    const double S = Sbase * (1.0 + model_.spread_bend_gain * bend);
    for (int s = 1; s <= 2; ++s) {
      const double dl = x[b + s], dlp = x_prev_[b + s];
      const double e = dl * dl - S, f = dl * dl - dlp * dlp;
      E += ks_ * (powm(e, m) + eta_ * powm(f, m));
      if (gx) {
        (*gx)[b + s] += ks_ * (dpowm(e, m) + eta_ * dpowm(f, m)) * 2.0 * dl;
        (*gx)[jt] -= ks_ * dpowm(e, m) * Sbase * model_.spread_bend_gain * dbend;
      }
    }
  }

  // bend springs between consecutive lateral nodes P_i = O_i +- d_i u_i, on each side:
  // kappa_lb |(t_i - t_{i-1}) - r_i|^m with t the unit edge directions (|t_i - t_{i-1}| ~ the
  // angle between them) and r_i their rest difference carried in node i's lateral frame
  if (model_.lateral_bend_stiffness > 0.0) {
    for (int side = 0; side < 2; ++side) {
      const double sg = side == 0 ? 1.0 : -1.0;
      const VecX& d = side == 0 ? d_plus_ : d_minus_;
      VecX& gd = side == 0 ? gdp_ : gdm_;
      Vec3 t_prev = Vec3::Zero();
      double len_prev = 1.0;
      for (int i = 0; i < n_; ++i) {
        const Vec3 Pa = O_[i] + sg * d[i] * u_[i], Pb = O_[i + 1] + sg * d[i + 1] * u_[i + 1];
        const Vec3 e = Pb - Pa;
        const double le = std::max(e.norm(), 1e-12);
        const Vec3 t = e / le;
        if (i > 0) {
          const Vec3& rl = lb_rest_[side][i];
          const Vec3 rv = rl.x() * w_[i] + rl.y() * u_[i] + rl.z() * nrm_[i];
          const Vec3 v = t - t_prev - rv;
          const double vv = v.squaredNorm();
          E += klb_[i] * pow_half(vv, m);
          if (gx) {
            const Vec3 dv = klb_[i] * dpow_half(vv, m) * v;
            // dt/de = (I - t t^T) / |e|
            const Vec3 ge = (dv - t * t.dot(dv)) / le;
            const Vec3 gep = -(dv - t_prev * t_prev.dot(dv)) / len_prev;
            // e_i = P_{i+1} - P_i, e_{i-1} = P_i - P_{i-1}; P = O + sg d u
            auto add_point = [&](int k, const Vec3& gP) {
              gO_[k] += gP;
              gu_[k] += sg * d[k] * gP;
              gd[k] += sg * gP.dot(u_[k]);
            };
            add_point(i + 1, ge);
            add_point(i, gep - ge);
            add_point(i - 1, -gep);
            tau_[i] += rv.cross(-dv);  // r_i turns with node i's lateral frame
          }
        }
        t_prev = t;
        len_prev = le;
      }
    }
  }

  // external friction mu R_i x_i for the frozen contact set, x_i the dragged distance on the
  // paper since the last frame, mu modulated by the hair direction: x_i = sqrt(D^T A D + eps^2)
  // - eps with A = mu_side^2 I + (mu_along^2 - mu_side^2) t t^T, t the unnormalised horizontal
  // projection of the segment above the node (a vertical segment drags isotropically)
  {
    const double ma2 = model_.friction_along * model_.friction_along;
    const double ms2 = model_.friction_side * model_.friction_side;
    const double eps = model_.friction_smoothing;
    for (int i = 1; i <= n_; ++i) {
      const Eigen::Vector2d& t = txy_[i];
      for (int k = 0; k < 3; ++k) {
        const double R = R_[3 * i + k];
        if (R <= 0.0) continue;
        const double sg = k == 1 ? 1.0 : -1.0;
        const double dk = k == 1 ? d_plus_[i] : d_minus_[i];
        const Vec3 P = k == 0 ? O_[i] : Vec3(O_[i] + sg * dk * u_[i]);
        const Eigen::Vector2d D = (P - prev_pts_[3 * i + k]).head<2>();
        const Eigen::Vector2d AD = ms2 * D + (ma2 - ms2) * t * t.dot(D);
        const double root = std::sqrt(D.dot(AD) + eps * eps);
        E += R * (root - eps);
        if (gx) {
          const Vec3 gP(R * AD.x() / root, R * AD.y() / root, 0.0);
          gO_[i] += gP;
          if (k > 0) {
            gu_[i] += sg * dk * gP;
            (k == 1 ? gdp_ : gdm_)[i] += sg * gP.dot(u_[i]);
          }
        }
      }
    }
  }
  if (gx) chain(*gx);

  // constraints: g_i = lowest point of the shrunk section Phi_i's ellipsoid (Omega_i turned about
  // its major axis, scaled by collision_shrink) >= 0; then the pore plane
  if (g) {
    int row = 0;
    if (model_.collision) {
      for (int i = 1; i <= n_; ++i, ++row) {
        const double uz = u_[i].z();
        const bool plus = uz < 0.0;  // the +u half reaches down when u points down
        const double A = (plus ? d_plus_[i] : d_minus_[i]) + rlat_[i], c = c_[i];
        const double h = std::sqrt(std::max(A * A * uz * uz + c * c * (1.0 - uz * uz), 1e-300));
        (*g)[row] = O_[i].z() - shrink_ * h;
        if (J) {
          const double gA = -shrink_ * A * uz * uz / h;
          const double gc = -shrink_ * c * (1.0 - uz * uz) / h;
          const double dc = -0.5 * c * c / (r0_[i] * r0_[i]);  // dc/da = dc/db
          constraint_row(i, Vec3(0.0, 0.0, 1.0), Vec3(0.0, 0.0, -shrink_ * (A * A - c * c) * uz / h),
                         gc * dc + (plus ? gA : 0.0), gc * dc + (plus ? 0.0 : gA), *J, row);
        }
      }
    }
    if (pore_on_) {
      // the blocking plane: pore_dir . O_n <= offset, i.e. offset - pore_dir . O_n >= 0
      (*g)[row] = pore_offset_ - pore_dir_.dot(O_[n_].head<2>());
      if (J)
        constraint_row(n_, Vec3(-pore_dir_.x(), -pore_dir_.y(), 0.0), Vec3::Zero(), 0.0, 0.0, *J, row);
    }
  }
  return E;
}

// ---------------------------------------------------------------------------------------------
// frame set-up: root pose, plasticity, straight-skeleton trick, frozen contact set
void Brush::begin_frame(const Pose& pose) {
  pose.validate();
  pose_ = pose;

  // root frame: e3 = -(handle axis) is the unbent tuft's direction; e1 lies in the vertical
  // plane through the handle (so bending with phi_0 = 0 keeps the lateral lines horizontal),
  // continuous as the tilt goes to 0; twist turns (e1, e2) about e3
  const double t = pose.tilt_deg * kDeg, az = pose.azimuth_deg * kDeg, tw = pose.twist_deg * kDeg;
  const Vec3 e3(-std::sin(t) * std::cos(az), -std::sin(t) * std::sin(az), -std::cos(t));
  const Vec3 e1(-std::cos(t) * std::cos(az), -std::cos(t) * std::sin(az), std::sin(t));
  const Vec3 e2 = e3.cross(e1);
  R0_.col(0) = std::cos(tw) * e1 + std::sin(tw) * e2;
  R0_.col(1) = -std::sin(tw) * e1 + std::cos(tw) * e2;
  R0_.col(2) = e3;

  // the ferrule cannot enter the paper: hold the root where its (shrunk) section touches it
  root_ = pose.position;
  const double zmin =
      shrink_ * r0_[0] * std::sqrt(std::max(0.0, 1.0 - e3.z() * e3.z())) + 1e-9 * model_.tuft_length;
  root_clamped_ = root_.z() < zmin;
  if (root_clamped_) root_.z() = zmin;

  // plasticity (seed "Brush plasticity"): rest angles rho = clamp(theta', -alpha, alpha).  rho
  // moves only when that target has moved by more than kPlasticDeadband: the plastic set has
  // its own static friction, so a brush held still settles instead of creeping forever
  x_prev_ = x_;
  const double alpha = model_.plasticity_alpha * kDeg;
  auto shift = [&](int k, double target) {
    if (std::abs(target - rest_[k]) > kPlasticDeadband || alpha == 0.0) rest_[k] = target;
  };
  for (int j = 0; j < n_; ++j) {
    shift(2 * j, std::clamp(x_[2 * j], -alpha, alpha));
    shift(2 * j + 1, j > 0 ? std::clamp(x_[2 * j + 1], -alpha, alpha) : 0.0);
  }

  // until the brush first touches, phi_0 keeps the bending plane vertical (seed "Real-time
  // simulation": the lateral lines start horizontal; upright, the angle does not matter)
  if (!touched_since_reset_) x_[1] = x_prev_[1] = -tw;
  kinematics(x_);

  // lowest point of the outer surface Omega_i (unshrunk) at node i
  auto outer_low = [&](int i) {
    const double uz = u_[i].z();
    const double A = (uz < 0 ? d_plus_[i] : d_minus_[i]) + rlat_[i];
    return O_[i].z() - std::sqrt(A * A * uz * uz + c_[i] * c_[i] * (1.0 - uz * uz));
  };

  // straight-skeleton trick (seed "Energy minimization problems"): a straight spine about to be
  // pressed gets minimal bend angles, or no gradient could start the bending; likewise a
  // stretch delta = 0 (a saddle of |delta^2 - S|^m, where d/d delta vanishes) gets a minimal
  // value once its node is under the paper.  In free air nothing is touched, so a brush at rest
  // stays exactly at rest.
  bool straight = true, kicked = false;
  for (int j = 0; j < n_; ++j) straight = straight && std::abs(x_[2 * j]) < 1e-7;
  for (int i = 1; i <= n_; ++i) {
    if (outer_low(i) >= 0.0) continue;
    if (straight) {
      for (int j = 0; j < n_; ++j) x_[2 * j] = x_prev_[2 * j] = kThetaEps;
      straight = false;
      kicked = true;
    }
    if (model_.lateral_spreading) {
      const double kick = std::sqrt(0.01 * r0_[i]);  // sqrt(mm): delta^2 = 1% of r_i
      for (int s = 1; s <= 2; ++s) {
        double& dl = x_[2 * n_ + 3 * (i - 1) + s];
        if (std::abs(dl) < kick) {
          dl = x_prev_[2 * n_ + 3 * (i - 1) + s] = kick;
          kicked = true;
        }
      }
    }
  }
  if (kicked) kinematics(x_);
  if (!have_prev_positions_) {
    for (int i = 0; i <= n_; ++i) {
      prev_pts_[3 * i] = O_[i];
      prev_pts_[3 * i + 1] = O_[i] + d_plus_[i] * u_[i];
      prev_pts_[3 * i + 2] = O_[i] - d_minus_[i] * u_[i];
    }
    have_prev_positions_ = true;
  }

  // frozen contact set at the first iterate: a node touches when its height minus its effective
  // radius is below the paper (r_sp = c of the last frame, r_lat a fraction of it); p_i is the
  // proportion of the segment above node i whose surface is under the paper
  // p_i is measured on the unstretched section (radius r_i in the section plane), not on the
  // spread one: measured on the spread surface, spreading (which flattens c) would lower p_i and
  // so undo itself next frame, a period-2 cycle between frames
  auto rest_low = [&](int i) {
    return O_[i].z() - r0_[i] * std::sqrt(std::max(0.0, 1.0 - nrm_[i].z() * nrm_[i].z()));
  };
  contacts_ = 0;
  bool tip_touch = false;
  double h_above = rest_low(0);
  for (int i = 1; i <= n_; ++i) {
    const double h = rest_low(i);
    double p_new;
    if (h_above < 0 && h < 0) p_new = 1.0;
    else if (h_above >= 0 && h >= 0) p_new = 0.0;
    else p_new = (h < 0 ? -h : -h_above) / std::abs(h - h_above);
    h_above = h;
    // p_i is lagged like R_i (it comes from the first iterate, last frame's shape) and relaxed
    // the same way: p high spreads the section, the spread tuft lifts, p falls, and without
    // relaxation the footprint flips between two sizes every other frame
    p_[i] += model_.contact_relaxation * (p_new - p_[i]);

    const double rsp = c_prev_[i], rl = model_.lateral_radius_fraction * c_prev_[i];
    const bool touch[3] = {O_[i].z() - rsp < 0.0,
                           (O_[i] + d_plus_[i] * u_[i]).z() - rl < 0.0,
                           (O_[i] - d_minus_[i] * u_[i]).z() - rl < 0.0};
    const int count = touch[0] + touch[1] + touch[2];
    // normal reaction R: last frame's contact force on this section (the seed's lagged force),
    // relaxed R <- R + omega (lambda - R): with omega = 1 a large force makes the tip stick, the
    // stuck tip unloads the section, the small force lets it slip, and the footprint flips
    // between two sizes every other frame (a period-2 cycle of the lagged iteration); omega
    // 1/2 damps it.  Plus wet adhesion.
    const double lam = (model_.collision && i - 1 < lambda_.size()) ? std::max(lambda_[i - 1], 0.0) : 0.0;
    double& Rr = R_relaxed_[i - 1];
    Rr += model_.contact_relaxation * (lam - Rr);
    const double total = Rr + model_.wet_adhesion * p_[i] * std::clamp(wetness[i], 0.0, 1.0);
    for (int k = 0; k < 3; ++k) R_[3 * i + k] = (touch[k] && count > 0) ? total / count : 0.0;
    contacts_ += count;
    if (i == n_ && count > 0) tip_touch = true;
    txy_[i] = F_[i - 1].col(2).head<2>();
  }

  // pore resistance (seed "Pore resistance"): a vertical blocking plane normal to the tip
  // segment's projection, lead L = a t + b u + c ahead of the tip, t = max(|beta| - gamma, 0)
  pore_on_ = false;
  const Vec3 tip = F_[n_ - 1].col(2);
  if (model_.pore_resistance && model_.collision && tip_touch && tip.head<2>().norm() > 1e-6) {
    const double beta = std::acos(std::min(1.0, std::abs(tip.z())));
    const double tt = std::max(beta - model_.pore_gamma * kDeg, 0.0);
    const double up = std::max(lambda_[n_ - 1], 0.0);
    const double L = model_.pore_a * tt + model_.pore_b * up + model_.pore_c;
    // the pores hold the plane where they trapped the tip: a tip pushed forward meets it,
    // a trailing tip (a normal drag) draws it along; it is released when the tip lifts
    const bool was_on = pore_on_prev_;
    pore_dir_ = tip.head<2>().normalized();
    pore_offset_ = pore_dir_.dot(prev_pts_[3 * n_].head<2>()) + L;
    if (was_on) pore_offset_ = std::min(pore_offset_, pore_dir_.dot(pore_anchor_));
    pore_anchor_ = prev_pts_[3 * n_].head<2>() +
                   (pore_offset_ - pore_dir_.dot(prev_pts_[3 * n_].head<2>())) * pore_dir_;
    pore_on_ = true;
  }
  pore_on_prev_ = pore_on_;
  const int m_old = m_;
  m_ = (model_.collision ? n_ : 0) + (pore_on_ ? 1 : 0);
  if (m_ > m_old && pore_on_) lambda_[m_ - 1] = 0.0;  // the plane starts without a force
  touched_since_reset_ = touched_since_reset_ || contacts_ > 0;
}

void Brush::end_frame() {
  kinematics(x_);
  for (int i = 0; i <= n_; ++i) {
    prev_pts_[3 * i] = O_[i];
    prev_pts_[3 * i + 1] = O_[i] + d_plus_[i] * u_[i];
    prev_pts_[3 * i + 2] = O_[i] - d_minus_[i] * u_[i];
  }
  c_prev_ = c_;
}

void Brush::prepare(const Pose& pose) { begin_frame(pose); }

// ---------------------------------------------------------------------------------------------
// the frame problem in active variables, for tests and other solvers
void Brush::gather(const VecX& full, VecX& act) const {
  for (size_t k = 0; k < active_.size(); ++k) act[k] = full[active_[k]];
}
void Brush::scatter(const VecX& act, VecX& full) const {
  for (size_t k = 0; k < active_.size(); ++k) full[active_[k]] = act[k];
}

VecX Brush::variables() const {
  VecX z(active_.size());
  gather(x_, z);
  return z;
}

void Brush::set_variables(const VecX& z) {
  if (z.size() != static_cast<int>(active_.size()))
    throw std::invalid_argument("variables: expected " + std::to_string(active_.size()) +
                                " values, got " + std::to_string(z.size()));
  for (int k = 0; k < z.size(); ++k)
    if (!std::isfinite(z[k]))
      throw std::invalid_argument("variables: " + variable_names()[k] + " = " + num(z[k]) +
                                  " is not finite");
  scatter(z, x_);
  end_frame();
}

std::vector<std::string> Brush::variable_names() const {
  std::vector<std::string> names;
  for (int idx : active_) {
    if (idx < 2 * n_) {
      names.push_back((idx % 2 == 0 ? "theta_" : "phi_") + std::to_string(idx / 2));
    } else {
      const int i = (idx - 2 * n_) / 3 + 1, k = (idx - 2 * n_) % 3;
      names.push_back((k == 0 ? "psi_" : k == 1 ? "delta+_" : "delta-_") + std::to_string(i));
    }
  }
  return names;
}

namespace {
void check_size(const VecX& z, size_t n) {
  if (z.size() != static_cast<int>(n))
    throw std::invalid_argument("expected " + std::to_string(n) + " variables, got " +
                                std::to_string(z.size()));
}
}  // namespace

double Brush::energy(const VecX& z) {
  check_size(z, active_.size());
  VecX full = x_;
  scatter(z, full);
  const double E = evaluate(full, nullptr, nullptr, nullptr);
  kinematics(x_);
  return E;
}

VecX Brush::energy_gradient(const VecX& z) {
  check_size(z, active_.size());
  VecX full = x_, gfull(nx_), ga(active_.size());
  scatter(z, full);
  evaluate(full, &gfull, nullptr, nullptr);
  gather(gfull, ga);
  kinematics(x_);
  return ga;
}

VecX Brush::constraints(const VecX& z) {
  check_size(z, active_.size());
  VecX full = x_, g(mmax_);
  scatter(z, full);
  evaluate(full, nullptr, &g, nullptr);
  kinematics(x_);
  return g.head(m_);
}

MatX Brush::constraint_jacobian(const VecX& z) {
  check_size(z, active_.size());
  VecX full = x_, g(mmax_);
  MatX J(mmax_, nx_);
  scatter(z, full);
  evaluate(full, nullptr, &g, &J);
  MatX Ja(m_, active_.size());
  for (size_t k = 0; k < active_.size(); ++k) Ja.col(k) = J.col(active_[k]).head(m_);
  kinematics(x_);
  return Ja;
}

// ---------------------------------------------------------------------------------------------
// geometry of the current state
Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> Brush::skeleton() const {
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> s(n_ + 1, 3);
  for (int i = 0; i <= n_; ++i) s.row(i) = O_[i].transpose();
  return s;
}

Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> Brush::lateral_nodes() const {
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> s(2 * (n_ + 1), 3);
  for (int i = 0; i <= n_; ++i) {
    s.row(2 * i) = (O_[i] + d_plus_[i] * u_[i]).transpose();
    s.row(2 * i + 1) = (O_[i] - d_minus_[i] * u_[i]).transpose();
  }
  return s;
}

std::vector<Section> Brush::sections() const {
  std::vector<Section> out(n_ + 1);
  for (int i = 0; i <= n_; ++i) {
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
    const double wz = w_[i].z();
    double shift = (r0_[i] - c_[i]) * std::abs(wz);              // mm along the downward w
    if (shift * std::abs(wz) > O_[i].z()) shift = std::max(0.0, O_[i].z()) / std::max(std::abs(wz), 1e-12);
    s.center = O_[i] - (wz >= 0.0 ? 1.0 : -1.0) * shift * w_[i];
    s.u = u_[i];
    s.w = w_[i];
    s.n = nrm_[i];
    s.a_plus = d_plus_[i] + rlat_[i];  // major radii a + r_lat, b + r_lat
    s.a_minus = d_minus_[i] + rlat_[i];
    s.c = c_[i];
  }
  return out;
}

SurfaceMesh Brush::surface_mesh(const MeshOptions& opt) const {
  return sweep_surface(sections(), opt);
}

Loops Brush::footprint(const MeshOptions& opt) const { return footprint_loops(surface_mesh(opt)); }

double Brush::footprint_area(const MeshOptions& opt) const { return loops_area(footprint(opt)); }

VecX Brush::section_heights() const {
  VecX h(n_);
  for (int i = 1; i <= n_; ++i) {
    const double uz = u_[i].z();
    const double A = (uz < 0 ? d_plus_[i] : d_minus_[i]) + rlat_[i];
    h[i - 1] = O_[i].z() - shrink_ * std::sqrt(A * A * uz * uz + c_[i] * c_[i] * (1.0 - uz * uz));
  }
  return h;
}

}  // namespace brushwork
