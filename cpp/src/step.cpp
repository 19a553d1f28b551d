// One frame of one tuft, with continuation: a pose far from the last one (a straight brush put
// straight into a deep press, a drag of a tuft length per frame) makes the first iterate
// penetrate deeply, and a local SQP from there may need many frames to climb out.  Such a frame
// is split: the pose is interpolated from the last one in sub-steps, each solved in turn, so
// that no sub-step starts more than about 2% of the tuft length inside the paper.  Statistics
// add up.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "tuft/internal.hpp"

namespace brushwork {

namespace {

// -, a touching brush whose root travels more than this fraction of L in one frame is split:
// q_max iterations cannot carry a bent tuft that far, and the unconverged state floats above
// the paper (a drag of 20 belly radii a frame lost contact and broke the stroke)
constexpr double kTravelPerStep = 0.125;
// -, a first iterate deeper than this fraction of L below the paper is split
constexpr double kPressPerStep = 0.02;
constexpr int kMaxSubsteps = 32;
// -, a fresh brush comes down from this multiple of its first iterate's depth above the pose
constexpr double kDropHeight = 1.2;

// sub-steps needed to cover `amount` in pieces of at most `per_step` (1 when within one)
int pieces(double amount, double per_step) {
  return amount > per_step ? std::min(kMaxSubsteps, static_cast<int>(std::ceil(amount / per_step))) : 1;
}

double max_penetration(const Tuft& t, const Workspace& w) {
  return std::max(0.0, -section_heights(t, w).minCoeff());
}

// the pose a fraction k / substeps of the way from `from` to `to`; azimuth and twist along the
// shorter way round
Pose substep_pose(const Pose& from, const Pose& to, int k, int substeps) {
  Pose p = to;
  if (k == substeps) return p;
  const double t = static_cast<double>(k) / substeps;
  p.position = from.position + t * (to.position - from.position);
  p.tilt_deg = from.tilt_deg + t * (to.tilt_deg - from.tilt_deg);
  const double da = std::remainder(to.azimuth_deg - from.azimuth_deg, 360.0);
  const double dt = std::remainder(to.twist_deg - from.twist_deg, 360.0);
  p.azimuth_deg = to.azimuth_deg - (1.0 - t) * da;
  p.twist_deg = to.twist_deg - (1.0 - t) * dt;
  return p;
}

// set the frame up once; if its first iterate sinks too deep (or the root travels too far
// while touching), put the state back and return the number of sub-steps, with `from` the
// pose they start at.  A single step stays set up.
int plan_substeps(const Tuft& t, BrushState& s, const Pose& pose, Workspace& w, Pose& from) {
  const double L = t.model.tuft_length;
  from = s.pose;
  w.saved = s;
  const double travel = (pose.position - s.pose.position).norm();
  const int travel_steps =
      (s.have_prev_positions && s.stats.contacts > 0) ? pieces(travel, kTravelPerStep * L) : 1;
  prepare_frame(t, s, pose, w);
  if (!t.model.collision) return 1;
  const double pen = max_penetration(t, w);
  const int substeps = std::max(pieces(pen, kPressPerStep * L), travel_steps);
  if (substeps == 1) return 1;
  s = w.saved;  // the discarded set-up leaves no trace (it relaxed R and p once already)
  // a fresh (or reset) brush has no last pose: it comes down from straight above
  if (!s.have_prev_positions) {
    from = pose;
    from.position.z() += kDropHeight * pen + kPressPerStep * L;
  }
  return substeps;
}

}  // namespace

StepStats step(const Tuft& t, BrushState& s, const Pose& pose, Workspace& w) {
  const auto t0 = std::chrono::steady_clock::now();
  pose.validate();
  // sleep rule: the same pose as last frame and a residual within 10x tolerance means no motion
  // (without it, modes without a spring, like phi_0, creep by ~1e-5 rad a frame forever)
  s.same_pose = s.have_prev_positions && pose == s.pose;
  Pose from;
  const int substeps = plan_substeps(t, s, pose, w, from);
  StepStats& st = s.stats;
  int iterations = 0, ls_fail = 0, resets = 0;
  std::vector<double> mb, ma;
  for (int k = 1; k <= substeps; ++k) {
    if (substeps > 1) prepare_frame(t, s, substep_pose(from, pose, k, substeps), w);
    solve(t, s, w);
    end_frame(t, s, w);
    iterations += st.iterations;
    ls_fail += st.line_search_failures;
    resets += st.hessian_resets;
    if (substeps > 1) {
      mb.insert(mb.end(), st.merit_before.begin(), st.merit_before.end());
      ma.insert(ma.end(), st.merit_after.begin(), st.merit_after.end());
    }
  }
  if (substeps > 1) {
    st.merit_before = mb;  // rare path: allocation is fine here
    st.merit_after = ma;
  }
  st.iterations = iterations;
  st.line_search_failures = ls_fail;
  st.hessian_resets = resets;
  st.substeps = substeps;
  st.contacts = s.contacts;
  st.root_clamped = s.root_clamped;
  st.pore_active = s.pore_on;
  st.max_penetration = max_penetration(t, w);
  st.time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return st;
}

}  // namespace brushwork
