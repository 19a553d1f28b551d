// BrushState: every mutable thing of one tuft, as one copyable value (MuJoCo's mjData).
// The read-only parameters are BrushModel (and the constants derived from it, Tuft); the
// scratch buffers of a frame are Workspace (step.hpp).  Copying a BrushState and putting it
// back later makes the brush continue bit for bit as it would have from that moment.
#pragma once

#include <array>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "brushwork/geometry.hpp"
#include "brushwork/ink.hpp"

namespace brushwork {

using Mat3 = Eigen::Matrix3d;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;

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
  bool operator==(const Pose& o) const {
    return position == o.position && tilt_deg == o.tilt_deg && azimuth_deg == o.azimuth_deg &&
           twist_deg == o.twist_deg;
  }
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
  int tufts_active = 0;         // child tufts T_j sprouted after this frame
  int tuft_iterations = 0;      // SQP iterations of the child tufts' own minimisations this frame
  double sprout_score = 0.0;    // the main tuft's sprouting score (tufts.hpp) this frame
  std::string status;           // "converged", "iteration cap", "line search", "qp", "no motion"
  std::vector<double> merit_before, merit_after;  // per accepted step, with the same nu
  std::vector<double> step_sizes;                 // alpha of each accepted step
  std::vector<double> kkt_trace;                  // KKT residual after each accepted step
};

struct BrushState {
  // --- degrees of freedom (5n,), in the order brush.hpp lists ---
  VecX x;         // variables theta, phi, psi, delta+, delta- (rad, rad, rad, sqrt(mm), sqrt(mm))
  VecX x_prev;    // last frame's x
  VecX rest;      // plastic rest shifts rho (angles only; stretches stay 0)

  // --- lagged contact data carried from frame to frame ---
  VecX lambda;     // (n+1,) N, multipliers of the last QP (sections 1..n, then the pore plane)
  VecX R_relaxed;  // (n,) N, relaxed normal reaction of sections 1..n
  VecX p;          // (n+1,) -, proportion of the segment above node i under the paper (relaxed)
  VecX c_prev;     // (n+1,) mm, minor radius c_i at the end of the last frame (r_sp)
  std::vector<Vec3> prev_pts;  // (3(n+1)) mm, world positions of O_i, P_i^+, P_i^- last frame
  bool have_prev_positions = false;  // prev_pts hold a real frame
  bool touched_since_reset = false;  // the tuft has touched the paper since reset()

  // --- carried BFGS matrix (seed "Real-time simulation") ---
  MatX H;                      // (na, na) inverse BFGS matrix L_xx^-1
  MatX H_touching;             // (na, na) H as the brush last left the paper
  bool have_hessian = false, have_h_touching = false;
  int hessian_contacts = -1;   // contacts of the frame the carried H last solved
  double nu = 1.0;             // penalty of the l1 merit function, N

  // --- frozen frame data (first iterate of the current frame) ---
  int m = 0;                           // constraints in this frame's problem
  int contacts = 0;                    // nodes (spine + lateral) in the contact set
  std::vector<double> R;               // (3(n+1)) N, normal force of each node in contact, else 0
  std::vector<double> pull;            // (3(n+1)) N, wet adhesion pulling each node in contact down
  std::vector<Vec2> txy;               // (n+1) unnormalised horizontal projection of the segment above node i
  bool pore_on = false;                // the blocking plane is in this frame's problem
  bool pore_on_prev = false;           // it was in last frame's problem
  Vec2 pore_dir = Vec2::Zero();        // unit, tip direction on the paper
  double pore_offset = 0.0;            // mm, pore_dir . O_n must stay <= pore_offset
  Vec2 pore_anchor = Vec2::Zero();     // mm, a point of the plane

  // --- pose and root frame ---
  Pose pose;                           // the pose of the last frame set up
  Vec3 root = Vec3::Zero();            // mm, the root O_0 (held on the paper when clamped)
  Mat3 R0 = Mat3::Identity();          // root frame (e1, e2, e3), e3 the unbent tuft's direction
  bool root_clamped = false;           // the pose put the ferrule into the paper
  bool same_pose = false;              // this frame's pose equals the last one (sleep rule)

  // --- wetness (seed "wet adhesion") and the ink it comes from (seed "Ink loading") ---
  VecX wetness;  // (n+1,) in [0, 1]: load / capacity once the ink depletes
  Ink ink;       // no nodes until the brush is first dipped

  StepStats stats;  // of the last step

  // --- child tufts T_j (seed "Simulation with multiple tufts"): each one's own state (spine,
  // BFGS H, rest angles, contact), in Brush::state() copies; empty for a single tuft ---
  int tufts_active = 0;              // children 0..tufts_active-1 are sprouted
  int split_node = 0;                // N_i the children hang from (0: even tufts at the root)
  std::vector<BrushState> children;  // (model.tufts) the children's states
};

}  // namespace brushwork
