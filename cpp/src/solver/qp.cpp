// The QP of one SQP iteration through its small dual (seed "Real-time simulation"):
//     min 1/2 l^T M l + q^T l   over the box 0 <= l <= nu,
// M = J H J^T (m x m, m = n sections + the pore plane), solved by a primal active-set method;
// and the second-order correction's small solve.  Nothing here allocates.
#include <algorithm>
#include <cmath>

#include "../tuft/internal.hpp"

namespace brushwork {
namespace detail {

namespace {

// -, Tikhonov regularisation of the free-set block, relative to M's largest diagonal entry
constexpr double kQpRegularisation = 1e-13;
// -, release tolerance of a bound, relative to |q|_inf (plus a trace of nu)
constexpr double kQpReleaseTol = 1e-12;
constexpr double kQpNuTrace = 1e-6;  // -, nu's share of that tolerance's scale
// active-set iterations: this many per constraint, plus kQpIterBase
constexpr int kQpIterPerConstraint = 20;
constexpr int kQpIterBase = 20;
enum BoundState { kFree = 0, kAtLower = 1, kAtUpper = 2 };

void start_box(Workspace& w, int m, double nu) {
  for (int i = 0; i < m; ++i) {
    w.lam[i] = std::clamp(w.lam[i], 0.0, nu);
    w.qp_state[i] = w.lam[i] <= 0.0 ? kAtLower : (w.lam[i] >= nu ? kAtUpper : kFree);
  }
}

// ratio test from lam toward the free-set solution lam_f: the first bound hit (-1: none) and
// the fraction t of the way
int ratio_test(const Workspace& w, const int* idx, int nf, double nu, double& t, int& hit_state) {
  int hit = -1;
  t = 1.0;
  for (int a = 0; a < nf; ++a) {
    const double cur = w.lam[idx[a]], tgt = w.lam_f[a];
    if (tgt < 0.0 && cur - tgt > 0.0) {
      const double ta = cur / (cur - tgt);
      if (ta < t) t = ta, hit = idx[a], hit_state = kAtLower;
    } else if (tgt > nu && tgt - cur > 0.0) {
      const double ta = (nu - cur) / (tgt - cur);
      if (ta < t) t = ta, hit = idx[a], hit_state = kAtUpper;
    }
  }
  return hit;
}

// solve M_FF l_F = -q_F - M_FB l_B on the free set and move toward it, stopping at the first
// bound hit.  1: a bound was hit (the working set changed), 0: at the free-set optimum, -1: M_FF
// not positive definite
int free_set_step(Workspace& w, int m, double nu, double reg) {
  int nf = 0;
  int idx[kMaxSegments + 2];
  for (int i = 0; i < m; ++i)
    if (w.qp_state[i] == kFree) idx[nf++] = i;
  if (nf == 0) return 0;
  for (int a = 0; a < nf; ++a) {
    double r = -w.q[idx[a]];
    for (int i = 0; i < m; ++i)
      if (w.qp_state[i] != kFree) r -= w.M(idx[a], i) * w.lam[i];
    w.rhs[a] = r;
    for (int b = 0; b < nf; ++b) w.Mff(a, b) = w.M(idx[a], idx[b]);
    w.Mff(a, a) += reg;
  }
  // small dense Cholesky (M is PSD; reg keeps it definite)
  if (!cholesky_solve(w.Mff, w.rhs, w.lam_f, nf)) return -1;
  double t = 1.0;
  int hit_state = kFree;
  const int hit = ratio_test(w, idx, nf, nu, t, hit_state);
  for (int a = 0; a < nf; ++a) w.lam[idx[a]] += t * (w.lam_f[a] - w.lam[idx[a]]);
  if (hit < 0) return 0;
  w.lam[hit] = hit_state == kAtLower ? 0.0 : nu;
  w.qp_state[hit] = hit_state;
  return 1;
}

// optimal on this working set: the bound with the most violated sign condition, -1 if none
int bound_to_release(const Workspace& w, int m, double tol) {
  int rel = -1;
  double worst = tol;
  for (int i = 0; i < m; ++i) {
    if (w.qp_state[i] == kFree) continue;
    double gi = w.q[i];
    for (int k = 0; k < m; ++k) gi += w.M(i, k) * w.lam[k];
    const double viol = w.qp_state[i] == kAtLower ? -gi : gi;  // at 0 want g >= 0, at nu want g <= 0
    if (viol > worst) worst = viol, rel = i;
  }
  return rel;
}

}  // namespace

// solve A x = b for the leading k x k block of A (symmetric positive definite, overwritten by its
// Cholesky factor) into x; false if A is not positive definite.  k <= kMaxSegments + 2: no
// allocation.
bool cholesky_solve(MatX& A, const VecX& b, VecX& x, int k) {
  for (int a = 0; a < k; ++a) {
    double d = A(a, a);
    for (int c = 0; c < a; ++c) d -= A(a, c) * A(a, c);
    if (!(d > 0.0)) return false;
    d = std::sqrt(d);
    A(a, a) = d;
    for (int r = a + 1; r < k; ++r) {
      double v = A(r, a);
      for (int c = 0; c < a; ++c) v -= A(r, c) * A(a, c);
      A(r, a) = v / d;
    }
  }
  for (int a = 0; a < k; ++a) {  // forward, then backward substitution
    double v = b[a];
    for (int c = 0; c < a; ++c) v -= A(a, c) * x[c];
    x[a] = v / A(a, a);
  }
  for (int a = k - 1; a >= 0; --a) {
    double v = x[a];
    for (int c = a + 1; c < k; ++c) v -= A(c, a) * x[c];
    x[a] = v / A(a, a);
  }
  return true;
}

// Box-constrained dual QP  min 1/2 l^T M l + q^T l,  0 <= l <= nu  (M = M(0:m,0:m), q = w.q),
// primal active-set: keep l feasible, solve on the free set, step to the first bound hit, free
// the bound with the most violated multiplier.  Starts from w.lam (warm).  Returns iterations,
// or -1 if it did not finish (w.lam is then the best feasible point found).
int solve_box_qp(Workspace& w, int m, double nu) {
  if (m == 0) return 0;
  const double reg = kQpRegularisation * (w.M.topLeftCorner(m, m).diagonal().cwiseAbs().maxCoeff() + kTiny);
  const double tol = kQpReleaseTol * (w.q.head(m).cwiseAbs().maxCoeff() + nu * kQpNuTrace + kTiny);
  start_box(w, m, nu);
  for (int it = 0; it < kQpIterPerConstraint * m + kQpIterBase; ++it) {
    const int moved = free_set_step(w, m, nu, reg);
    if (moved < 0) return -1;
    if (moved > 0) continue;
    const int rel = bound_to_release(w, m, tol);
    if (rel < 0) return it + 1;
    w.qp_state[rel] = kFree;
  }
  return -1;
}

// second-order correction for the active set idx[0..k): s = H J_A^T mu, (J_A H J_A^T) mu =
// -g_A(trial) with w.gtrial holding g at the trial point; uses M = J H J^T and HJt of this
// iteration.  Returns false if M_AA is not positive definite.
bool soc_solve(Workspace& w, const int* idx, int k) {
  for (int a = 0; a < k; ++a) {
    w.rhs[a] = -w.gtrial[idx[a]];
    for (int b = 0; b < k; ++b) w.Mff(a, b) = w.M(idx[a], idx[b]);
    w.Mff(a, a) += kQpRegularisation * std::abs(w.M(idx[a], idx[a])) + kTiny;
  }
  if (!cholesky_solve(w.Mff, w.rhs, w.lam_f, k)) return false;
  w.s.setZero();
  for (int a = 0; a < k; ++a) w.s += w.lam_f[a] * w.HJt.col(idx[a]);
  return w.s.allFinite();
}

}  // namespace detail
}  // namespace brushwork
