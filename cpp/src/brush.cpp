// Brush: the facade over (Tuft, BrushState, Workspace) that the bindings and the renderer use.
// The physics lives in tuft/*.cpp (kinematics, energy, frame set-up), solver/*.cpp (SQP, QP,
// BFGS) and step.cpp (continuation sub-steps).
#include "brushwork/brush.hpp"

#include <atomic>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "brushwork/tufts.hpp"
#include "tuft/internal.hpp"

namespace brushwork {

namespace {

// mm and deg: the largest |coordinate| or angle a pose may hold
constexpr double kPoseBound = 1e6;
constexpr double kMaxTiltDeg = 89.9;  // deg: the handle stays above the paper's plane

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

void check_size(const VecX& z, size_t n) {
  if (z.size() != static_cast<int>(n))
    throw std::invalid_argument("expected " + std::to_string(n) + " variables, got " +
                                std::to_string(z.size()));
}

}  // namespace

void Pose::validate() const {
  check_finite("position[0] (x, mm)", position.x(), -kPoseBound, kPoseBound);
  check_finite("position[1] (y, mm)", position.y(), -kPoseBound, kPoseBound);
  check_finite("position[2] (z, mm)", position.z(), -kPoseBound, kPoseBound);
  check_finite("tilt_deg", tilt_deg, 0.0, kMaxTiltDeg);
  check_finite("azimuth_deg", azimuth_deg, -kPoseBound, kPoseBound);
  check_finite("twist_deg", twist_deg, -kPoseBound, kPoseBound);
}

Brush::Brush(const BrushModel& model) : tuft_(model), state_(initial_state(tuft_)), ws_(tuft_) {
  if (model.tufts > 0) children_.assign(model.tufts, Brush(model.split_model()));
  state_.split_node = sprout_node();
  reset();
}

void Brush::reset() {
  // a simple reset reverts a split brush to a single tuft
  reset_state(tuft_, state_, ws_);
  state_.tufts_active = 0;
  hang_children(sprout_node());
  for (Brush& c : children_) c.reset();
}

void Brush::hang_children(int node) {
  if (node == state_.split_node) return;
  for (Brush& c : children_) c = Brush(tuft_.model.child_model(node));
  state_.split_node = node;
}

StepStats Brush::step(const Pose& pose) {
  StepStats st = brushwork::step(tuft_, state_, pose, ws_);
  if (children_.empty()) return st;
  step_children(st);
  state_.stats = st;
  return st;
}

void Brush::step_children(StepStats& st) {
  const BrushModel& md = tuft_.model;
  // friction acts only in contact: a tuft in the air does not sprout
  const double score = sprout_score(tuft_, state_, ws_, md.tuft_node);
  if (state_.tufts_active == 0 && st.contacts > 0 && score >= md.sprout_spread) sprout();
  // the satellites' parent node N_i spreads as a split does: it becomes N_{i-1}
  else if (state_.tufts_active > 0 && !md.even_tufts && state_.split_node > 1 && st.contacts > 0 &&
           split_reach(tuft_, state_, ws_, state_.split_node) >= md.sprout_spread)
    grow();
  st.tuft_iterations = 0;
  st.sprout_score = score;
  for (int j = 0; j < state_.tufts_active; ++j) {
    const Vec2 r = child_displacement(j, md.tufts, md.even_tufts);
    const Pose p = child_pose(tuft_, state_, ws_, state_.split_node, r);
    // the tufts share the brush's ink: a child is as wet as the parent's nodes from its root down
    VecX& wet = children_[j].state_.wetness;
    wet = state_.wetness.tail(wet.size());
    const StepStats& cs = children_[j].step(p);
    st.tuft_iterations += cs.iterations;
    st.max_penetration = std::max(st.max_penetration, cs.max_penetration);
    st.time += cs.time;
  }
  // a split brush stays split while any of its tufts is near the paper (merged there, the one
  // tuft would lay its whole belly down); clear of it by merge_clearance, the tufts close into
  // one once the spread has fallen below half of sprout_spread
  if (state_.tufts_active > 0 && score < 0.5 * md.sprout_spread && clearance() > md.merge_clearance)
    state_.tufts_active = 0;
  st.tufts_active = state_.tufts_active;
}

double Brush::clearance() const {
  double low = tuft_clearance(tuft_, ws_);
  for (int j = 0; j < state_.tufts_active; ++j) low = std::min(low, children_[j].clearance());
  return low;
}

void Brush::sprout() {
  state_.tufts_active = static_cast<int>(children_.size());
  hang_children(sprout_node());
  for (Brush& c : children_) {
    c.reset();
    seed_child(tuft_, state_, state_.split_node, c.tuft_, c.state_);
    kinematics(c.tuft_, c.state_, c.state_.x, c.ws_);
  }
}

void Brush::grow() {
  const int node = state_.split_node - 1;
  for (Brush& c : children_) {
    const BrushState old = c.state_;
    c = Brush(tuft_.model.child_model(node));
    grow_child(tuft_, state_, node, old, c.tuft_, c.state_);
    kinematics(c.tuft_, c.state_, c.state_.x, c.ws_);
  }
  state_.split_node = node;
}

BrushState Brush::state() const {
  BrushState s = state_;
  for (const Brush& c : children_) s.children.push_back(c.state_);
  return s;
}

void Brush::set_state(const BrushState& s) {
  check_state_shape(tuft_, s);
  if (s.children.size() != children_.size())
    throw std::invalid_argument("state: expected " + std::to_string(children_.size()) +
                                " child tufts, got " + std::to_string(s.children.size()));
  if (!children_.empty()) {
    // satellites hang from N_1..N_{tuft_node}, even tufts from the root
    const bool hung = s.split_node == sprout_node() ||
                      (!tuft_.model.even_tufts && s.split_node >= 1 && s.split_node < tuft_.model.tuft_node);
    if (!hung)
      throw std::invalid_argument("state: child tufts on node " + std::to_string(s.split_node) +
                                  ", which this brush's children cannot hang from");
    hang_children(s.split_node);
  }
  for (size_t j = 0; j < children_.size(); ++j) children_[j].set_state(s.children[j]);
  state_ = s;
  state_.children.clear();
  kinematics(tuft_, state_, state_.x, ws_);
}

Brush::Identity::Identity() {
  static std::atomic<std::uint64_t> next{1};
  value = next++;
}

TuftFrame Brush::tuft_frame(int index) const {
  const Brush& t = index == 0 ? *this : children_[index - 1];
  TuftFrame f;
  f.tuft = index;
  f.sections = t.sections();
  f.root = t.ws_.O[0];
  f.wetness = t.state_.wetness;
  f.segment_mm = t.tuft_.model.segment_lengths().maxCoeff();
  f.belly_mm = t.tuft_.model.belly_radius;
  if (t.state_.ink.loaded()) f.ramp = t.state_.ink.ramp;
  return f;
}

BrushFrame Brush::frame() const {
  BrushFrame f;
  f.brush = id();
  f.nodes = tuft_.n + 1;
  f.pressure = node_pressure(sections());
  // even tufts replace this one while split (as in tufts())
  if (!(tuft_.model.even_tufts && state_.tufts_active > 0)) f.tufts.push_back(tuft_frame(0));
  for (int j = 0; j < state_.tufts_active; ++j) f.tufts.push_back(tuft_frame(j + 1));
  return f;
}

std::vector<const Brush*> Brush::tufts() const {
  // even tufts replace this one while split (it is still solved, to merge back into)
  std::vector<const Brush*> all;
  if (!(tuft_.model.even_tufts && state_.tufts_active > 0)) all.push_back(this);
  for (int j = 0; j < state_.tufts_active; ++j) all.push_back(&children_[j]);
  return all;
}

void Brush::set_ink(const Ink& ink) {
  ink.validate(tuft_.n + 1);
  state_.ink = ink;
}

void Brush::spend_ink(const InkUse& use, const SceneFeatures& scene, Ink& ink) {
  ink.validate(tuft_.n + 1);
  if (use.drawn && use.pressure.size() != static_cast<std::size_t>(tuft_.n + 1))
    throw std::invalid_argument("spend_ink: the deposit measured " + std::to_string(use.pressure.size()) +
                                " nodes, the brush has " + std::to_string(tuft_.n + 1));
  brushwork::spend_ink(use, scene, ink, state_.wetness);
}

void Brush::prepare(const Pose& pose) { prepare_frame(tuft_, state_, pose, ws_); }

// ---------------------------------------------------------------------------------------------
// the frame problem in active variables, for tests and other solvers
VecX Brush::variables() const {
  VecX z(tuft_.na());
  detail::gather(tuft_, state_.x, z);
  return z;
}

void Brush::set_variables(const VecX& z) {
  if (z.size() != tuft_.na())
    throw std::invalid_argument("variables: expected " + std::to_string(tuft_.na()) + " values, got " +
                                std::to_string(z.size()));
  for (int k = 0; k < z.size(); ++k)
    if (!std::isfinite(z[k]))
      throw std::invalid_argument("variables: " + variable_names()[k] + " = " + num(z[k]) +
                                  " is not finite");
  detail::scatter(tuft_, z, state_.x);
  end_frame(tuft_, state_, ws_);
}

std::vector<std::string> Brush::variable_names() const {
  const int n = tuft_.n;
  std::vector<std::string> names;
  for (int idx : tuft_.active) {
    if (idx < 2 * n) {
      names.push_back((idx % 2 == 0 ? "theta_" : "phi_") + std::to_string(idx / 2));
    } else {
      const int i = (idx - 2 * n) / 3 + 1, k = (idx - 2 * n) % 3;
      names.push_back((k == 0 ? "psi_" : k == 1 ? "delta+_" : "delta-_") + std::to_string(i));
    }
  }
  return names;
}

VecX Brush::with_variables(const VecX& z) const {
  check_size(z, tuft_.active.size());
  VecX full = state_.x;
  detail::scatter(tuft_, z, full);
  return full;
}

// each query leaves the workspace's kinematics at the state's x, as it found them
double Brush::energy(const VecX& z) {
  const double E = evaluate(tuft_, state_, ws_, with_variables(z), nullptr, nullptr, nullptr);
  kinematics(tuft_, state_, state_.x, ws_);
  return E;
}

VecX Brush::energy_gradient(const VecX& z) {
  VecX gfull(tuft_.nx), ga(tuft_.na());
  evaluate(tuft_, state_, ws_, with_variables(z), &gfull, nullptr, nullptr);
  detail::gather(tuft_, gfull, ga);
  kinematics(tuft_, state_, state_.x, ws_);
  return ga;
}

VecX Brush::constraints(const VecX& z) {
  VecX g(tuft_.mmax);
  evaluate(tuft_, state_, ws_, with_variables(z), nullptr, &g, nullptr);
  kinematics(tuft_, state_, state_.x, ws_);
  return g.head(state_.m);
}

MatX Brush::constraint_jacobian(const VecX& z) {
  VecX g(tuft_.mmax);
  MatX J(tuft_.mmax, tuft_.nx);
  evaluate(tuft_, state_, ws_, with_variables(z), nullptr, &g, &J);
  MatX Ja(state_.m, tuft_.na());
  for (size_t k = 0; k < tuft_.active.size(); ++k) Ja.col(k) = J.col(tuft_.active[k]).head(state_.m);
  kinematics(tuft_, state_, state_.x, ws_);
  return Ja;
}

// ---------------------------------------------------------------------------------------------
// geometry of the current state
Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> Brush::skeleton() const {
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> s(tuft_.n + 1, 3);
  for (int i = 0; i <= tuft_.n; ++i) s.row(i) = ws_.O[i].transpose();
  return s;
}

Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> Brush::lateral_nodes() const {
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> s(2 * (tuft_.n + 1), 3);
  for (int i = 0; i <= tuft_.n; ++i) {
    s.row(2 * i) = detail::lateral_plus(ws_, i).transpose();
    s.row(2 * i + 1) = detail::lateral_minus(ws_, i).transpose();
  }
  return s;
}

std::vector<Section> Brush::sections() const {
  std::vector<Section> secs = brushwork::sections(tuft_, ws_);
  if (state_.tufts_active == 0 || tuft_.model.even_tufts) return secs;
  // split: below N_i the main tuft keeps tuft_core of its major radii, the children the rest
  for (int i = state_.split_node + 1; i <= tuft_.n; ++i) {
    secs[i].a_plus *= tuft_.model.tuft_core;
    secs[i].a_minus *= tuft_.model.tuft_core;
  }
  return secs;
}

SurfaceMesh Brush::surface_mesh(const MeshOptions& opt) const { return sweep_surface(sections(), opt); }

Loops Brush::own_footprint(const MeshOptions& opt) const { return footprint_loops(surface_mesh(opt)); }

Loops Brush::footprint(const MeshOptions& opt) const {
  Loops all;
  for (const Brush* t : tufts()) {
    Loops l = t->own_footprint(opt);
    all.insert(all.end(), l.begin(), l.end());
  }
  return all;
}

double Brush::footprint_area(const MeshOptions& opt) const {
  double area = 0.0;
  for (const Brush* t : tufts()) area += loops_area(t->own_footprint(opt));
  return area;
}

VecX Brush::section_heights() const { return brushwork::section_heights(tuft_, ws_); }

}  // namespace brushwork
