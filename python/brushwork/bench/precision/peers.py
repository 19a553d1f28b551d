"""Work-precision benchmark: other solvers (SciPy's SLSQP, NLopt's SLSQP, IPOPT) on the same frame problem."""
from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Callable, Optional, Sequence

import numpy as np

from ...brush import Brush


class FrameProblem:
    """The prepared frame problem of `brush` as plain functions of z (numpy in, numpy out)."""

    def __init__(self, brush: Brush):
        self.brush = brush
        self.m = brush.num_constraints

    def f(self, z):
        return self.brush.energy(np.asarray(z, float))

    def grad(self, z):
        return np.asarray(self.brush.energy_gradient(np.asarray(z, float)))

    def g(self, z):
        return np.asarray(self.brush.constraints(np.asarray(z, float)))

    def jac(self, z):
        return np.asarray(self.brush.constraint_jacobian(np.asarray(z, float)))


def _scipy_slsqp(prob: FrameProblem, z0: np.ndarray, tol: float):
    from scipy.optimize import minimize

    cons = [{"type": "ineq", "fun": prob.g, "jac": prob.jac}] if prob.m else []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = minimize(prob.f, z0, jac=prob.grad, method="SLSQP", constraints=cons,
                     options={"ftol": tol, "maxiter": 1000})
    return np.asarray(r.x, float), bool(r.success)


def _nlopt_slsqp(prob: FrameProblem, z0: np.ndarray, tol: float):
    import nlopt

    last = [np.array(z0, float)]

    def objective(x, grad):
        last[0] = np.array(x, float)
        if grad.size:
            grad[:] = prob.grad(x)
        return prob.f(x)

    def constraints(result, x, grad):
        # NLopt wants c(x) <= 0: c = -g
        result[:] = -prob.g(x)
        if grad.size:
            grad[:, :] = -prob.jac(x)

    opt = nlopt.opt(nlopt.LD_SLSQP, len(z0))
    opt.set_min_objective(objective)
    if prob.m:
        opt.add_inequality_mconstraint(constraints, [1e-9 * prob.brush.model.tuft_length] * prob.m)
    opt.set_ftol_rel(tol)
    opt.set_maxeval(2000)
    try:
        x = opt.optimize(np.array(z0, float))
        return np.asarray(x, float), opt.last_optimize_result() > 0
    except (nlopt.RoundoffLimited, nlopt.ForcedStop, RuntimeError, ValueError):
        return last[0], False


def _ipopt(prob: FrameProblem, z0: np.ndarray, tol: float):
    from cyipopt import minimize_ipopt

    cons = [{"type": "ineq", "fun": prob.g, "jac": prob.jac}] if prob.m else []
    r = minimize_ipopt(prob.f, np.array(z0, float), jac=prob.grad, constraints=cons,
                       options={"tol": tol, "print_level": 0, "sb": "yes", "max_iter": 1000,
                                "hessian_approximation": "limited-memory"})
    # status 1: "converged to acceptable tolerances" (IPOPT's acceptable_tol) counts as a solve
    return np.asarray(r.x, float), int(r.status) in (0, 1)


@dataclass
class Peer:
    """A peer solver: `module` to import, `solve(problem, z0, tol) -> (z, ok)`, its tolerance
    settings, the one that is its own default (None: it has none), and `stride`: it runs on one
    posable frame in `stride` (IPOPT takes ~0.2 s a frame here)."""
    name: str
    module: str
    option: str
    solve: Callable
    tols: Sequence[float]
    own_default: Optional[float]
    stride: int = 1


PEERS = [
    Peer("SciPy SLSQP", "scipy.optimize", "ftol", _scipy_slsqp, (1e-4, 1e-6, 1e-8, 1e-10), 1e-6),
    Peer("NLopt SLSQP", "nlopt", "ftol_rel", _nlopt_slsqp, (1e-4, 1e-6, 1e-8, 1e-10), None),
    Peer("IPOPT (cyipopt)", "cyipopt", "tol", _ipopt, (1e-6, 1e-8), 1e-8, stride=4),
]


def available_peers(quick: bool) -> tuple[list[tuple[Peer, float]], list[str]]:
    """(peer, tol) pairs to run and a note per missing peer.  quick: each peer at its own default
    (1e-6 where it has none)."""
    import importlib

    runs, notes = [], []
    for p in PEERS:
        try:
            importlib.import_module(p.module)
        except ImportError as exc:
            extra = "ipopt" if p.module == "cyipopt" else "bench"
            notes.append(f"{p.name}: not installed ({exc}); `pip install .[{extra}]`")
            continue
        tols = [p.own_default or 1e-6] if quick else list(p.tols)
        runs += [(p, t) for t in tols]
    return runs, notes
