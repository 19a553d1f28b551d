// The Chu-Tai brush: a thin facade over its tufts (BrushTufts: the main tuft and its children,
// read-only, with their scratch Workspaces) and its state (BrushState, one copyable value, the
// children's states in it); see step.hpp and tufts.hpp.
//
// step(pose) = one frame (seed "Energy minimization problems", "Real-time simulation"):
//   1. the root moves to the pose; plasticity shifts the rest angles; the contact set, the
//      proportions p_i and the normal forces R_i are frozen at the first iterate;
//   2. local SQP minimises the incremental potential (strain + internal friction + external
//      friction) subject to the non-penetration of the shrunk sections Phi_i and, while the tip
//      touches, the pore-resistance blocking plane;
//   3. the BFGS matrix L_xx (kept as its inverse H = L_xx^-1) carries into the next frame.
//
// Degrees of freedom, in the order of the full variable vector x (5n entries):
//   x[2j]   = theta_j  bend angle at joint j (j = 0..n-1; joint j joins segment j to what is above it)
//   x[2j+1] = phi_j    turn angle at joint j (phi_0: the plane of bending, no twist spring)
//   x[2n + 3(i-1) + 0] = psi_i     rotation of the lateral line of node i in its bisecting plane
//   x[2n + 3(i-1) + 1] = delta+_i  stretch of the lateral node on the +u side (distance r_i - r_lat + delta^2)
//   x[2n + 3(i-1) + 2] = delta-_i  stretch on the -u side                       (i = 1..n)
// Features a model turns off remove their variables (delta with lateral_spreading off).
//
// Double precision throughout: the problem has tens of variables, so float buys no speed (the
// cost is in branches and tiny products, not memory bandwidth), while stiffness ratios up to 1e4
// with m = 3 and BFGS updates carried over thousands of frames need the extra digits.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "brushwork/geometry.hpp"
#include "brushwork/model.hpp"
#include "brushwork/state.hpp"
#include "brushwork/step.hpp"
#include "brushwork/tuft_frame.hpp"
#include "brushwork/tufts.hpp"

namespace brushwork {

class Brush {
 public:
  explicit Brush(const BrushModel& model);

  const BrushModel& model() const { return core_.main.model; }
  // one frame: this tuft's minimisation, then (model.tufts > 0) sprouting, each sprouted child
  // tuft's own minimisation and merging (seed "Simulation with multiple tufts"; tufts.hpp)
  StepStats step(const Pose& pose) { return brushwork::step(core_, state_, pose); }
  const StepStats& last_stats() const { return state_.stats; }
  void reset();  // straight, unstrained, plasticity forgotten, Hessian forgotten

  // the whole mutable state, as a value: state() is a copy; set_state() puts one back (throws
  // std::invalid_argument if it was made for a brush of another shape)
  BrushState state() const { return state_; }  // this tuft's state, the children's in its `children`
  void set_state(const BrushState& s);

  // geometry of the current state
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> skeleton() const { return skeleton(0); }  // (n+1, 3) mm
  // (n_k+1, 3) mm, the spine of tuft k: 0 this one, 1 + j the child T_j
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> skeleton(int k) const;
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> lateral_nodes() const;   // (2(n+1), 3) mm: node i at rows 2i (+u) and 2i+1 (-u)
  std::vector<Section> sections() const;  // Omega_0..Omega_n (below N_i thinned by tuft_core while satellites sprout)
  SurfaceMesh surface_mesh(const MeshOptions& opt) const;
  Loops footprint(const MeshOptions& opt) const;        // the loops of every tuft of tufts()
  double footprint_area(const MeshOptions& opt) const;  // mm^2, summed over the tufts
  Loops own_footprint(const MeshOptions& opt) const;    // this tuft's loops alone

  // the tufts that meet the paper: this tuft (0), then each sprouted child T_j (1 + j, a tuft of
  // model().split_model()); while even tufts replace this one, those alone
  std::vector<int> tufts() const;
  int tufts_active() const { return state_.tufts_active; }
  // what a paper takes of the brush now: each tuft of tufts() as geometry and wetness, this
  // tuft's node pressure, and the brush's identity
  BrushFrame frame() const;
  // the brush's identity, kept by assignment (a brush that becomes a copy of another is still
  // itself on the paper) and new in every brush constructed or copy-constructed
  std::uint64_t id() const { return id_.value; }
  Eigen::VectorXd section_heights() const;  // (n,) mm, lowest point of Phi_1..Phi_n (the constraints g_i)
  // mm, the lowest point of every sprouted tuft's sections Omega_1..Omega_n above the paper
  double clearance() const { return brushwork::clearance(core_, state_); }

  // the frame problem, for tests and other solvers: prepare() does step()'s set-up (pose,
  // plasticity, frozen contact set) without solving; the functions below then evaluate it at
  // any active-variable vector z.
  void prepare(const Pose& pose);
  int num_variables() const { return core_.main.na(); }
  int num_constraints() const { return state_.m; }
  VecX variables() const;            // (num_variables,) current active variables
  void set_variables(const VecX& z); // validates size and finiteness
  double energy(const VecX& z);
  VecX energy_gradient(const VecX& z);
  VecX constraints(const VecX& z);           // (m,) g(z) >= 0 is feasible, mm
  MatX constraint_jacobian(const VecX& z);   // (m, num_variables)
  std::vector<std::string> variable_names() const;
  VecX full_state() const { return state_.x; }  // (5n,) all variables, fixed ones included
  VecX multipliers() const { return state_.lambda.head(state_.m); }  // (m,) N, last frame's contact forces

  // per-node wetness in [0, 1] (n+1,), used by wet adhesion; the ink's depletion sets it
  VecX& wetness() { return state_.wetness; }
  const VecX& wetness() const { return state_.wetness; }

  // the ink on the brush, part of its state (not loaded until set_ink or Ink::full)
  Ink& ink() { return state_.ink; }
  const Ink& ink() const { return state_.ink; }
  void set_ink(const Ink& ink);  // validates it for this brush's n+1 nodes
  // the ink's state update after a deposit took `use` of it: `ink` (the brush's own or any other of
  // its n+1 nodes) spent as the scene says, this tuft's wetness set from it (spend_ink, ink.hpp)
  void spend_ink(const InkUse& use, const SceneFeatures& scene, Ink& ink);

 private:
  // the full vector x with the active variables z put in (validates z's size)
  VecX with_variables(const VecX& z) const;
  // tuft k (as tufts() numbers them): its read-only tuft, its scratch (kinematics) and its state
  const Tuft& tuft(int k) const { return k == 0 ? core_.main : core_.children[k - 1]; }
  const Workspace& workspace(int k) const { return k == 0 ? core_.ws : core_.child_ws[k - 1]; }
  const BrushState& tuft_state(int k) const { return k == 0 ? state_ : state_.children[k - 1]; }
  std::vector<Section> sections(int k) const;  // Omega_0..Omega_n of tuft k
  TuftFrame tuft_frame(int k) const;

  struct Identity {
    std::uint64_t value;
    Identity();
    Identity(const Identity&) : Identity() {}
    Identity& operator=(const Identity&) { return *this; }
  };

  BrushTufts core_;
  BrushState state_;
  Identity id_;
};

}  // namespace brushwork
