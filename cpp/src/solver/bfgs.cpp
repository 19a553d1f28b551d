// The BFGS matrix L_xx of the SQP, kept as its inverse H (seed "Real-time simulation"): the
// diagonal start, the damped update, and one carried matrix per regime (touching, in the air).
#include <algorithm>
#include <cmath>
#include <Eigen/Eigenvalues>

#include "../power.hpp"
#include "../tuft/internal.hpp"
#include "bfgs.hpp"

namespace brushwork {
namespace detail {

namespace {

// rad (or mm): the start matrix uses at least the springs' curvature at this strain
constexpr double kCurvatureStrain = 0.2;
// -, a model's twist springs count as at least this fraction of the bend springs at the start
constexpr double kTwistFloor = 0.1;
// -, the stretch's curvature scale: this fraction of r_i
constexpr double kStretchScale = 0.3;
// -, factor of the stretch springs' start curvature, ks 8 |e|^m'' scale^(m-1)
constexpr double kStretchCurvature = 8.0;
// -, Powell's damping: y is blended toward B s when s^T y < this fraction of s^T B s
constexpr double kPowellDamping = 0.2;
constexpr double kPowellBlend = 0.8;  // -, the blend's numerator factor
// -, an update is skipped when r^T s is below this fraction of |r| |s|
constexpr double kCurvatureCos = 1e-16;

// curvature of the separable springs at the state's x, floored (b of H = diag(1/b))
void spring_curvature(const Tuft& t, const BrushState& s, VecX& b) {
  const double m = t.m_exp, eta = t.eta;
  const double floor_p = power::d2powm(kCurvatureStrain, m);
  for (int j = 0; j < t.n; ++j) {
    b[2 * j] = t.kb[j] * std::max(power::d2powm(s.x[2 * j] - s.rest[2 * j], m) +
                                      eta * power::d2powm(s.x[2 * j] - s.x_prev[2 * j], m),
                                  floor_p * (1.0 + eta));
    b[2 * j + 1] = std::max(t.kt[j], kTwistFloor * t.kb[j]) * floor_p * (1.0 + eta);
  }
  for (int i = 1; i <= t.n; ++i) {
    const int k = 2 * t.n + 3 * (i - 1);
    b[k] = t.kpsi[i] * floor_p * (1.0 + eta);
    const double scale = kStretchScale * t.r0[i];
    b[k + 1] = b[k + 2] = t.ks * kStretchCurvature * floor_p * std::pow(scale, m - 1.0) * (1.0 + eta);
  }
}

// friction: sum over contacting nodes of R mu^2 / max(eps, |D|) |a_j x (P - O_j)|_xy^2
void friction_curvature(const Tuft& t, const BrushState& s, const Workspace& w, VecX& b) {
  const double mu2 = std::max(t.model.friction_along, t.model.friction_side);
  for (int i = 1; i <= t.n; ++i)
    for (int k = 0; k < 3; ++k) {
      const double R = s.R[3 * i + k];
      if (R <= 0.0) continue;
      const Vec3 P = detail::touch_point(w, i, k);
      const double drag = (P - s.prev_pts[3 * i + k]).head<2>().norm();
      const double wt = R * mu2 * mu2 / std::max(t.model.friction_smoothing, drag);
      for (int j = 0; j < std::min(i, t.n); ++j) {
        b[2 * j] += wt * w.ath[j].cross(P - w.O[j]).head<2>().squaredNorm();
        b[2 * j + 1] += wt * w.aphi[j].cross(P - w.O[j]).head<2>().squaredNorm();
      }
    }
}

}  // namespace

// H = diag(1/b): b from the separable springs' curvature at x, floored, plus a Gauss-Newton
// estimate of the friction curvature of the contacting nodes (R mu^2 / max(eps, |drag|) times
// the squared horizontal lever arm) so that the first steps of a dragged frame are sane.
void fresh_hessian(const Tuft& t, BrushState& s, Workspace& w) {
  VecX b(t.nx);
  spring_curvature(t, s, b);
  friction_curvature(t, s, w, b);
  s.H.setZero();
  for (size_t k = 0; k < t.active.size(); ++k) s.H(k, k) = 1.0 / b[t.active[k]];
  s.have_hessian = true;
}

// one carried Hessian per regime, touching and in the air.  The touching one holds the stuck
// contacts' friction curvature (~100x the bend springs'), which free air lacks: carried into
// a lift it let a loop's tip segment swing past -4 rad over capped frames and come down on
// the paper again.  So a lift-off keeps it aside and starts the air afresh, and a touch-down
// takes it back (the air's matrix knows nothing of friction either)
void start_hessian(const Tuft& t, BrushState& s, Workspace& w) {
  const bool warm = t.model.warm_hessian;
  if (warm && s.have_hessian && s.hessian_contacts >= 0 && (s.contacts > 0) != (s.hessian_contacts > 0)) {
    if (s.hessian_contacts > 0) {
      s.H_touching = s.H;
      s.have_h_touching = true;
      fresh_hessian(t, s, w);
    } else if (s.have_h_touching) {
      s.H = s.H_touching;
    }
  }
  if (!warm || !s.have_hessian) fresh_hessian(t, s, w);
  s.hessian_contacts = s.contacts;
}

// damped BFGS (Powell) on B = H^-1 with s = alpha p, y = grad L(x+) - grad L(x):
// B s = alpha (J^T lambda - grad_f) by the QP's stationarity, so B is never formed
void bfgs_update(const Tuft& t, BrushState& st, Workspace& w, int m, double alpha) {
  const int na = t.na();
  w.s = alpha * w.step;
  for (int k = 0; k < na; ++k) {
    double jl_new = 0.0, jl = 0.0;  // (J^T lambda)_k at the new and the old point
    for (int i = 0; i < m; ++i) {
      jl_new += w.Jact_new(i, k) * w.lam[i];
      jl += w.Jact(i, k) * w.lam[i];
    }
    w.yv[k] = (w.gact_new[k] - w.gact[k]) - (jl_new - jl);
    w.Bs[k] = -alpha * w.gact[k] + alpha * jl;
  }
  const double sBs = w.s.dot(w.Bs), sy = w.s.dot(w.yv);
  if (!(sBs > 0.0 && std::isfinite(sy))) return;
  const double th = sy >= kPowellDamping * sBs ? 1.0 : kPowellBlend * sBs / (sBs - sy);
  w.r = th * w.yv + (1.0 - th) * w.Bs;
  const double rs = w.r.dot(w.s);
  if (!(rs > kCurvatureCos * w.r.norm() * w.s.norm())) return;
  // H+ = (I - rho s r^T) H (I - rho r s^T) + rho s s^T
  //    = H - rho (s (Hr)^T + Hr s^T) + (rho^2 r^T H r + rho) s s^T, in one pass over
  //    the lower half, mirrored: H stays exactly symmetric
  MatX& H = st.H;
  const double rho = 1.0 / rs;
  w.Hr.noalias() = H * w.r;
  const double rHr = w.r.dot(w.Hr);
  const double css = rho * rho * rHr + rho;
  for (int c = 0; c < na; ++c)
    for (int k = c; k < na; ++k)
      H(k, c) = H(c, k) = H(k, c) - rho * (w.s[k] * w.Hr[c] + w.Hr[k] * w.s[c]) + css * (w.s[k] * w.s[c]);
}

// H = B^-1 with B the Lagrangian's Hessian at the current iterate w.za (multipliers w.lam fixed),
// by forward differences of grad L = grad f - J^T lambda, symmetrised; eigenvalues below a floor
// (the fresh start's smallest curvature) are raised to it so that H stays positive definite
void newton_hessian(const Tuft& t, BrushState& s, Workspace& w, int m) {
  const int na = t.na();
  VecX gl0(na), gl(na), gfull(t.nx), gcon(t.mmax);
  MatX Jfull(t.mmax, t.nx), B(na, na);
  auto grad_l = [&](const VecX& x, VecX& out) {
    evaluate(t, s, w, x, &gfull, &gcon, &Jfull);
    for (int k = 0; k < na; ++k) {
      double v = gfull[t.active[k]];
      for (int i = 0; i < m; ++i) v -= Jfull(i, t.active[k]) * w.lam[i];
      out[k] = v;
    }
  };
  const VecX x0 = s.x;
  grad_l(x0, gl0);
  VecX xh = x0;
  for (int k = 0; k < na; ++k) {
    const int j = t.active[k];
    const double h = 1e-6 * std::max(1.0, std::abs(x0[j]));
    xh[j] = x0[j] + h;
    grad_l(xh, gl);
    B.col(k) = (gl - gl0) / h;
    xh[j] = x0[j];
  }
  evaluate(t, s, w, x0, nullptr, nullptr, nullptr);  // the workspace back at the iterate
  B = 0.5 * (B + B.transpose()).eval();
  VecX b(t.nx);
  spring_curvature(t, s, b);
  double floor_b = kHuge;
  for (int k = 0; k < na; ++k) floor_b = std::min(floor_b, b[t.active[k]]);
  Eigen::SelfAdjointEigenSolver<MatX> es(B);
  VecX ev = es.eigenvalues().cwiseMax(floor_b).cwiseInverse();
  s.H = es.eigenvectors() * ev.asDiagonal() * es.eigenvectors().transpose();
}

// H's diagonal is positive and finite
bool hessian_ok(const Tuft& t, const BrushState& s) {
  for (int k = 0; k < t.na(); ++k)
    if (!(s.H(k, k) > 0.0) || !std::isfinite(s.H(k, k))) return false;
  return true;
}

}  // namespace detail
}  // namespace brushwork
