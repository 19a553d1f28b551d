// Local SQP for one frame (seed "Energy minimization problems", "Real-time simulation").
//
// Each iteration solves the QP   min_p  1/2 p^T B p + grad_f^T p   s.t.  g + J p >= -s, s >= 0,
// with penalty nu * sum(s) (Fletcher's Sl1QP: always feasible, consistent with the merit
// phi(x) = f(x) + nu * sum max(0, -g_i(x))).  B = L_xx is the damped-BFGS approximation of the
// Lagrangian's Hessian, kept as its inverse H so that the QP is solved exactly through its small
// dual: with p = H (J^T lambda - grad_f), lambda minimises
//     1/2 lambda^T (J H J^T) lambda + (g - J H grad_f)^T lambda   over the box 0 <= lambda <= nu,
// an m x m problem (m = n sections + the pore plane) solved by a primal active-set method (qp.cpp).
// A backtracking line search on phi accepts the step; H carries into the next frame (bfgs.cpp).
#include <algorithm>
#include <cmath>

#include "../tuft/internal.hpp"
#include "bfgs.hpp"

namespace brushwork {

using namespace detail;

namespace {

// N/(N*mm/mm): the penalty's floor nu0 = this x kappa_root / L, the brush's force scale
constexpr double kPenaltyScale = 100.0;
constexpr double kPenaltyCeiling = 1e12;  // -, nu never exceeds this x nu0
constexpr double kPenaltyRaise = 10.0;    // -, nu grows by this factor for an elastic QP
constexpr int kPenaltyRaises = 4;         // times nu may grow in one iteration
constexpr double kElastic = 0.999;        // -, a multiplier at this fraction of nu sits on the box
constexpr double kSleepResidual = 10.0;   // -, residual (x tolerance) within which a still pose sleeps
constexpr double kMaxStep = 0.5;          // rad (sqrt(mm) for stretches): largest move of a variable
constexpr double kArmijo = 1e-4;          // -, sufficient-decrease fraction of the merit's slope
constexpr int kBacktracks = 40;           // halvings of alpha before the line search gives up
constexpr double kBacktrack = 0.5;        // -, alpha shrinks by this factor per rejected trial
constexpr double kPenaltyMargin = 2.0;    // -, nu starts at least this multiple of the largest multiplier
constexpr double kNegligibleStep = 1e-14; // rad: a step this small leaves nothing to do

inline double neg_sum(const VecX& g, int m) {
  double s = 0.0;
  for (int i = 0; i < m; ++i) s += std::max(0.0, -g[i]);
  return s;
}

// the state of one frame's SQP loop
struct Loop {
  int m = 0;                // constraints
  double f = 0.0;           // energy at the current iterate, N*mm
  double res = 0.0;         // scaled KKT residual there
  double nu_max = 0.0;      // N, ceiling of the penalty
  bool fresh = false;       // H was started afresh since the last accepted step
  int q = 0;                // accepted steps
};

enum class Outcome { kAccepted, kRetry, kStop };

void start_stats(StepStats& st) {
  st.iterations = 0;
  st.line_search_failures = 0;
  st.hessian_resets = 0;
  st.merit_before.clear();
  st.merit_after.clear();
  st.step_sizes.clear();
  st.kkt_trace.clear();
  st.converged = false;
  st.status = "iteration cap";
}

// the active columns of J into Jact (m rows)
void gather_jacobian(const Tuft& t, const MatX& J, MatX& Jact, int m) {
  for (size_t k = 0; k < t.active.size(); ++k) Jact.col(k).head(m) = J.col(t.active[k]).head(m);
}

// first iterate: the last frame's state at the new pose; H, multipliers and penalty to start
Loop start_loop(const Tuft& t, BrushState& s, Workspace& w) {
  Loop L;
  L.m = s.m;
  start_stats(s.stats);
  L.f = evaluate(t, s, w, s.x, &w.gf, &w.g, &w.J);
  gather(t, w.gf, w.gact);
  gather_jacobian(t, w.J, w.Jact, L.m);
  start_hessian(t, s, w);
  for (int i = 0; i < L.m; ++i) w.lam[i] = std::max(s.lambda[i], 0.0);
  gather(t, s.x, w.za);
  // the penalty nu must exceed the contact forces; its floor is the brush's force scale
  const double nu0 = kPenaltyScale * t.model.bend_stiffness / t.model.tuft_length;
  s.nu = std::max(nu0, kPenaltyMargin * (L.m > 0 ? w.lam.head(L.m).maxCoeff() : 0.0));
  L.nu_max = kPenaltyCeiling * nu0;
  const double tol = t.model.tolerance;
  L.res = kkt(t, w.gact, w.g, w.Jact, w.lam, L.m);
  if (L.res <= tol || (s.same_pose && L.res <= kSleepResidual * tol)) {
    s.stats.converged = true;
    s.stats.status = "no motion";
  }
  L.fresh = !t.model.warm_hessian;
  return L;
}

// the dual QP's data: M = J H J^T, q = g - J H grad_f.  A few dozen variables and constraints:
// plain loops, no matrix-product kernels (their packing cost more than the arithmetic).  Row i
// of J is sparse (the joints above node i and node i's own lateral variables), so H J^T's
// column i gathers only those columns of H; M is symmetric, its lower half is computed and
// mirrored.
void build_dual(const Tuft& t, const BrushState& s, Workspace& w, int m) {
  const int na = t.na();
  for (int i = 0; i < m; ++i) {
    auto hj = w.HJt.col(i);
    hj.setZero();
    for (int k = 0; k < na; ++k)
      if (w.Jact(i, k) != 0.0) hj += w.Jact(i, k) * s.H.col(k);
  }
  for (int i = 0; i < m; ++i)
    for (int c = 0; c <= i; ++c) {
      double v = 0.0;
      for (int k = 0; k < na; ++k) v += w.Jact(i, k) * w.HJt(k, c);
      w.M(i, c) = w.M(c, i) = v;
    }
  w.tmp.noalias() = s.H * w.gact;  // H grad_f
  for (int i = 0; i < m; ++i) w.q[i] = w.g[i] - w.Jact.row(i).dot(w.tmp);
}

// the QP; an elastic (infeasible-looking) linearisation raises nu and solves again.  Returns
// the QP's iterations, -1 if it failed
int solve_dual(BrushState& s, Workspace& w, const Loop& L) {
  const int m = L.m;
  int qp_it = solve_box_qp(w, m, s.nu);
  for (int tries = 0; tries < kPenaltyRaises && m > 0 && qp_it >= 0 &&
                      w.lam.head(m).maxCoeff() >= kElastic * s.nu && s.nu < L.nu_max;
       ++tries) {
    s.nu *= kPenaltyRaise;
    qp_it = solve_box_qp(w, m, s.nu);
  }
  return qp_it;
}

// start H afresh once per accepted step before giving up: true if it did (retry the iteration)
bool retry_fresh(const Tuft& t, BrushState& s, Workspace& w, Loop& L) {
  if (L.fresh) return false;
  fresh_hessian(t, s, w);
  ++s.stats.hessian_resets;
  L.fresh = true;
  return true;
}

// the merit at w.zt; w.gtrial keeps g there.  True if it decreases enough for step a
bool trial(const Tuft& t, const BrushState& s, Workspace& w, int m, double a, double merit0, double D,
           double& f_new, double& merit_new) {
  w.xf_trial = s.x;
  scatter(t, w.zt, w.xf_trial);
  f_new = evaluate(t, s, w, w.xf_trial, nullptr, &w.gtrial, nullptr);
  merit_new = f_new + s.nu * neg_sum(w.gtrial, m);
  return std::isfinite(merit_new) && merit_new <= merit0 + kArmijo * a * D;
}

// the full step, and if the merit rejects it, a second-order correction: curved constraints
// make the l1 merit refuse good full steps near the solution (the Maratos effect); p_c = H J_A^T
// mu with (J_A H J_A^T) mu = -g_A(x + p) puts the active constraints back on the paper at second
// order, and the same merit test decides
bool full_step(const Tuft& t, const BrushState& s, Workspace& w, int m, double merit0, double D,
               double& f_new, double& merit_new) {
  w.zt = w.za + w.step;
  if (trial(t, s, w, m, 1.0, merit0, D, f_new, merit_new)) return true;
  if (!std::isfinite(merit_new)) return false;
  int na_act = 0, idx[kMaxSegments + 2];
  for (int i = 0; i < m; ++i)
    if (w.lam[i] > 0.0) idx[na_act++] = i;
  if (na_act == 0 || !soc_solve(w, idx, na_act)) return false;
  w.zt = w.za + w.step + w.s;
  if (!trial(t, s, w, m, 1.0, merit0, D, f_new, merit_new)) return false;
  w.step += w.s;  // the accepted displacement, for the BFGS pair
  return true;
}

// backtracking on the merit; a trial with a non-finite value is rejected, never accepted.
// The step is capped so that no variable moves more than kMaxStep at once.  True if a step
// alpha was accepted (its point in w.zt, w.xf_trial)
bool line_search(const Tuft& t, const BrushState& s, Workspace& w, int m, double merit0, double D,
                 double& alpha, double& f_new, double& merit_new) {
  const double pmax = w.step.cwiseAbs().maxCoeff();
  alpha = std::min(1.0, kMaxStep / pmax);
  bool accepted = false;
  f_new = merit_new = 0.0;
  if (alpha == 1.0 && m > 0) {
    accepted = full_step(t, s, w, m, merit0, D, f_new, merit_new);
    if (!accepted) alpha = kBacktrack;
  }
  for (int ls = 0; ls < kBacktracks && !accepted; ++ls) {
    w.zt = w.za + alpha * w.step;
    accepted = trial(t, s, w, m, alpha, merit0, D, f_new, merit_new);
    if (!accepted) alpha *= kBacktrack;
  }
  return accepted;
}

// take the accepted point, its derivatives, the BFGS update and the new residual
void accept(const Tuft& t, BrushState& s, Workspace& w, Loop& L, double alpha, double merit0,
            double merit_new) {
  L.fresh = false;
  ++L.q;
  s.stats.merit_before.push_back(merit0);
  s.stats.merit_after.push_back(merit_new);
  s.stats.step_sizes.push_back(alpha);
  s.x = w.xf_trial;
  w.za = w.zt;
  L.f = evaluate(t, s, w, s.x, &w.gf_new, &w.g_new, &w.J);
  gather(t, w.gf_new, w.gact_new);
  gather_jacobian(t, w.J, w.Jact_new, L.m);
  bfgs_update(t, s, w, L.m, alpha);
  if (!hessian_ok(t, s)) {
    fresh_hessian(t, s, w);
    ++s.stats.hessian_resets;
  }
  w.gact.swap(w.gact_new);
  w.g.swap(w.g_new);
  w.Jact.swap(w.Jact_new);
  L.res = kkt(t, w.gact, w.g, w.Jact, w.lam, L.m);
  s.stats.kkt_trace.push_back(L.res);
  if (L.res <= t.model.tolerance) {
    s.stats.converged = true;
    s.stats.status = "converged";
  }
}

// a step along which the merit does not descend: done if it is negligible, else a retry or a stop
Outcome no_descent(const Tuft& t, BrushState& s, Workspace& w, Loop& L) {
  if (w.step.cwiseAbs().maxCoeff() < kNegligibleStep) {  // nothing left to do
    s.stats.converged = L.res <= t.model.tolerance;
    s.stats.status = s.stats.converged ? "converged" : "stalled";
    return Outcome::kStop;
  }
  if (retry_fresh(t, s, w, L)) return Outcome::kRetry;
  s.stats.status = "line search";
  return Outcome::kStop;
}

// one SQP iteration: QP, merit slope, line search, update
Outcome iterate(const Tuft& t, BrushState& s, Workspace& w, Loop& L) {
  const int m = L.m;
  build_dual(t, s, w, m);
  if (solve_dual(s, w, L) < 0) {
    s.stats.status = "qp";
    return retry_fresh(t, s, w, L) ? Outcome::kRetry : Outcome::kStop;
  }
  // p = H (J^T lambda - grad_f)
  w.step = -w.tmp;
  if (m > 0) w.step.noalias() += w.HJt.leftCols(m) * w.lam.head(m);

  // directional derivative of the l1 merit along p (negative for an Sl1QP step)
  double lin_viol = 0.0;
  for (int i = 0; i < m; ++i) lin_viol += std::max(0.0, -(w.g[i] + w.Jact.row(i).dot(w.step)));
  const double viol0 = neg_sum(w.g, m);
  const double D = w.gact.dot(w.step) - s.nu * viol0 + s.nu * lin_viol;
  const double merit0 = L.f + s.nu * viol0;
  if (!(D < 0.0) || !std::isfinite(D)) return no_descent(t, s, w, L);

  double alpha = 1.0, f_new = 0.0, merit_new = 0.0;
  if (!line_search(t, s, w, m, merit0, D, alpha, f_new, merit_new)) {
    ++s.stats.line_search_failures;
    if (retry_fresh(t, s, w, L)) return Outcome::kRetry;
    s.stats.status = "line search";
    return Outcome::kStop;
  }
  accept(t, s, w, L, alpha, merit0, merit_new);
  return Outcome::kAccepted;
}

}  // namespace

namespace detail {

// scaled KKT residual: max of stationarity |grad f - J^T lambda|_inf / kappa_root, primal
// infeasibility max(-g)/tuft_length and complementarity max|lambda_i g_i| / kappa_root
double kkt(const Tuft& t, const VecX& gact, const VecX& g, const MatX& Jact, const VecX& lam, int m) {
  double stat = 0.0;
  for (int k = 0; k < gact.size(); ++k) {
    double v = gact[k];
    for (int i = 0; i < m; ++i) v -= Jact(i, k) * lam[i];
    stat = std::max(stat, std::abs(v));
  }
  double feas = 0.0, comp = 0.0;
  for (int i = 0; i < m; ++i) {
    feas = std::max(feas, -g[i]);
    comp = std::max(comp, std::abs(lam[i] * g[i]));
  }
  const double r = std::max({stat / t.f_scale, feas / t.model.tuft_length, comp / t.f_scale});
  return std::isfinite(r) ? r : kHuge;
}

}  // namespace detail

void solve(const Tuft& t, BrushState& s, Workspace& w) {
  Loop L = start_loop(t, s, w);
  while (!s.stats.converged && L.q < t.model.q_max) {
    // every newton_after iterations without convergence, H from the Lagrangian's Hessian
    if (t.model.newton_after > 0 && L.q > 0 && L.q % t.model.newton_after == 0) newton_hessian(t, s, w, L.m);
    if (iterate(t, s, w, L) == Outcome::kStop) break;
  }
  if (!t.model.warm_hessian) s.have_hessian = false;
  for (int i = 0; i < L.m; ++i) s.lambda[i] = w.lam[i];
  s.stats.iterations = L.q;
  s.stats.energy = L.f;
  s.stats.kkt_residual = L.res;
  s.stats.penalty = s.nu;
}

}  // namespace brushwork
