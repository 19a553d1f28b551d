// Pieces of the frame problem shared between the tuft's and the solver's source files.
#pragma once

#include "brushwork/step.hpp"

namespace brushwork {
namespace detail {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;  // rad per degree
// floor under square roots and divisors that are positive in exact arithmetic (mm^2, or -)
constexpr double kTiny = 1e-300;
// "infinitely large" for residuals and bounds that are not finite (-, or mm)
constexpr double kHuge = 1e300;

// the distance from O_i down to the lowest point of the section Omega_i (unshrunk), mm: the
// half-ellipse reaching down (A = a_i + r_lat on the +u side when u points down, else b_i + r_lat)
// seen along z: sqrt(A^2 u_z^2 + c^2 (1 - u_z^2))
double section_reach(const Tuft& t, const Workspace& w, int i);
// world positions of node i's lateral points P_i^+ = O_i + a_i u_i and P_i^- = O_i - b_i u_i, mm
inline Vec3 lateral_plus(const Workspace& w, int i) { return w.O[i] + w.d_plus[i] * w.u[i]; }
inline Vec3 lateral_minus(const Workspace& w, int i) { return w.O[i] - w.d_minus[i] * w.u[i]; }
// node i's touching point k (the contact set's points, 3 a node): 0 O_i, 1 P_i^+, 2 P_i^-, mm
inline Vec3 touch_point(const Workspace& w, int i, int k) {
  return k == 0 ? w.O[i] : k == 1 ? lateral_plus(w, i) : lateral_minus(w, i);
}

// node-level gradients to d/dx (suffix sums, O(n)); one Jacobian row of a constraint on node i
void clear_node_grads(const Tuft& t, Workspace& w);
void chain(const Tuft& t, const Workspace& w, VecX& gx);
void constraint_row(const Tuft& t, const Workspace& w, int i, const Vec3& gO, const Vec3& gu, double gdp,
                    double gdm, MatX& J, int row);

// active variables <-> full vector x
void gather(const Tuft& t, const VecX& full, VecX& act);
void scatter(const Tuft& t, const VecX& act, VecX& full);

// solver parts (solver/*.cpp)
void fresh_hessian(const Tuft& t, BrushState& s, Workspace& w);
double kkt(const Tuft& t, const VecX& gact, const VecX& g, const MatX& Jact, const VecX& lam, int m);
int solve_box_qp(Workspace& w, int m, double nu);
bool soc_solve(Workspace& w, const int* idx, int k);
bool cholesky_solve(MatX& A, const VecX& b, VecX& x, int k);

}  // namespace detail
}  // namespace brushwork
