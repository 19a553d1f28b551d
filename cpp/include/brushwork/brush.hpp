// One tuft of the Chu-Tai brush: its state, its per-frame energy minimisation, its geometry.
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
#include <Eigen/Geometry>
#include <chrono>
#include <string>
#include <vector>

#include "brushwork/geometry.hpp"
#include "brushwork/model.hpp"

namespace brushwork {

using Mat3 = Eigen::Matrix3d;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;
using Loops = std::vector<Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>;

// Where the hand holds the brush.  position: the tuft root (where the hairs leave the ferrule),
// mm, paper at z = 0.  tilt: angle between the handle and the paper normal (0 = upright), deg.
// azimuth: the direction on the paper toward which the handle leans, deg from +x.  twist: rotation
// of the handle about its own axis, deg.
struct Pose {
  Vec3 position = Vec3(0, 0, 40);
  double tilt_deg = 0.0;
  double azimuth_deg = 0.0;
  double twist_deg = 0.0;
  void validate() const;  // throws std::invalid_argument naming the field
};

// Statistics of the last step (seed Table 1 counts iterations q per frame).
struct StepStats {
  int iterations = 0;           // SQP iterations (QP solves with an accepted step) this frame
  double energy = 0.0;          // incremental potential at the end of the frame, N*mm
  double kkt_residual = 0.0;    // scaled KKT residual at the end of the frame
  double max_penetration = 0.0; // mm, deepest point of the shrunk sections Phi_i below the paper
  bool converged = false;       // kkt_residual <= tolerance
  double time = 0.0;            // s, wall time of step()
  int line_search_failures = 0; // iterations whose line search found no decrease
  int hessian_resets = 0;       // times H was reset to the diagonal start this frame
  int contacts = 0;             // nodes (spine + lateral) in the frozen contact set
  bool root_clamped = false;    // the pose put the ferrule into the paper; root held on it
  bool pore_active = false;     // the blocking plane was in the problem this frame
  int substeps = 1;             // the frame was split into this many sub-steps (continuation)
  double penalty = 0.0;         // nu of the l1 merit function
  std::string status;           // "converged", "iteration cap", "line search", "qp", "no motion"
  std::vector<double> merit_before, merit_after;  // per accepted step, with the same nu
  std::vector<double> step_sizes;                 // alpha of each accepted step
  std::vector<double> kkt_trace;                  // KKT residual after each accepted step
};

class Brush {
 public:
  explicit Brush(const BrushModel& model);

  const BrushModel& model() const { return model_; }
  StepStats step(const Pose& pose);
  const StepStats& last_stats() const { return stats_; }
  void reset();  // straight, unstrained, plasticity forgotten, Hessian forgotten

  // geometry of the current state
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> skeleton() const;        // (n+1, 3) mm
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> lateral_nodes() const;   // (2(n+1), 3) mm: node i at rows 2i (+u) and 2i+1 (-u)
  std::vector<Section> sections() const;                                             // Omega_0..Omega_n
  SurfaceMesh surface_mesh(const MeshOptions& opt) const;
  Loops footprint(const MeshOptions& opt) const;
  double footprint_area(const MeshOptions& opt) const;
  Eigen::VectorXd section_heights() const;  // (n,) mm, lowest point of Phi_1..Phi_n (the constraints g_i)

  // the frame problem, for tests and other solvers: prepare() does step()'s set-up (pose,
  // plasticity, frozen contact set) without solving; the functions below then evaluate it at
  // any active-variable vector z.
  void prepare(const Pose& pose);
  int num_variables() const { return static_cast<int>(active_.size()); }
  int num_constraints() const { return m_; }
  VecX variables() const;            // (num_variables,) current active variables
  void set_variables(const VecX& z); // validates size and finiteness
  double energy(const VecX& z);
  VecX energy_gradient(const VecX& z);
  VecX constraints(const VecX& z);           // (m,) g(z) >= 0 is feasible, mm
  MatX constraint_jacobian(const VecX& z);   // (m, num_variables)
  std::vector<std::string> variable_names() const;
  VecX full_state() const { return x_; }     // (5n,) all variables, fixed ones included
  VecX multipliers() const { return lambda_.head(m_); }  // (m,) N, last frame's contact forces

  // per-node wetness in [0, 1] (n+1,), used by wet adhesion; ink and drying build on it
  VecX wetness;

 private:
  // --- forward kinematics at the full vector x (seed Figure 2) ---
  void kinematics(const VecX& x);
  // --- everything at x: energy, and if asked its gradient and the constraints with Jacobian ---
  double evaluate(const VecX& x, VecX* grad, VecX* g, MatX* J);
  // map node-level gradients (positions, lateral directions, lateral distances) to x
  void chain(VecX& gx) const;
  // one Jacobian row of a constraint on node i alone (chain() with only node i's gradients)
  void constraint_row(int i, const Vec3& gO, const Vec3& gu, double gdp, double gdm, MatX& J,
                      int row) const;
  void clear_node_grads();
  void begin_frame(const Pose& pose);
  void end_frame();
  void fresh_hessian();
  void gather(const VecX& full, VecX& act) const;
  void scatter(const VecX& act, VecX& full) const;
  double kkt(const VecX& gact, const VecX& g, const MatX& Jact, const VecX& lam, int m) const;
  void solve();
  int solve_box_qp(int m, double nu);
  bool soc_solve(const int* idx, int k);

  BrushModel model_;
  int n_ = 0, nx_ = 0, m_ = 0, mmax_ = 0;
  double m_exp_ = 2.0, f_scale_ = 1.0, shrink_ = 0.5;

  // constants of the model (per segment j = 0..n-1 or node i = 0..n)
  VecX len_, r0_, rlat_, kb_, kt_, kpsi_;
  VecX klb_;                        // (n+1,) N*mm, lateral bend springs at node i
  double ks_ = 0.0, eta_ = 0.0;

  // state
  VecX x_, x_prev_, rest_;         // (5n,) variables, last frame's, rest shifts rho (angles only)
  std::vector<int> active_;        // active variable indices into x
  MatX H_;                         // (na, na) inverse BFGS matrix L_xx^-1
  bool have_hessian_ = false, touched_since_reset_ = false, have_prev_positions_ = false;
  Pose pose_;
  Vec3 root_ = Vec3::Zero();
  Mat3 R0_ = Mat3::Identity();
  bool root_clamped_ = false;
  bool same_pose_ = false;         // this frame's pose equals the last one (sleep rule)
  double nu_ = 1.0;
  VecX lambda_;                    // (mmax,) multipliers of the last QP
  VecX R_relaxed_;                 // (n,) N, the relaxed normal reaction of sections 1..n
  VecX c_prev_;                    // (n+1,) minor radius c_i at the end of the last frame (r_sp)

  // frozen frame data (first iterate)
  std::vector<Vec3> prev_pts_;           // (3(n+1)) world positions of O_i, P_i^+, P_i^- last frame
  std::vector<double> R_;                // (3(n+1)) normal force R for nodes in contact, else 0
  std::vector<Eigen::Vector2d> txy_;     // (n+1) unnormalised horizontal projection of the segment above node i
  VecX p_;                               // (n+1) proportion of the segment above node i under the paper
  bool pore_on_ = false;
  Eigen::Vector2d pore_dir_ = Eigen::Vector2d::Zero();  // unit, tip direction on the paper
  double pore_offset_ = 0.0;             // pore_dir . O_n must stay <= pore_offset_ (mm)
  bool pore_on_prev_ = false;            // the plane was in last frame's problem
  Eigen::Vector2d pore_anchor_ = Eigen::Vector2d::Zero();  // a point of the plane, mm
  int contacts_ = 0;
  int hessian_contacts_ = -1;  // contacts_ of the frame the carried Hessian last solved
  MatX H_touching_;            // (na, na) H_ as the brush last left the paper
  bool have_h_touching_ = false;

  // kinematics workspace (sized once)
  std::vector<Vec3> O_, u_, w_, nrm_, aphi_, ath_;
  std::vector<Mat3> F_, Q_;
  VecX d_plus_, d_minus_, c_;
  // node-level gradient workspace
  std::vector<Vec3> gO_, gu_, tau_;  // d/dO_i, d/du_i, and the torque of vectors fixed in node i's lateral frame
  std::vector<Vec3> lb_rest_[2];      // rest (t_i - t_{i-1}) of each side's lateral polyline, in (w_i, u_i, n_i) coordinates
  VecX gdp_, gdm_;

  // solver workspace (sized once; nothing is allocated inside solve())
  VecX x_eval_, step_;  // x at the last kinematics() (5n), SQP step (na)
  VecX xf_trial_, za_, zt_, gf_, gf_new_, gact_, gact_new_, g_, g_new_, gtrial_;
  VecX s_, yv_, r_, Hr_, Bs_, tmp_, h0_;
  MatX J_, Jact_, Jact_new_, HJt_, M_;
  VecX q_, lam_, lam_f_, lam_old_, qp_grad_;
  std::vector<int> qp_state_;
  Eigen::MatrixXd Mff_;
  VecX rhs_;
  // the state step() puts back when it splits a frame into sub-steps (sized once)
  struct FrameSave {
    VecX x, x_prev, rest, lambda;
    Pose pose;
    bool touched = false, have_prev = false, pore_on_prev = false;
    Eigen::Vector2d pore_anchor = Eigen::Vector2d::Zero();
    int m = 0;
  } save_;
  StepStats stats_;
};

}  // namespace brushwork
