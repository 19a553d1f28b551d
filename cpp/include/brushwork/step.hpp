// One frame of one tuft (MuJoCo's mj_step): step(tuft, state, pose, workspace) moves a
// BrushState to the pose.  Tuft is read-only, BrushState carries everything from frame to frame,
// Workspace is scratch sized once (nothing in it outlives a call, except the kinematics of the
// state's x, which the geometry queries read).
//
// The frame problem (seed "Energy minimization problems"):
//   prepare_frame  root frame, plasticity, frozen contact set and pore plane at the first iterate
//   evaluate       incremental potential, its gradient, the constraints and their Jacobian at x
//   solve          local SQP with the carried BFGS matrix
//   end_frame      last frame's positions and radii for the next frame
#pragma once

#include <vector>

#include "brushwork/geometry.hpp"
#include "brushwork/model.hpp"
#include "brushwork/state.hpp"

namespace brushwork {

struct Workspace {
  // --- kinematics at x_eval (seed Figure 2) ---
  VecX x_eval;                                   // (5n,) x at the last kinematics()
  std::vector<Vec3> O, u, w, nrm;                // (n+1) node O_i mm, lateral line u_i, minor axis w_i, section normal n_i
  std::vector<Vec3> aphi, ath;                   // (n) rotation axes of phi_j and theta_j
  std::vector<Mat3> F, Q;                        // (n) frame of segment j, and that frame before its bend
  VecX d_plus, d_minus, c;                       // (n+1,) mm, lateral distances a_i, b_i and minor radius c_i
  // --- node-level gradients: d/dO_i, d/du_i, torque of vectors fixed in node i's lateral frame ---
  std::vector<Vec3> gO, gu, tau;
  VecX gdp, gdm;                                 // (n+1,) d/da_i, d/db_i
  // --- SQP (na active variables, up to mmax constraints) ---
  VecX step;                                     // (na,) SQP step p
  VecX xf_trial, gf, gf_new;                     // (5n,) trial x, grad f, grad f at the new point
  VecX za, zt, gact, gact_new;                   // (na,) active x, trial, active gradients
  VecX s, yv, r, Hr, Bs, tmp;                    // (na,) BFGS pair and products
  VecX g, g_new, gtrial;                         // (mmax,) constraint values, mm
  MatX J, Jact, Jact_new, HJt, M, Mff;           // (mmax, 5n), (mmax, na) x2, (na, mmax), (mmax, mmax) x2
  VecX q, lam, lam_f, rhs;                       // (mmax,) dual QP
  std::vector<int> qp_state;                     // (mmax) 0 free, 1 at lower bound, 2 at upper bound
  BrushState saved;                              // step()'s copy of the state when it splits a frame

  explicit Workspace(const Tuft& t);
};

// straight, unstrained, at rest above the paper; reset_state() then forgets plasticity and H
BrushState initial_state(const Tuft& t);
void reset_state(const Tuft& t, BrushState& s, Workspace& w);
// throws std::invalid_argument unless s was made for a tuft of t's shape
void check_state_shape(const Tuft& t, const BrushState& s);

// one frame: set-up, SQP, continuation sub-steps when the pose is far from the last one
StepStats step(const Tuft& t, BrushState& s, const Pose& pose, Workspace& w);

// the frame problem
void prepare_frame(const Tuft& t, BrushState& s, const Pose& pose, Workspace& w);
void end_frame(const Tuft& t, BrushState& s, Workspace& w);
void solve(const Tuft& t, BrushState& s, Workspace& w);
void kinematics(const Tuft& t, const BrushState& s, const VecX& x, Workspace& w);
// energy at the full vector x (5n,), N*mm; grad: (5n,) dE/dx; g: (m,) mm; J: (m, 5n)
double evaluate(const Tuft& t, const BrushState& s, Workspace& w, const VecX& x, VecX* grad, VecX* g,
                MatX* J);

// geometry at the workspace's kinematics
VecX section_heights(const Tuft& t, const Workspace& w);  // (n,) mm, lowest point of Phi_1..Phi_n
std::vector<Section> sections(const Tuft& t, const Workspace& w);  // Omega_0..Omega_n

}  // namespace brushwork
