// Brush: the facade over (BrushTufts, BrushState) that the bindings use; a paper takes its
// frame().  The physics lives in tuft/*.cpp (kinematics, energy, frame set-up), solver/*.cpp (SQP,
// QP, BFGS), step.cpp (continuation sub-steps) and brush_step.cpp (the tufts of a split brush).
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

Brush::Brush(const BrushModel& model) : core_(model), state_(initial_state(core_)) { reset(); }

void Brush::reset() { reset_state(core_, state_); }

void Brush::set_state(const BrushState& s) { brushwork::set_state(core_, state_, s); }

Brush::Identity::Identity() {
  static std::atomic<std::uint64_t> next{1};
  value = next++;
}

TuftFrame Brush::tuft_frame(int k) const {
  const BrushModel& md = tuft(k).model;
  TuftFrame f;
  f.tuft = k;
  f.sections = sections(k);
  f.root = workspace(k).O[0];
  f.wetness = tuft_state(k).wetness;
  f.segment_mm = md.segment_lengths().maxCoeff();
  f.belly_mm = md.belly_radius;
  if (tuft_state(k).ink.loaded()) f.ramp = tuft_state(k).ink.ramp;
  return f;
}

BrushFrame Brush::frame() const {
  BrushFrame f;
  f.brush = id();
  f.nodes = core_.main.n + 1;
  f.pressure = node_pressure(sections());
  for (int k : tufts()) f.tufts.push_back(tuft_frame(k));
  return f;
}

std::vector<int> Brush::tufts() const {
  // even tufts replace this one while split (it is still solved, to merge back into)
  std::vector<int> all;
  if (!(core_.main.model.even_tufts && state_.tufts_active > 0)) all.push_back(0);
  for (int j = 0; j < state_.tufts_active; ++j) all.push_back(j + 1);
  return all;
}

void Brush::set_ink(const Ink& ink) {
  ink.validate(core_.main.n + 1);
  state_.ink = ink;
}

void Brush::spend_ink(const InkUse& use, const SceneFeatures& scene, Ink& ink) {
  ink.validate(core_.main.n + 1);
  if (use.drawn && use.pressure.size() != static_cast<std::size_t>(core_.main.n + 1))
    throw std::invalid_argument("spend_ink: the deposit measured " + std::to_string(use.pressure.size()) +
                                " nodes, the brush has " + std::to_string(core_.main.n + 1));
  brushwork::spend_ink(use, scene, ink, state_.wetness);
}

void Brush::prepare(const Pose& pose) { prepare_frame(core_.main, state_, pose, core_.ws); }

// ---------------------------------------------------------------------------------------------
// the frame problem in active variables, for tests and other solvers
VecX Brush::variables() const {
  VecX z(core_.main.na());
  detail::gather(core_.main, state_.x, z);
  return z;
}

void Brush::set_variables(const VecX& z) {
  if (z.size() != core_.main.na())
    throw std::invalid_argument("variables: expected " + std::to_string(core_.main.na()) + " values, got " +
                                std::to_string(z.size()));
  for (int k = 0; k < z.size(); ++k)
    if (!std::isfinite(z[k]))
      throw std::invalid_argument("variables: " + variable_names()[k] + " = " + num(z[k]) +
                                  " is not finite");
  detail::scatter(core_.main, z, state_.x);
  end_frame(core_.main, state_, core_.ws);
}

std::vector<std::string> Brush::variable_names() const {
  const int n = core_.main.n;
  std::vector<std::string> names;
  for (int idx : core_.main.active) {
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
  check_size(z, core_.main.active.size());
  VecX full = state_.x;
  detail::scatter(core_.main, z, full);
  return full;
}

// each query leaves the workspace's kinematics at the state's x, as it found them
double Brush::energy(const VecX& z) {
  const double E = evaluate(core_.main, state_, core_.ws, with_variables(z), nullptr, nullptr, nullptr);
  kinematics(core_.main, state_, state_.x, core_.ws);
  return E;
}

VecX Brush::energy_gradient(const VecX& z) {
  VecX gfull(core_.main.nx), ga(core_.main.na());
  evaluate(core_.main, state_, core_.ws, with_variables(z), &gfull, nullptr, nullptr);
  detail::gather(core_.main, gfull, ga);
  kinematics(core_.main, state_, state_.x, core_.ws);
  return ga;
}

VecX Brush::constraints(const VecX& z) {
  VecX g(core_.main.mmax);
  evaluate(core_.main, state_, core_.ws, with_variables(z), nullptr, &g, nullptr);
  kinematics(core_.main, state_, state_.x, core_.ws);
  return g.head(state_.m);
}

MatX Brush::constraint_jacobian(const VecX& z) {
  VecX g(core_.main.mmax);
  MatX J(core_.main.mmax, core_.main.nx);
  evaluate(core_.main, state_, core_.ws, with_variables(z), nullptr, &g, &J);
  MatX Ja(state_.m, core_.main.na());
  for (size_t k = 0; k < core_.main.active.size(); ++k) Ja.col(k) = J.col(core_.main.active[k]).head(state_.m);
  kinematics(core_.main, state_, state_.x, core_.ws);
  return Ja;
}

// ---------------------------------------------------------------------------------------------
// geometry of the current state
Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> Brush::skeleton(int k) const {
  const Workspace& w = workspace(k);
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> s(tuft(k).n + 1, 3);
  for (int i = 0; i <= tuft(k).n; ++i) s.row(i) = w.O[i].transpose();
  return s;
}

Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> Brush::lateral_nodes() const {
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> s(2 * (core_.main.n + 1), 3);
  for (int i = 0; i <= core_.main.n; ++i) {
    s.row(2 * i) = detail::lateral_plus(core_.ws, i).transpose();
    s.row(2 * i + 1) = detail::lateral_minus(core_.ws, i).transpose();
  }
  return s;
}

std::vector<Section> Brush::sections() const {
  std::vector<Section> secs = brushwork::sections(core_.main, core_.ws);
  if (state_.tufts_active == 0 || core_.main.model.even_tufts) return secs;
  // split: below N_i the main tuft keeps tuft_core of its major radii, the children the rest
  for (int i = state_.split_node + 1; i <= core_.main.n; ++i) {
    secs[i].a_plus *= core_.main.model.tuft_core;
    secs[i].a_minus *= core_.main.model.tuft_core;
  }
  return secs;
}

std::vector<Section> Brush::sections(int k) const {
  return k == 0 ? sections() : brushwork::sections(tuft(k), workspace(k));
}

SurfaceMesh Brush::surface_mesh(const MeshOptions& opt) const { return sweep_surface(sections(), opt); }

Loops Brush::own_footprint(const MeshOptions& opt) const { return footprint_of(sections(), opt); }

Loops Brush::footprint(const MeshOptions& opt) const {
  Loops all;
  for (int k : tufts()) {
    Loops l = footprint_of(sections(k), opt);
    all.insert(all.end(), l.begin(), l.end());
  }
  return all;
}

double Brush::footprint_area(const MeshOptions& opt) const {
  double area = 0.0;
  for (int k : tufts()) area += loops_area(footprint_of(sections(k), opt));
  return area;
}

VecX Brush::section_heights() const { return brushwork::section_heights(core_.main, core_.ws); }

}  // namespace brushwork
