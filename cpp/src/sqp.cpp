// Local SQP for one frame (seed "Energy minimization problems", "Real-time simulation").
//
// Each iteration solves the QP   min_p  1/2 p^T B p + grad_f^T p   s.t.  g + J p >= -s, s >= 0,
// with penalty nu * sum(s) (Fletcher's Sl1QP: always feasible, consistent with the merit
// phi(x) = f(x) + nu * sum max(0, -g_i(x))).  B = L_xx is the damped-BFGS approximation of the
// Lagrangian's Hessian, kept as its inverse H so that the QP is solved exactly through its small
// dual: with p = H (J^T lambda - grad_f), lambda minimises
//     1/2 lambda^T (J H J^T) lambda + (g - J H grad_f)^T lambda   over the box 0 <= lambda <= nu,
// an m x m problem (m = n sections + the pore plane) solved by a primal active-set method.
// A backtracking line search on phi accepts the step; H carries into the next frame.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "brushwork/brush.hpp"
#include "power.hpp"

namespace brushwork {

namespace {
inline double neg_sum(const VecX& g, int m) {
  double s = 0.0;
  for (int i = 0; i < m; ++i) s += std::max(0.0, -g[i]);
  return s;
}

// solve A x = b for the leading k x k block of A (symmetric positive definite, overwritten by its
// Cholesky factor) into x; false if A is not positive definite.  k <= kMaxSegments + 2: no
// allocation.
bool cholesky_solve(Eigen::MatrixXd& A, const VecX& b, VecX& x, int k) {
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
}  // namespace

// H = diag(1/b): b from the separable springs' curvature at x, floored, plus a Gauss-Newton
// estimate of the friction curvature of the contacting nodes (R mu^2 / max(eps, |drag|) times
// the squared horizontal lever arm) so that the first steps of a dragged frame are sane.
void Brush::fresh_hessian() {
  const double m = m_exp_, eta = eta_;
  const double floor_p = power::d2powm(0.2, m);  // curvature of |e|^m at 0.2 (rad or mm)
  VecX b(nx_);
  for (int j = 0; j < n_; ++j) {
    b[2 * j] = kb_[j] * std::max(power::d2powm(x_[2 * j] - rest_[2 * j], m) +
                                     eta * power::d2powm(x_[2 * j] - x_prev_[2 * j], m),
                                 floor_p * (1.0 + eta));
    b[2 * j + 1] = std::max(kt_[j], 0.1 * kb_[j]) * floor_p * (1.0 + eta);
  }
  for (int i = 1; i <= n_; ++i) {
    const int k = 2 * n_ + 3 * (i - 1);
    b[k] = kpsi_[i] * floor_p * (1.0 + eta);
    const double scale = 0.3 * r0_[i];
    b[k + 1] = b[k + 2] = ks_ * 8.0 * floor_p * std::pow(scale, m - 1.0) * (1.0 + eta);
  }
  // friction: sum over contacting nodes of R mu^2 / max(eps, |D|) |a_j x (P - O_j)|_xy^2
  const double mu2 = std::max(model_.friction_along, model_.friction_side);
  for (int i = 1; i <= n_; ++i)
    for (int k = 0; k < 3; ++k) {
      const double R = R_[3 * i + k];
      if (R <= 0.0) continue;
      const double sg = k == 1 ? 1.0 : -1.0;
      const Vec3 P = k == 0 ? O_[i] : Vec3(O_[i] + sg * (k == 1 ? d_plus_[i] : d_minus_[i]) * u_[i]);
      const double drag = (P - prev_pts_[3 * i + k]).head<2>().norm();
      const double w = R * mu2 * mu2 / std::max(model_.friction_smoothing, drag);
      for (int j = 0; j < std::min(i, n_); ++j) {
        b[2 * j] += w * ath_[j].cross(P - O_[j]).head<2>().squaredNorm();
        b[2 * j + 1] += w * aphi_[j].cross(P - O_[j]).head<2>().squaredNorm();
      }
    }
  H_.setZero();
  for (size_t k = 0; k < active_.size(); ++k) H_(k, k) = 1.0 / b[active_[k]];
  have_hessian_ = true;
}

// scaled KKT residual: max of stationarity |grad f - J^T lambda|_inf / kappa_root, primal
// infeasibility max(-g)/tuft_length and complementarity max|lambda_i g_i| / kappa_root
double Brush::kkt(const VecX& gact, const VecX& g, const MatX& Jact, const VecX& lam, int m) const {
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
  const double r = std::max({stat / f_scale_, feas / model_.tuft_length, comp / f_scale_});
  return std::isfinite(r) ? r : 1e300;
}

// Box-constrained dual QP  min 1/2 l^T M l + q^T l,  0 <= l <= nu  (M = M_(0:m,0:m), q = q_),
// primal active-set: keep l feasible, solve on the free set, step to the first bound hit, free
// the bound with the most violated multiplier.  Starts from lam_ (warm).  Returns iterations,
// or -1 if it did not finish (lam_ is then the best feasible point found).
int Brush::solve_box_qp(int m, double nu) {
  if (m == 0) return 0;
  const double reg = 1e-13 * (M_.topLeftCorner(m, m).diagonal().cwiseAbs().maxCoeff() + 1e-300);
  const double tol = 1e-12 * (q_.head(m).cwiseAbs().maxCoeff() + nu * 1e-6 + 1e-300);
  // state: 0 free, 1 at lower bound, 2 at upper bound
  for (int i = 0; i < m; ++i) {
    lam_[i] = std::clamp(lam_[i], 0.0, nu);
    qp_state_[i] = lam_[i] <= 0.0 ? 1 : (lam_[i] >= nu ? 2 : 0);
  }
  for (int it = 0; it < 20 * m + 20; ++it) {
    // solve M_FF l_F = -q_F - M_FB l_B on the free set
    int nf = 0;
    int idx[kMaxSegments + 2];
    for (int i = 0; i < m; ++i)
      if (qp_state_[i] == 0) idx[nf++] = i;
    bool moved = false;
    if (nf > 0) {
      for (int a = 0; a < nf; ++a) {
        double r = -q_[idx[a]];
        for (int i = 0; i < m; ++i)
          if (qp_state_[i] != 0) r -= M_(idx[a], i) * lam_[i];
        rhs_[a] = r;
        for (int b = 0; b < nf; ++b) Mff_(a, b) = M_(idx[a], idx[b]);
        Mff_(a, a) += reg;
      }
      // small dense Cholesky (M is PSD; reg keeps it definite)
      if (!cholesky_solve(Mff_, rhs_, lam_f_, nf)) return -1;
      // ratio test toward the free-set solution
      double t = 1.0;
      int hit = -1, hit_state = 0;
      for (int a = 0; a < nf; ++a) {
        const double cur = lam_[idx[a]], tgt = lam_f_[a];
        if (tgt < 0.0 && cur - tgt > 0.0) {
          const double ta = cur / (cur - tgt);
          if (ta < t) t = ta, hit = idx[a], hit_state = 1;
        } else if (tgt > nu && tgt - cur > 0.0) {
          const double ta = (nu - cur) / (tgt - cur);
          if (ta < t) t = ta, hit = idx[a], hit_state = 2;
        }
      }
      for (int a = 0; a < nf; ++a) lam_[idx[a]] += t * (lam_f_[a] - lam_[idx[a]]);
      if (hit >= 0) {
        lam_[hit] = hit_state == 1 ? 0.0 : nu;
        qp_state_[hit] = hit_state;
        moved = true;
      }
    }
    if (moved) continue;
    // optimal on this working set: release the bound with the most violated sign condition
    int rel = -1;
    double worst = tol;
    for (int i = 0; i < m; ++i) {
      if (qp_state_[i] == 0) continue;
      double gi = q_[i];
      for (int k = 0; k < m; ++k) gi += M_(i, k) * lam_[k];
      const double viol = qp_state_[i] == 1 ? -gi : gi;  // at 0 want g >= 0, at nu want g <= 0
      if (viol > worst) worst = viol, rel = i;
    }
    if (rel < 0) return it + 1;
    qp_state_[rel] = 0;
  }
  return -1;
}

// second-order correction for the active set idx[0..k): s_ = H J_A^T mu, (J_A H J_A^T) mu =
// -g_A(trial) with gtrial_ holding g at the trial point; uses M_ = J H J^T and HJt_ of this
// iteration.  Returns false if M_AA is not positive definite.
bool Brush::soc_solve(const int* idx, int k) {
  for (int a = 0; a < k; ++a) {
    rhs_[a] = -gtrial_[idx[a]];
    for (int b = 0; b < k; ++b) Mff_(a, b) = M_(idx[a], idx[b]);
    Mff_(a, a) += 1e-13 * std::abs(M_(idx[a], idx[a])) + 1e-300;
  }
  if (!cholesky_solve(Mff_, rhs_, lam_f_, k)) return false;
  s_.setZero();
  for (int a = 0; a < k; ++a) s_ += lam_f_[a] * HJt_.col(idx[a]);
  return s_.allFinite();
}

// One frame.  A pose far from the last one (a straight brush put straight into a deep press, a
// drag of a tuft length per frame) makes the first iterate penetrate deeply, and a local SQP
// from there may need many frames to climb out.  Such a frame is split: the pose is
// interpolated from the last one in sub-steps, each solved in turn (continuation), so that no
// sub-step starts more than about 2% of the tuft length inside the paper.  Statistics add up.
StepStats Brush::step(const Pose& pose) {
  const auto t0 = std::chrono::steady_clock::now();
  pose.validate();
  // sleep rule: the same pose as last frame and a residual within 10x tolerance means no motion
  // (without it, modes without a spring, like phi_0, creep by ~1e-5 rad a frame forever)
  same_pose_ = have_prev_positions_ && pose.position == pose_.position &&
               pose.tilt_deg == pose_.tilt_deg && pose.azimuth_deg == pose_.azimuth_deg &&
               pose.twist_deg == pose_.twist_deg;

  // set the frame up once; if its first iterate sinks too deep, put the state back and split
  // the frame into sub-steps from the last pose.  The saved copies live in buffers sized once.
  int substeps = 1;
  Pose from = pose_;
  // every (saved, live) pair the frame set-up changes, in one list for both directions
  auto each_pair = [&](auto&& f) {
    f(save_.x, x_), f(save_.x_prev, x_prev_), f(save_.rest, rest_), f(save_.lambda, lambda_);
    f(save_.pose, pose_), f(save_.touched, touched_since_reset_);
    f(save_.have_prev, have_prev_positions_), f(save_.pore_on_prev, pore_on_prev_);
    f(save_.pore_anchor, pore_anchor_), f(save_.m, m_);
  };
  each_pair([](auto& saved, const auto& live) { saved = live; });
  // a touching brush whose root jumps more than L/4 in one frame is also split: q_max
  // iterations cannot carry a bent tuft that far, and the unconverged state floats above the
  // paper (a drag of 20 belly radii a frame lost contact and broke the stroke)
  const double step_travel = 0.125 * model_.tuft_length;
  const double travel = (pose.position - pose_.position).norm();
  const int travel_steps = (have_prev_positions_ && stats_.contacts > 0 && travel > step_travel)
                               ? std::min(32, static_cast<int>(std::ceil(travel / step_travel)))
                               : 1;
  begin_frame(pose);
  if (model_.collision) {
    const double pen = std::max(0.0, -section_heights().minCoeff());
    const double step_pen = 0.02 * model_.tuft_length;
    const int pen_steps = pen > step_pen ? std::min(32, static_cast<int>(std::ceil(pen / step_pen))) : 1;
    if (std::max(pen_steps, travel_steps) > 1) {
      substeps = std::max(pen_steps, travel_steps);
      each_pair([](const auto& saved, auto& live) { live = saved; });
      // a fresh (or reset) brush has no last pose: it comes down from straight above
      if (!have_prev_positions_) {
        from = pose;
        from.position.z() += 1.2 * pen + step_pen;
      }
    }
  }
  int iterations = 0, ls_fail = 0, resets = 0;
  std::vector<double> mb, ma;
  for (int k = 1; k <= substeps; ++k) {
    Pose p = pose;
    if (k < substeps) {
      const double t = static_cast<double>(k) / substeps;
      p.position = from.position + t * (pose.position - from.position);
      p.tilt_deg = from.tilt_deg + t * (pose.tilt_deg - from.tilt_deg);
      // azimuth and twist along the shorter way round
      const double da = std::remainder(pose.azimuth_deg - from.azimuth_deg, 360.0);
      const double dt = std::remainder(pose.twist_deg - from.twist_deg, 360.0);
      p.azimuth_deg = pose.azimuth_deg - (1.0 - t) * da;
      p.twist_deg = pose.twist_deg - (1.0 - t) * dt;
    }
    if (substeps > 1) begin_frame(p);  // a single step was set up above
    solve();
    end_frame();
    iterations += stats_.iterations;
    ls_fail += stats_.line_search_failures;
    resets += stats_.hessian_resets;
    if (substeps > 1) {
      mb.insert(mb.end(), stats_.merit_before.begin(), stats_.merit_before.end());
      ma.insert(ma.end(), stats_.merit_after.begin(), stats_.merit_after.end());
    }
  }
  if (substeps > 1) {
    stats_.merit_before = mb;  // rare path: allocation is fine here
    stats_.merit_after = ma;
  }
  stats_.iterations = iterations;
  stats_.line_search_failures = ls_fail;
  stats_.hessian_resets = resets;
  stats_.substeps = substeps;
  stats_.contacts = contacts_;
  stats_.root_clamped = root_clamped_;
  stats_.pore_active = pore_on_;
  stats_.max_penetration = std::max(0.0, -section_heights().minCoeff());
  stats_.time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats_;
}

void Brush::solve() {
  const int na = static_cast<int>(active_.size());
  const int m = m_;
  const int qmax = model_.q_max;
  const double tol = model_.tolerance;
  stats_.iterations = 0;
  stats_.line_search_failures = 0;
  stats_.hessian_resets = 0;
  stats_.merit_before.clear();
  stats_.merit_after.clear();
  stats_.step_sizes.clear();
  stats_.kkt_trace.clear();
  stats_.converged = false;
  stats_.status = "iteration cap";

  // first iterate: the last frame's state at the new pose
  double f = evaluate(x_, &gf_, &g_, &J_);
  gather(gf_, gact_);
  for (size_t k = 0; k < active_.size(); ++k) Jact_.col(k).head(m) = J_.col(active_[k]).head(m);
  // one carried Hessian per regime, touching and in the air.  The touching one holds the stuck
  // contacts' friction curvature (~100x the bend springs'), which free air lacks: carried into
  // a lift it let a loop's tip segment swing past -4 rad over capped frames and come down on
  // the paper again.  So a lift-off keeps it aside and starts the air afresh, and a touch-down
  // takes it back (the air's matrix knows nothing of friction either)
  if (model_.warm_hessian && have_hessian_ && hessian_contacts_ >= 0 &&
      (contacts_ > 0) != (hessian_contacts_ > 0)) {
    if (hessian_contacts_ > 0) {
      H_touching_ = H_;
      have_h_touching_ = true;
      fresh_hessian();
    } else if (have_h_touching_) {
      H_ = H_touching_;
    }
  }
  if (!model_.warm_hessian || !have_hessian_) fresh_hessian();
  hessian_contacts_ = contacts_;
  for (int i = 0; i < m; ++i) lam_[i] = std::max(lambda_[i], 0.0);
  gather(x_, za_);

  // the penalty nu must exceed the contact forces; its floor is the brush's force scale
  const double nu0 = 100.0 * model_.bend_stiffness / model_.tuft_length;
  nu_ = std::max(nu0, 2.0 * (m > 0 ? lam_.head(m).maxCoeff() : 0.0));
  const double nu_max = 1e12 * nu0;

  double res = kkt(gact_, g_, Jact_, lam_, m);
  if (res <= tol || (same_pose_ && res <= 10.0 * tol)) {
    stats_.converged = true;
    stats_.status = "no motion";
  }
  bool fresh_this_iter = !model_.warm_hessian;
  int q = 0;
  while (!stats_.converged && q < qmax) {
    // --- QP through its dual: M = J H J^T, q = g - J H grad_f.  A few dozen variables and
    // constraints: plain loops, no matrix-product kernels (their packing cost more than the
    // arithmetic).  Row i of J is sparse (the joints above node i and node i's own lateral
    // variables), so H J^T's column i gathers only those columns of H; M is symmetric, its
    // lower half is computed and mirrored.
    for (int i = 0; i < m; ++i) {
      auto hj = HJt_.col(i);
      hj.setZero();
      for (int k = 0; k < na; ++k)
        if (Jact_(i, k) != 0.0) hj += Jact_(i, k) * H_.col(k);
    }
    for (int i = 0; i < m; ++i)
      for (int c = 0; c <= i; ++c) {
        double v = 0.0;
        for (int k = 0; k < na; ++k) v += Jact_(i, k) * HJt_(k, c);
        M_(i, c) = M_(c, i) = v;
      }
    tmp_.noalias() = H_ * gact_;  // H grad_f
    for (int i = 0; i < m; ++i) q_[i] = g_[i] - Jact_.row(i).dot(tmp_);
    int qp_it = solve_box_qp(m, nu_);
    // an elastic (infeasible-looking) linearisation: raise nu and solve again
    for (int tries = 0; tries < 4 && m > 0 && qp_it >= 0 && lam_.head(m).maxCoeff() >= 0.999 * nu_ &&
                        nu_ < nu_max;
         ++tries) {
      nu_ *= 10.0;
      qp_it = solve_box_qp(m, nu_);
    }
    if (qp_it < 0) {
      stats_.status = "qp";
      if (!fresh_this_iter) {  // try once more from a fresh matrix
        fresh_hessian();
        ++stats_.hessian_resets;
        fresh_this_iter = true;
        continue;
      }
      break;
    }
    // p = H (J^T lambda - grad_f)
    step_ = -tmp_;
    if (m > 0) step_.noalias() += HJt_.leftCols(m) * lam_.head(m);

    // directional derivative of the l1 merit along p (negative for an Sl1QP step)
    double lin_viol = 0.0;
    for (int i = 0; i < m; ++i) lin_viol += std::max(0.0, -(g_[i] + Jact_.row(i).dot(step_)));
    const double viol0 = neg_sum(g_, m);
    const double D = gact_.dot(step_) - nu_ * viol0 + nu_ * lin_viol;
    const double merit0 = f + nu_ * viol0;
    if (!(D < 0.0) || !std::isfinite(D)) {
      if (step_.cwiseAbs().maxCoeff() < 1e-14) {  // nothing left to do
        stats_.converged = res <= tol;
        stats_.status = stats_.converged ? "converged" : "stalled";
        break;
      }
      if (!fresh_this_iter) {
        fresh_hessian();
        ++stats_.hessian_resets;
        fresh_this_iter = true;
        continue;
      }
      stats_.status = "line search";
      break;
    }

    // step cap: no variable moves more than 0.5 (rad, or sqrt(mm) for the stretches) at once
    const double pmax = step_.cwiseAbs().maxCoeff();
    double alpha = std::min(1.0, 0.5 / pmax);

    // backtracking on the merit; a trial with a non-finite value is rejected, never accepted.
    // trial(): the merit at zt_ (set by the caller); gtrial_ keeps g there
    bool accepted = false;
    double f_new = 0.0, merit_new = 0.0;
    auto trial = [&](double a) {
      xf_trial_ = x_;
      scatter(zt_, xf_trial_);
      f_new = evaluate(xf_trial_, nullptr, &gtrial_, nullptr);
      merit_new = f_new + nu_ * neg_sum(gtrial_, m);
      return std::isfinite(merit_new) && merit_new <= merit0 + 1e-4 * a * D;
    };
    if (alpha == 1.0 && m > 0) {
      // try the full step first, and if the merit rejects it, a second-order correction: curved
      // constraints make the l1 merit refuse good full steps near the solution (the Maratos
      // effect); p_c = H J_A^T mu with (J_A H J_A^T) mu = -g_A(x + p) puts the active
      // constraints back on the paper at second order, and the same merit test decides
      zt_ = za_ + step_;
      accepted = trial(1.0);
      if (!accepted && std::isfinite(merit_new)) {
        int na_act = 0, idx[kMaxSegments + 2];
        for (int i = 0; i < m; ++i)
          if (lam_[i] > 0.0) idx[na_act++] = i;
        if (na_act > 0 && soc_solve(idx, na_act)) {
          zt_ = za_ + step_ + s_;
          accepted = trial(1.0);
          if (accepted) step_ += s_;  // the accepted displacement, for the BFGS pair
        }
      }
      if (!accepted) alpha = 0.5;
    }
    for (int ls = 0; ls < 40 && !accepted; ++ls) {
      zt_ = za_ + alpha * step_;
      accepted = trial(alpha);
      if (!accepted) alpha *= 0.5;
    }
    if (!accepted) {
      ++stats_.line_search_failures;
      if (!fresh_this_iter) {
        fresh_hessian();
        ++stats_.hessian_resets;
        fresh_this_iter = true;
        continue;
      }
      stats_.status = "line search";
      break;
    }
    fresh_this_iter = false;
    ++q;
    stats_.merit_before.push_back(merit0);
    stats_.merit_after.push_back(merit_new);
    stats_.step_sizes.push_back(alpha);

    // accept, and evaluate the derivatives at the new point
    x_ = xf_trial_;
    za_ = zt_;
    f = evaluate(x_, &gf_new_, &g_new_, &J_);
    gather(gf_new_, gact_new_);
    for (size_t k = 0; k < active_.size(); ++k)
      Jact_new_.col(k).head(m) = J_.col(active_[k]).head(m);

    // damped BFGS (Powell) on B = H^-1 with s = alpha p, y = grad L(x+) - grad L(x):
    // B s = alpha (J^T lambda - grad_f) by the QP's stationarity, so B is never formed
    s_ = alpha * step_;
    for (int k = 0; k < na; ++k) {
      double jl_new = 0.0, jl = 0.0;  // (J^T lambda)_k at the new and the old point
      for (int i = 0; i < m; ++i) {
        jl_new += Jact_new_(i, k) * lam_[i];
        jl += Jact_(i, k) * lam_[i];
      }
      yv_[k] = (gact_new_[k] - gact_[k]) - (jl_new - jl);
      Bs_[k] = -alpha * gact_[k] + alpha * jl;
    }
    const double sBs = s_.dot(Bs_), sy = s_.dot(yv_);
    if (sBs > 0.0 && std::isfinite(sy)) {
      const double th = sy >= 0.2 * sBs ? 1.0 : 0.8 * sBs / (sBs - sy);
      r_ = th * yv_ + (1.0 - th) * Bs_;
      const double rs = r_.dot(s_);
      if (rs > 1e-16 * r_.norm() * s_.norm()) {
        // H+ = (I - rho s r^T) H (I - rho r s^T) + rho s s^T
        //    = H - rho (s (Hr)^T + Hr s^T) + (rho^2 r^T H r + rho) s s^T, in one pass over
        //    the lower half, mirrored: H stays exactly symmetric
        const double rho = 1.0 / rs;
        Hr_.noalias() = H_ * r_;
        const double rHr = r_.dot(Hr_);
        const double css = rho * rho * rHr + rho;
        for (int c = 0; c < na; ++c)
          for (int k = c; k < na; ++k)
            H_(k, c) = H_(c, k) =
                H_(k, c) - rho * (s_[k] * Hr_[c] + Hr_[k] * s_[c]) + css * (s_[k] * s_[c]);
      }
    }
    bool bad = false;
    for (int k = 0; k < na && !bad; ++k) bad = !(H_(k, k) > 0.0) || !std::isfinite(H_(k, k));
    if (bad) {
      fresh_hessian();
      ++stats_.hessian_resets;
    }

    gact_.swap(gact_new_);
    g_.swap(g_new_);
    Jact_.swap(Jact_new_);
    res = kkt(gact_, g_, Jact_, lam_, m);
    stats_.kkt_trace.push_back(res);
    if (res <= tol) {
      stats_.converged = true;
      stats_.status = "converged";
    }
  }
  if (!model_.warm_hessian) have_hessian_ = false;
  for (int i = 0; i < m; ++i) lambda_[i] = lam_[i];
  stats_.iterations = q;
  stats_.energy = f;
  stats_.kkt_residual = res;
  stats_.penalty = nu_;
}

}  // namespace brushwork
