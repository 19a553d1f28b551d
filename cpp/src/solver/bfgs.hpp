// The carried BFGS matrix (bfgs.cpp).
#pragma once

#include "brushwork/step.hpp"

namespace brushwork {
namespace detail {

// H for this frame's first iterate: the carried one of the current regime, or a fresh start
void start_hessian(const Tuft& t, BrushState& s, Workspace& w);
// damped BFGS update of H = L_xx^-1 with the accepted step alpha w.step and the multipliers w.lam
void bfgs_update(const Tuft& t, BrushState& st, Workspace& w, int m, double alpha);
bool hessian_ok(const Tuft& t, const BrushState& s);
// H from the Lagrangian's Hessian at the current iterate by differences of its gradient
void newton_hessian(const Tuft& t, BrushState& s, Workspace& w, int m);

}  // namespace detail
}  // namespace brushwork
