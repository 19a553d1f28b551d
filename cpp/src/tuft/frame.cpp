// Frame set-up (seed "Real-time simulation"): the root frame at the pose, plasticity, the
// straight-skeleton trick, the contact set and normal forces frozen at the first iterate, the
// pore plane; and the state a fresh or reset brush starts from.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "internal.hpp"

namespace brushwork {

using detail::kDeg;

namespace {

constexpr double kPlasticDeadband = 1e-4;  // rad: rest angles move only when their target moved more
constexpr double kThetaEps = 1e-3;  // rad: the straight-skeleton trick (seed "Energy minimization problems")
constexpr double kStraight = 1e-7;  // rad: a spine whose every bend is below this is straight
// -, a pressed stretch delta = 0 is kicked to delta^2 = this fraction of r_i
constexpr double kStretchKick = 0.01;
// -, the root is held this fraction of the tuft length above its touching height
constexpr double kRootClearance = 1e-9;
// -, |horizontal part| of the tip's unit direction below which the tip points straight down
// (no direction for the pore plane)
constexpr double kVerticalTip = 1e-6;

// root frame: e3 = -(handle axis) is the unbent tuft's direction; e1 lies in the vertical
// plane through the handle (so bending with phi_0 = 0 keeps the lateral lines horizontal),
// continuous as the tilt goes to 0; twist turns (e1, e2) about e3.  The ferrule cannot enter
// the paper: the root is held where its (shrunk) section touches it
void set_root_frame(const Tuft& t, BrushState& s, const Pose& pose) {
  const double tl = pose.tilt_deg * kDeg, az = pose.azimuth_deg * kDeg, tw = pose.twist_deg * kDeg;
  const Vec3 e3(-std::sin(tl) * std::cos(az), -std::sin(tl) * std::sin(az), -std::cos(tl));
  const Vec3 e1(-std::cos(tl) * std::cos(az), -std::cos(tl) * std::sin(az), std::sin(tl));
  const Vec3 e2 = e3.cross(e1);
  s.R0.col(0) = std::cos(tw) * e1 + std::sin(tw) * e2;
  s.R0.col(1) = -std::sin(tw) * e1 + std::cos(tw) * e2;
  s.R0.col(2) = e3;
  s.root = pose.position;
  const double zmin = t.shrink * t.r0[0] * std::sqrt(std::max(0.0, 1.0 - e3.z() * e3.z())) +
                      kRootClearance * t.model.tuft_length;
  s.root_clamped = s.root.z() < zmin;
  if (s.root_clamped) s.root.z() = zmin;
}

// plasticity (seed "Brush plasticity"): rest angles rho = clamp(theta', -alpha, alpha).  rho
// moves only when that target has moved by more than kPlasticDeadband: the plastic set has
// its own static friction, so a brush held still settles instead of creeping forever
void plasticity(const Tuft& t, BrushState& s) {
  s.x_prev = s.x;
  const double alpha = t.model.plasticity_alpha * kDeg;
  auto shift = [&](int k, double target) {
    if (std::abs(target - s.rest[k]) > kPlasticDeadband || alpha == 0.0) s.rest[k] = target;
  };
  for (int j = 0; j < t.n; ++j) {
    shift(2 * j, std::clamp(s.x[2 * j], -alpha, alpha));
    shift(2 * j + 1, j > 0 ? std::clamp(s.x[2 * j + 1], -alpha, alpha) : 0.0);
  }
}

// lowest point of the outer surface Omega_i (unshrunk) at node i, mm
double outer_low(const Tuft& t, const Workspace& w, int i) {
  return w.O[i].z() - detail::section_reach(t, w, i);
}

// a pressed node's stretches delta = 0 (a saddle of |delta^2 - S|^m when S > 0, where d/d delta
// vanishes) get a minimal value; true if one moved
bool kick_stretches(const Tuft& t, BrushState& s, int i) {
  bool kicked = false;
  const double kick = std::sqrt(kStretchKick * t.r0[i]);  // sqrt(mm)
  for (int k = 1; k <= 2; ++k) {
    double& dl = s.x[2 * t.n + 3 * (i - 1) + k];
    if (std::abs(dl) < kick) {
      dl = s.x_prev[2 * t.n + 3 * (i - 1) + k] = kick;
      kicked = true;
    }
  }
  return kicked;
}

// straight-skeleton trick (seed "Energy minimization problems"): a straight spine about to be
// pressed gets minimal bend angles, or no gradient could start the bending; likewise the
// stretches of a node under the paper.  In free air nothing is touched, so a brush at rest
// stays exactly at rest.  True if x moved.
bool kick_pressed(const Tuft& t, BrushState& s, const Workspace& w) {
  bool straight = true, kicked = false;
  for (int j = 0; j < t.n; ++j) straight = straight && std::abs(s.x[2 * j]) < kStraight;
  for (int i = 1; i <= t.n; ++i) {
    if (outer_low(t, w, i) >= 0.0) continue;
    if (straight) {
      for (int j = 0; j < t.n; ++j) s.x[2 * j] = s.x_prev[2 * j] = kThetaEps;
      straight = false;
      kicked = true;
    }
    // with spread_reach > 0, only where last frame's p_i > 0: a node under the paper whose
    // window is not yet pressed has S = 0, where delta = 0 is the minimum (a kick there is undone
    // by a slow quartic descent every frame, and a still pose never sleeps)
    const bool spreads = s.p[i] > 0.0 || !(t.model.spread_reach > 0.0);
    if (t.model.lateral_spreading && spreads && kick_stretches(t, s, i)) kicked = true;
  }
  return kicked;
}

// O_i, P_i^+ and P_i^- of the current kinematics, as last frame's points
void record_points(const Tuft& t, BrushState& s, const Workspace& w) {
  for (int i = 0; i <= t.n; ++i)
    for (int k = 0; k < 3; ++k) s.prev_pts[3 * i + k] = detail::touch_point(w, i, k);
}

// p_i, the proportion of the segment above node i whose surface is under the paper, from the
// lowest points of the unstretched sections above (h_above) and at (h) node i
double pressed_proportion(double h_above, double h) {
  if (h_above < 0 && h < 0) return 1.0;
  if (h_above >= 0 && h >= 0) return 0.0;
  return (h < 0 ? -h : -h_above) / std::abs(h - h_above);
}

// node i's contact: its p_i relaxed, and the normal force R shared by its touching points;
// returns how many of O_i, P_i^+, P_i^- touch
int node_contact(const Tuft& t, BrushState& s, const Workspace& w, int i, double p_new) {
  const BrushModel& md = t.model;
  // p_i is lagged like R_i (it comes from the first iterate, last frame's shape) and relaxed
  // the same way: p high spreads the section, the spread tuft lifts, p falls, and without
  // relaxation the footprint flips between two sizes every other frame
  s.p[i] += md.contact_relaxation * (p_new - s.p[i]);
  // a node touches when its height minus its effective radius is below the paper (r_sp = c of
  // the last frame, r_lat a fraction of it)
  const double rsp = s.c_prev[i], rl = md.lateral_radius_fraction * s.c_prev[i];
  const bool touch[3] = {w.O[i].z() - rsp < 0.0, detail::lateral_plus(w, i).z() - rl < 0.0,
                         detail::lateral_minus(w, i).z() - rl < 0.0};
  const int count = touch[0] + touch[1] + touch[2];
  // normal reaction R: last frame's contact force on this section (the seed's lagged force),
  // relaxed R <- R + omega (lambda - R): with omega = 1 a large force makes the tip stick, the
  // stuck tip unloads the section, the small force lets it slip, and the footprint flips
  // between two sizes every other frame (a period-2 cycle of the lagged iteration); omega
  // 1/2 damps it.
  const double lam = (md.collision && i - 1 < s.lambda.size()) ? std::max(s.lambda[i - 1], 0.0) : 0.0;
  double& Rr = s.R_relaxed[i - 1];
  Rr += md.contact_relaxation * (lam - Rr);
  // wet adhesion A_i pulls the touching points down (energy.cpp): the force that holds them up,
  // and so next frame's R, carries it.  (Added to R instead, as friction without a normal force,
  // it held lightly dragged sections back until they lifted, and the next frame, free of it,
  // put them down again: a period-2 cycle of the contact set.)
  const double adhesion = md.wet_adhesion * s.p[i] * std::clamp(s.wetness[i], 0.0, 1.0);
  for (int k = 0; k < 3; ++k) {
    const bool on = touch[k] && count > 0;
    s.R[3 * i + k] = on ? Rr / count : 0.0;
    s.pull[3 * i + k] = on ? adhesion / count : 0.0;
  }
  return count;
}

// p_i over the spine from O_{i-1-reach} down to O_i: the segment above node i (the seed's
// "associated tuft segment") and `reach` segments above it (fractional: the lower part of the
// last), each segment's proportion under the paper weighted by its length l_j; low[k] is the
// lowest point of node k's unstretched section.  With the segment above alone, p_i reaches 1
// as soon as node i-1 touches, and S = spread_gain r_i p_i stops growing: the widest section
// on the paper stops widening while the next one up, whose centre is still above the paper,
// cuts a narrower chord, and the footprint's width stands still over a range of press (a small
// brush dragged at 15 deg: 5.2 mm from 0.22 to 0.30 L, then 7.5 mm by 0.35 L).  The longer
// window lets each node spread until the one above has overtaken it (the model parameter
// spread_reach, 0 by default: the seed's segment above alone)
double window_proportion(const Tuft& t, const double* low, int i) {
  const double reach = t.model.spread_reach;
  if (!(reach > 0.0)) return pressed_proportion(low[i - 1], low[i]);
  double under = t.len[i - 1] * pressed_proportion(low[i - 1], low[i]), span = t.len[i - 1];
  for (int j = i - 2; j >= 0 && i - 2 - j < reach; --j) {
    const double f = std::min(1.0, reach - (i - 2 - j));  // the share of segment j in the window
    under += f * t.len[j] * pressed_proportion(low[j + 1] + f * (low[j] - low[j + 1]), low[j + 1]);
    span += f * t.len[j];
  }
  return under / span;
}

// frozen contact set at the first iterate.  p_i is measured on the unstretched section (radius
// r_i in the section plane), not on the spread one: measured on the spread surface, spreading
// (which flattens c) would lower p_i and so undo itself next frame, a period-2 cycle between
// frames.  Returns whether the tip node touches.
bool contact_set(const Tuft& t, BrushState& s, const Workspace& w) {
  double low[kMaxSegments + 1];
  for (int i = 0; i <= t.n; ++i)
    low[i] = w.O[i].z() - t.r0[i] * std::sqrt(std::max(0.0, 1.0 - w.nrm[i].z() * w.nrm[i].z()));
  s.contacts = 0;
  bool tip_touch = false;
  for (int i = 1; i <= t.n; ++i) {
    const int count = node_contact(t, s, w, i, window_proportion(t, low, i));
    s.contacts += count;
    if (i == t.n && count > 0) tip_touch = true;
    s.txy[i] = w.F[i - 1].col(2).head<2>();
  }
  return tip_touch;
}

// pore resistance (seed "Pore resistance"): a vertical blocking plane normal to the tip
// segment's projection, lead L = a t + b u + c ahead of the tip, t = max(|beta| - gamma, 0).
// The pores hold the plane where they trapped the tip: a tip pushed forward meets it, a
// trailing tip (a normal drag) draws it along; it is released when the tip lifts
void pore_plane(const Tuft& t, BrushState& s, const Workspace& w, bool tip_touch) {
  const BrushModel& md = t.model;
  s.pore_on = false;
  const Vec3 tip = w.F[t.n - 1].col(2);
  if (md.pore_resistance && md.collision && tip_touch && tip.head<2>().norm() > kVerticalTip) {
    const double beta = std::acos(std::min(1.0, std::abs(tip.z())));
    const double tt = std::max(beta - md.pore_gamma * kDeg, 0.0);
    const double up = std::max(s.lambda[t.n - 1], 0.0);
    const double L = md.pore_a * tt + md.pore_b * up + md.pore_c;
    const bool was_on = s.pore_on_prev;
    const Vec2 last_tip = s.prev_pts[3 * t.n].head<2>();
    s.pore_dir = tip.head<2>().normalized();
    s.pore_offset = s.pore_dir.dot(last_tip) + L;
    if (was_on) s.pore_offset = std::min(s.pore_offset, s.pore_dir.dot(s.pore_anchor));
    s.pore_anchor = last_tip + (s.pore_offset - s.pore_dir.dot(last_tip)) * s.pore_dir;
    s.pore_on = true;
  }
  s.pore_on_prev = s.pore_on;
}

}  // namespace

void prepare_frame(const Tuft& t, BrushState& s, const Pose& pose, Workspace& w) {
  pose.validate();
  s.pose = pose;
  set_root_frame(t, s, pose);
  plasticity(t, s);
  // until the brush first touches, phi_0 keeps the bending plane vertical (seed "Real-time
  // simulation": the lateral lines start horizontal; upright, the angle does not matter)
  if (!s.touched_since_reset) s.x[1] = s.x_prev[1] = -pose.twist_deg * kDeg;
  kinematics(t, s, s.x, w);
  if (kick_pressed(t, s, w)) kinematics(t, s, s.x, w);
  if (!s.have_prev_positions) {
    record_points(t, s, w);
    s.have_prev_positions = true;
  }
  const bool tip_touch = contact_set(t, s, w);
  pore_plane(t, s, w, tip_touch);
  const int m_old = s.m;
  s.m = (t.model.collision ? t.n : 0) + (s.pore_on ? 1 : 0);
  if (s.m > m_old && s.pore_on) s.lambda[s.m - 1] = 0.0;  // the plane starts without a force
  s.touched_since_reset = s.touched_since_reset || s.contacts > 0;
}

void end_frame(const Tuft& t, BrushState& s, Workspace& w) {
  kinematics(t, s, s.x, w);
  record_points(t, s, w);
  s.c_prev = w.c;
}

// ---------------------------------------------------------------------------------------------
// the state of a brush just made: straight, at the default pose's root frame, wet
BrushState initial_state(const Tuft& t) {
  BrushState s;
  const int n = t.n;
  s.x = s.x_prev = s.rest = VecX::Zero(t.nx);
  s.prev_pts.assign(3 * (n + 1), Vec3::Zero());
  s.R.assign(3 * (n + 1), 0.0);
  s.pull.assign(3 * (n + 1), 0.0);
  s.txy.assign(n + 1, Vec2::Zero());
  s.p = VecX::Zero(n + 1);
  s.c_prev = t.r0;
  s.wetness = VecX::Ones(n + 1);
  s.lambda = VecX::Zero(t.mmax);
  s.R_relaxed = VecX::Zero(n);
  s.H = MatX::Identity(t.na(), t.na());
  return s;
}

void reset_state(const Tuft& t, BrushState& s, Workspace& w) {
  // straight and unstrained: zero angles and stretches, rest shifts forgotten; the
  // straight-skeleton trick gives the bend angles a minimal value once pressed
  s.x = VecX::Zero(t.nx);
  s.x_prev = s.x;
  s.rest = VecX::Zero(t.nx);
  s.have_hessian = false;
  s.have_h_touching = false;
  s.hessian_contacts = -1;
  s.touched_since_reset = false;
  s.have_prev_positions = false;
  s.pore_on_prev = false;
  s.lambda.setZero();
  s.R_relaxed.setZero();
  s.p.setZero();
  s.c_prev = t.r0;
  s.nu = 0.0;
  kinematics(t, s, s.x, w);
  s.stats = StepStats();
  // per-step traces keep their capacity, so solve() does not allocate after this
  const int cap = t.model.q_max + 8;
  s.stats.merit_before.reserve(cap);
  s.stats.merit_after.reserve(cap);
  s.stats.step_sizes.reserve(cap);
  s.stats.kkt_trace.reserve(cap);
}

namespace {

// every per-node and per-variable array of s has the sizes t gives it
bool arrays_fit(const Tuft& t, const BrushState& s) {
  const int n = t.n;
  const auto size = [](const auto& v) { return static_cast<int>(v.size()); };
  const int node_arrays[] = {size(s.p), size(s.c_prev), size(s.wetness), size(s.txy)};
  for (int k : node_arrays)
    if (k != n + 1) return false;
  if (s.ink.loaded() && (size(s.ink.load) != n + 1 || size(s.ink.capacity) != n + 1)) return false;
  return s.x.size() == t.nx && s.x_prev.size() == t.nx && s.rest.size() == t.nx &&
         s.lambda.size() == t.mmax && s.R_relaxed.size() == n && size(s.prev_pts) == 3 * (n + 1) &&
         size(s.R) == 3 * (n + 1);
}

// the carried matrices are na x na (H_touching may not have been made yet)
bool matrices_fit(const Tuft& t, const BrushState& s) {
  const int na = t.na();
  const bool h = s.H.rows() == na && s.H.cols() == na;
  return h && (s.H_touching.size() == 0 || (s.H_touching.rows() == na && s.H_touching.cols() == na));
}

}  // namespace

void check_state_shape(const Tuft& t, const BrushState& s) {
  if (arrays_fit(t, s) && matrices_fit(t, s)) return;
  throw std::invalid_argument(
      "set_state: the state belongs to a brush of " + std::to_string(s.x.size() / 5) + " segments and " +
      std::to_string(s.H.rows()) + " active variables; this brush has " + std::to_string(t.n) +
      " segments and " + std::to_string(t.na()) + " active variables");
}

}  // namespace brushwork
