"""Work-precision benchmark: per-frame error against per-frame run time, ours and the peers'.

    brushwork bench precision [--json FILE] [--out DIR] [--quick]

What is measured (error against run time, one frame problem at a time):

* **References.** Every recorded motion (press-drag-turn-lift and a fast flick, on the stiffest
  and the softest preset, exponent m = 2 and 3) is replayed with the core's own solver at
  tolerance 1e-10 (REF_TOLERANCE) and q_max REF_Q_MAX.  The core's SQP usually stops before
  1e-10 on its own (its l1-merit line search hits the floating-point floor of the energy near
  1e-7), so each frame's solution is then *polished* in Python by Newton's method on the KKT
  system of the same frame problem (finite-difference Hessian of the Lagrangian from the core's
  analytic gradients, active set from the core's multipliers) until the scaled KKT residual is
  <= 1e-10.  The reference *history* (the state that poses the next frame) stays the core's
  own tight solution, so the next frame's normal forces R_i come from the core's multipliers.
  A reference frame that fails (KKT above REF_KKT_OK after the polish; the core's tight solve
  can end in a state it cannot leave, see the README) is left out of every statistic of every
  solver (``valid_frames`` counts the frames kept).
* **The frame problem.** ``Brush.prepare(pose)`` freezes frame k's problem P_k (contact set, R_i,
  friction anchors, plasticity shift rho, pore plane) from the state after frame k-1; then
  ``energy(z)``, ``energy_gradient(z)``, ``constraints(z)`` (g(z) >= 0 feasible, mm) and
  ``constraint_jacobian(z)`` evaluate it.  A *probe* brush is kept in lockstep with the
  reference brush and prepared at each frame before the reference steps, so that the polish,
  the peers and the energy gaps all see exactly the P_k that the reference's ``step()`` solved.
  ``step()`` does two things ``prepare()`` does not: continuation (a frame whose first iterate
  sinks more than 2% L is split into sub-steps; then P_k is not the problem the core solved,
  and the frame is left out of the energy gaps and the peers' runs: ``posable`` false) and the
  sleep rule (no iterations for the same pose; a step after a prepare always sees "the same
  pose").  The probe is put back in lockstep after each frame by copying the stepping brush's
  whole state (``Brush.copy_state_from``).
* **Peers** (SciPy's SLSQP, NLopt's SLSQP, IPOPT through cyipopt; each optional) solve the
  reference's P_k, warm-started from the reference's previous-frame solution (what
  ``variables()`` returns after ``prepare``), fed the core's energy, gradient, constraints and
  Jacobian.  They cannot be run on a trajectory of their own on the same physics: after
  ``set_variables(z)`` the core keeps the contact multipliers of the last solve it did itself,
  so the next frame's normal forces R_i would not follow the peer.  Their errors are therefore
  one-frame errors from a perfect start, which favours them; ours are errors along our own
  trajectory.
* **Errors per frame** against the reference frame: the scaled KKT residual (the core's measure)
  on the problem each solver was given (ours: its own frame problem, as ``step()`` reports it;
  peers: P_k, multipliers by least squares); relative energy gap
  |E - E*| / max(|E*|, ENERGY_FLOOR * kappa_root), E the energy of the frame's own problem at
  the solver's state (ours: ``stats.energy``; peers: P_k at their solution) and E* the
  reference's (P_k at the polished solution), so that it measures both the solver's error and
  how far our trajectory has drifted from the reference's; skeleton error max_i |O_i - O_i*| (mm, and as a
  fraction of the tuft length L); footprint error 1 - IoU of the footprint polygons (shapely when
  installed, else a raster of both polygon sets); and at the end of the pipeline (full runs, not
  ``--quick``) the ink-mask IoU of 永 written by the kai driver at 512 px with each setting's
  brush against the same written with a tight solve (``INK_MASK_IOU``, ``bench.glyphs.InkMaskIoU``).
* **Time per frame**: wall time in Python around ``step()`` for ours (best of ``repeats`` runs
  per frame), around the solve call for peers (``prepare`` is not counted for them).

Float against double: the core is double only (cpp/include/brushwork/brush.hpp), so the float
row says "not built"; the peers are double only too.
"""
from __future__ import annotations

import argparse
import math
import os
import platform
import sys
import time
import warnings
from dataclasses import dataclass, field
from typing import Callable, Optional, Sequence

import numpy as np

from .. import BrushModel
from ..brush import Brush
from ..recorded import flick, press_drag_turn_lift

# the peers' linear algebra on one thread, like the core (set before SciPy loads its BLAS; a
# value the user set is kept)
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

# the reference: the core at this tolerance and iteration budget, then the Newton polish
REF_TOLERANCE = 1e-10
REF_Q_MAX = 1000
# the settings swept (the shipped q_max and tolerance are added if missing)
Q_MAX_SWEEP = (1, 2, 3, 5, 10, 20, 50)
TOL_SWEEP = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8)
RATE_SWEEP = (0.5, 2.0, 4.0)
# a reference frame counts when its polished KKT is at most this (or, on a frame split into
# sub-steps, which cannot be polished, when the core's own KKT is at most REF_CORE_KKT_OK)
REF_KKT_OK = 1e-9
REF_CORE_KKT_OK = 1e-5
# denominator floor of the relative energy gap, in units of kappa_root (N*mm): frames in the
# air have E* ~ 0, where a relative gap means nothing
ENERGY_FLOOR = 1e-3
# a row is "faster" than the default only when its median time is this much smaller (timing noise
# on a shared 2-core machine)
FASTER_MARGIN = 0.05

# the end of the pipeline: ink-mask IoU of one rendered character against its reference render.
# A function (brush_model_overrides: dict) -> float; None turns the column off (--quick does).
def _ink_mask_iou_default() -> Callable[[dict], float]:
    from .glyphs import InkMaskIoU

    return InkMaskIoU()


INK_MASK_IOU: Optional[Callable[[], Callable[[dict], float]]] = _ink_mask_iou_default
INK_NOTE = ("永 (bundled glyph) written by the kai driver at 512 px with each setting's brush, against the "
            "same written with q_max 100000 and tolerance 1e-10; full runs only (not --quick)")
FLOAT_NOTE = "not built: the core is double only (cpp/include/brushwork/brush.hpp)"
TUFTS_NOTE = ("tufts: the main tuft and its children, split from the first touch (sprout_spread 0); "
              "mean q is the main tuft's, frames/s the whole brush's")

OURS = "brushwork SQP"


# ---------------------------------------------------------------------------------------------
# motions and settings


@dataclass(frozen=True)
class Motion:
    """One recorded motion on one brush: `kind` "pdtl" (press_drag_turn_lift) or "flick",
    `frames` poses at rate 1."""
    kind: str
    preset: str
    exponent: float
    frames: int

    @property
    def name(self) -> str:
        what = {"pdtl": "press-drag-turn-lift", "flick": "flick"}[self.kind]
        return f"{what} {self.preset} m={self.exponent:g}"

    def model(self) -> BrushModel:
        m = BrushModel.preset(self.preset)
        m.exponent = self.exponent
        return m

    def poses(self, rate: float = 1.0) -> list:
        """The motion's poses, resampled to `rate` times as many per stroke."""
        n = max(1, int(round(self.frames * rate)))
        if self.kind == "pdtl":
            return press_drag_turn_lift(self.model(), frames=max(n, 50))
        return flick(self.model(), frames=max(n, 20))


@dataclass(frozen=True)
class Setting:
    """A setting of ours: `family` is q_max, tolerance, hessian, rate or float; `overrides` the
    BrushModel fields it changes from the shipped default; `rate` the poses-per-stroke factor."""
    label: str
    family: str
    overrides: tuple = ()
    rate: float = 1.0
    default: bool = False


def stiffest_and_softest() -> tuple[str, str]:
    """The presets with the stiffest and the softest tip (tip kappa = bend_stiffness /
    stiffness_ratio, N*mm/rad^m)."""
    tip = {p: BrushModel.preset(p).bend_stiffness / BrushModel.preset(p).stiffness_ratio
           for p in BrushModel.presets()}
    return max(tip, key=tip.get), min(tip, key=tip.get)


def motions(quick: bool) -> list[Motion]:
    """The recorded motions: quick = one short stroke on the shipped `medium` brush."""
    if quick:
        return [Motion("pdtl", "medium", 2.0, 50)]
    stiff, soft = stiffest_and_softest()
    return [Motion(kind, preset, m, frames)
            for preset in (stiff, soft) for m in (2.0, 3.0)
            for kind, frames in (("pdtl", 120), ("flick", 40))]


def settings(quick: bool) -> list[Setting]:
    """Our settings: the q_max sweep at the shipped tolerance (its shipped q_max row is the
    default), the tolerance sweep at the shipped q_max, a fresh Hessian, the frame rates, float."""
    shipped = BrushModel.preset("medium")
    qs = sorted(set(Q_MAX_SWEEP) | {shipped.q_max})
    tols = sorted(set(TOL_SWEEP) - {shipped.tolerance}, reverse=True)
    rates = RATE_SWEEP
    if quick:
        qs = [q for q in qs if q in (1, 3, 10, shipped.q_max, 50)]
        tols = [t for t in tols if t in (1e-3, 1e-8)]
        rates = (2.0,)
    out = [Setting(f"q_max={q}", "q_max", (("q_max", q),), default=q == shipped.q_max) for q in qs]
    out += [Setting(f"tol={t:.0e}", "tolerance", (("tolerance", t),)) for t in tols]
    out.append(Setting("fresh Hessian", "hessian", (("warm_hessian", False),)))
    out += [Setting(f"{r:g}x poses", "rate", rate=r) for r in rates]
    out.append(Setting("float", "float"))
    return out


def default_label() -> str:
    """The shipped setting, spelled out."""
    m = BrushModel.preset("medium")
    return (f"q_max={m.q_max}, tol={m.tolerance:.0e}, "
            f"{'carried' if m.warm_hessian else 'fresh'} Hessian, double, 1x poses")


# ---------------------------------------------------------------------------------------------
# errors


def skeleton_error(a: np.ndarray, b: np.ndarray) -> float:
    """Largest distance between corresponding spine nodes of two (n+1, 3) skeletons, mm."""
    return float(np.max(np.linalg.norm(np.asarray(a) - np.asarray(b), axis=1)))


def _signed_area(p: np.ndarray) -> float:
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def _shapely_region(loops):
    # outer loops counter-clockwise, holes clockwise (Brush.footprint's convention)
    from shapely.geometry import Polygon
    from shapely.ops import unary_union

    outers = [Polygon(p).buffer(0) for p in loops if len(p) >= 3 and _signed_area(p) > 0]
    holes = [Polygon(p).buffer(0) for p in loops if len(p) >= 3 and _signed_area(p) < 0]
    region = unary_union(outers) if outers else Polygon()
    return region.difference(unary_union(holes)) if holes else region


RASTER_PX = 400       # the raster backend's grid: RASTER_PX x RASTER_PX cells over both footprints' bounds
_SUBPIXEL_BITS = 8    # cv2.fillPoly's fixed-point fraction bits for the vertices


def _raster_region(loops, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """(RASTER_PX, RASTER_PX) bool: the even-odd fill of every loop (mm) on a grid spanning lo..hi
    (mm): each loop toggles its cells, so holes return to empty."""
    import cv2

    scale = (RASTER_PX - 1) / np.maximum(hi - lo, 1e-12) * (1 << _SUBPIXEL_BITS)
    inside = np.zeros((RASTER_PX, RASTER_PX), dtype=np.uint8)
    for p in loops:
        if len(p) >= 3:
            mask = np.zeros_like(inside)
            px = np.round((np.asarray(p) - lo) * scale).astype(np.int32)
            cv2.fillPoly(mask, [px], 1, lineType=cv2.LINE_8, shift=_SUBPIXEL_BITS)
            inside ^= mask
    return inside.astype(bool)


def footprint_backend() -> str:
    """"shapely" when it is installed, else "raster" (cv2.fillPoly on a RASTER_PX x RASTER_PX grid)."""
    try:
        import shapely  # noqa: F401
        return "shapely"
    except ImportError:
        return "raster"


def footprint_error(a, b, backend: Optional[str] = None) -> float:
    """1 - IoU of two footprints (lists of (k, 2) polygons in mm); 0 when both are empty."""
    a = [np.asarray(p, float) for p in a]
    b = [np.asarray(p, float) for p in b]
    if not any(len(p) >= 3 for p in a) and not any(len(p) >= 3 for p in b):
        return 0.0
    if (backend or footprint_backend()) == "shapely":
        ra, rb = _shapely_region(a), _shapely_region(b)
        union = ra.union(rb).area
        return 0.0 if union <= 0.0 else 1.0 - ra.intersection(rb).area / union
    pts = np.vstack([p for p in a + b if len(p)])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    ia, ib = _raster_region(a, lo, hi), _raster_region(b, lo, hi)
    union = np.count_nonzero(ia | ib)
    return 0.0 if union == 0 else 1.0 - np.count_nonzero(ia & ib) / union


def kkt_residual(brush: Brush, z: np.ndarray, lam: np.ndarray) -> float:
    """The core's scaled KKT residual (sqp.cpp Brush::kkt) of the prepared frame problem at
    (z, lam): max(|grad f - J^T lam|_inf / kappa_root, max(-g) / L, max|lam_i g_i| / kappa_root)."""
    m = brush.model
    grad = brush.energy_gradient(z)
    g = brush.constraints(z)
    stat = grad - brush.constraint_jacobian(z).T @ lam if len(g) else grad
    feas = max(0.0, float(np.max(-g))) if len(g) else 0.0
    comp = float(np.max(np.abs(lam * g))) if len(g) else 0.0
    r = max(float(np.max(np.abs(stat))) / m.bend_stiffness, feas / m.tuft_length,
            comp / m.bend_stiffness)
    return r if math.isfinite(r) else math.inf


def peer_kkt(brush: Brush, z: np.ndarray) -> float:
    """kkt_residual at a point z that came without multipliers: lam from least squares on the
    constraints within 1e-6 L of the paper, clipped at 0 (the best stationarity they allow)."""
    g = brush.constraints(z)
    lam = np.zeros(len(g))
    act = np.flatnonzero(g < 1e-6 * brush.model.tuft_length)
    if len(act):
        J = brush.constraint_jacobian(z)[act]
        lam[act] = np.maximum(np.linalg.lstsq(J.T, brush.energy_gradient(z), rcond=None)[0], 0.0)
    return kkt_residual(brush, z, lam)


def polish(brush: Brush, z: np.ndarray, lam: np.ndarray, target: float = 1e-12,
           max_iter: int = 20) -> tuple[np.ndarray, np.ndarray, float]:
    """Newton's method on the KKT system of the prepared frame problem from (z, lam): active
    set A = {lam_i > 0 or g_i ~ 0}, Hessian of the Lagrangian f - lam_A^T g_A by central
    differences of the analytic gradients (step 1e-6), steps from the (least-squares) solution of
        [ H    -J_A^T ] [dz  ]     [ grad f - J_A^T lam_A ]
        [ J_A   0     ] [dlam] = - [ g_A                  ],
    multipliers kept >= 0.  Returns the best (z, lam, kkt_residual) seen, the start included."""
    model = brush.model
    z, lam = np.array(z, float), np.array(lam, float)
    best = (z.copy(), lam.copy(), kkt_residual(brush, z, lam))
    n, h = len(z), 1e-6
    for _ in range(max_iter):
        if best[2] <= target:
            break
        g = brush.constraints(z)
        act = np.flatnonzero((lam > 0.0) | (g < 1e-9 * model.tuft_length)) if len(g) else np.zeros(0, int)

        def grad_l(x):
            gl = brush.energy_gradient(x)
            return gl - brush.constraint_jacobian(x)[act].T @ lam[act] if len(act) else gl

        H = np.empty((n, n))
        for j in range(n):
            e = np.zeros(n)
            e[j] = h
            H[:, j] = (grad_l(z + e) - grad_l(z - e)) / (2.0 * h)
        H = 0.5 * (H + H.T)
        Ja = brush.constraint_jacobian(z)[act] if len(act) else np.zeros((0, n))
        k = len(act)
        K = np.block([[H, -Ja.T], [Ja, np.zeros((k, k))]])
        rhs = -np.concatenate([grad_l(z), g[act] if k else np.zeros(0)])
        d = np.linalg.lstsq(K, rhs, rcond=1e-14)[0]
        if not np.all(np.isfinite(d)):
            break
        z = z + d[:n]
        lam = lam.copy()
        lam[act] = np.maximum(lam[act] + d[n:], 0.0)
        r = kkt_residual(brush, z, lam)
        if r < best[2]:
            best = (z.copy(), lam.copy(), r)
    return best


# ---------------------------------------------------------------------------------------------
# peers: other solvers on the same frame problem


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


# ---------------------------------------------------------------------------------------------
# running


def _model_for(motion: Motion, overrides: Sequence = ()) -> BrushModel:
    m = motion.model()
    for k, v in overrides:
        setattr(m, k, v)
    return m


@dataclass
class Trajectory:
    """Per-frame record of one run over F frames: times (F,) s, skeletons (F, n+1, 3) mm,
    footprints (F lists of (k, 2) polygons, mm), iterations (F,), converged (F,), and the frame's
    own problem at the end of the frame: energies (F,) N*mm and kkt (F,) scaled KKT residuals."""
    times: np.ndarray
    skeletons: np.ndarray
    footprints: list
    iterations: np.ndarray
    converged: np.ndarray
    energies: np.ndarray
    kkt: np.ndarray
    gaps: Optional[np.ndarray] = None  # (F,) own_problem_gaps, filled by run()


def run_ours(model: BrushModel, poses: list, repeats: int) -> Trajectory:
    """Replay `poses` on a fresh brush `repeats` times; per-frame time is the least over runs
    (the runs are deterministic, so the other records come from the first)."""
    times = None
    for r in range(repeats):
        b = Brush(model)
        t = np.empty(len(poses))
        rec = ([], [], [], [], [], []) if r == 0 else None
        for k, p in enumerate(poses):
            t0 = time.perf_counter()
            s = b.step(p)
            t[k] = time.perf_counter() - t0
            if rec is not None:
                rec[0].append(np.array(b.skeleton()))
                rec[1].append([np.array(q) for q in b.footprint()])
                rec[2].append(s.iterations)
                rec[3].append(s.converged)
                rec[4].append(s.energy)
                rec[5].append(s.kkt_residual)
        times = t if times is None else np.minimum(times, t)
        if rec is not None:
            first = rec
    return Trajectory(times, np.array(first[0]), first[1], np.array(first[2]),
                      np.array(first[3], bool), np.array(first[4]), np.array(first[5]))


@dataclass
class Reference:
    """The reference of one motion at one rate over F frames: skeletons (F, n+1, 3) mm,
    footprints, energies (F,) N*mm of P_k at z*, kkt (F,) after the polish, core_kkt (F,) before it,
    posable (F,) bool (P_k is the problem the core solved: no continuation sub-steps), resyncs.

    ``valid`` (F,): the frames whose reference holds (a polished KKT at most REF_KKT_OK, or on a
    frame that cannot be polished a core KKT at most REF_CORE_KKT_OK); every statistic of every
    solver uses only these frames."""
    skeletons: np.ndarray
    footprints: list
    energies: np.ndarray
    kkt: np.ndarray
    core_kkt: np.ndarray
    posable: np.ndarray
    core_energies: np.ndarray
    resyncs: int = 0

    @property
    def valid(self) -> np.ndarray:
        return np.where(self.posable, self.kkt <= REF_KKT_OK, self.core_kkt <= REF_CORE_KKT_OK)
    # per peer run: (peer name, tol) -> dict of per-frame arrays (posable frames only)
    peers: dict = field(default_factory=dict)


class LockstepProbe:
    """A second brush of the same model kept at the state of a stepping brush, so that frame k's
    problem P_k can be prepared on it before the stepping brush solves frame k.

    Use: ``probe.prepare(k)``; step the other brush; read P_k from ``probe.brush``;
    ``probe.advance(k, other)``, which copies the other brush's whole state (a prepared brush's
    own ``step()`` would see "the same pose", the sleep rule, and leave lockstep).
    ``resyncs`` stays 0 (kept for the report's format)."""

    def __init__(self, model: BrushModel, poses: list):
        self.model, self.poses = model, poses
        self.brush = Brush(model)
        self.resyncs = 0

    def prepare(self, k: int) -> None:
        self.brush.prepare(self.poses[k])

    def advance(self, k: int, other: Brush) -> None:
        # back in lockstep by copying the stepping brush's whole state (stepping the probe
        # itself could leave lockstep, and replaying poses[:k + 1] then made the reference
        # quadratic in the number of frames)
        self.brush.copy_state_from(other)


def own_problem_gaps(model: BrushModel, poses: list) -> np.ndarray:
    """(F,) relative energy gap of each frame's solution on its own frame problem:
    (E(z) - E(z*)) / max(|E(z*)|, ENERGY_FLOOR * kappa_root), z* the polished minimiser of the same
    problem started from z.  NaN where it cannot be measured: a frame split into sub-steps, or a
    polish that does not reach KKT <= 1e-9 at an energy no higher than E(z)."""
    b = Brush(model)
    probe = LockstepProbe(model, poses)
    floor = ENERGY_FLOOR * model.bend_stiffness
    gaps = np.full(len(poses), np.nan)
    for k, pose in enumerate(poses):
        probe.prepare(k)
        s = b.step(pose)
        pb = probe.brush
        if s.substeps == 1 and pb.num_constraints == b.num_constraints:
            z = np.array(b.variables())
            z_star, _, r = polish(pb, z, np.array(b.multipliers()))
            e, e_star = pb.energy(z), pb.energy(z_star)
            if r <= 1e-9 and e_star <= e + 1e-12 * max(abs(e), floor):
                gaps[k] = (e - e_star) / max(abs(e_star), floor)
        probe.advance(k, b)
    return gaps


def run_reference(motion: Motion, poses: list, peer_runs: list,
                  progress: Callable[[str], None]) -> Reference:
    """Replay `poses` with the reference model and a lockstep probe; per posable frame: the
    polish, and the peers' solves of the same P_k (`peer_runs`: (Peer, tol) pairs)."""
    model = _model_for(motion, (("tolerance", REF_TOLERANCE), ("q_max", REF_Q_MAX)))
    ref, geo = Brush(model), Brush(model)
    probe = LockstepProbe(model, poses)
    F = len(poses)
    skels, fps = [], []
    energies, kkts, core_kkts = np.full(F, np.nan), np.full(F, np.nan), np.full(F, np.nan)
    posable = np.zeros(F, bool)
    core_energies = np.full(F, np.nan)
    peers = {(p.name, tol): {"frame": [], "times": [], "skel_err": [], "fp_err": [], "gap": [], "kkt": [],
                             "ok": []}
             for p, tol in peer_runs}
    for k, pose in enumerate(poses):
        # P_k on the probe, then the reference's own step (its history is what poses P_k+1)
        probe.prepare(k)
        s = ref.step(pose)
        pb = probe.brush
        core_kkts[k] = s.kkt_residual
        core_energies[k] = s.energy
        posable[k] = s.substeps == 1 and pb.num_constraints == ref.num_constraints
        if posable[k]:
            z_star, _, kkts[k] = polish(pb, np.array(ref.variables()), np.array(ref.multipliers()))
            geo.prepare(pose)
            geo.set_variables(z_star)
            skels.append(np.array(geo.skeleton()))
            fps.append([np.array(q) for q in geo.footprint()])
            e_star = pb.energy(z_star)
            energies[k] = e_star
            scale = max(abs(e_star), ENERGY_FLOOR * model.bend_stiffness)
            # the peers on the same P_k, from the reference's previous-frame solution
            z0 = np.array(pb.variables())
            prob = FrameProblem(pb)
            n_posable = int(posable[:k].sum())
            for p, tol in peer_runs:
                if n_posable % p.stride:
                    continue
                t0 = time.perf_counter()
                try:
                    z, ok = p.solve(prob, z0, tol)
                except Exception:  # noqa: BLE001 - a peer's failure is a data point
                    z, ok = z0, False
                dt = time.perf_counter() - t0
                rec = peers[(p.name, tol)]
                rec["frame"].append(k)
                rec["times"].append(dt)
                rec["ok"].append(ok and bool(np.all(np.isfinite(z))))
                if not np.all(np.isfinite(z)):
                    z = z0
                geo.prepare(pose)
                geo.set_variables(z)
                rec["skel_err"].append(skeleton_error(geo.skeleton(), skels[-1]))
                rec["fp_err"].append(footprint_error(geo.footprint(), fps[-1]))
                rec["gap"].append(abs(prob.f(z) - e_star) / scale)
                rec["kkt"].append(peer_kkt(pb, z))
        else:
            skels.append(np.array(ref.skeleton()))
            fps.append([np.array(q) for q in ref.footprint()])
            kkts[k] = s.kkt_residual
        probe.advance(k, ref)
    progress(f"{motion.name}: reference over {F} frames, {int(posable.sum())} posable, "
             f"polished KKT max {np.nanmax(kkts[posable]) if posable.any() else float('nan'):.1e}, "
             f"{probe.resyncs} probe resyncs")
    peer_arrays = {key: {k: np.array(v) for k, v in rec.items()} for key, rec in peers.items()}
    return Reference(np.array(skels), fps, energies, kkts, core_kkts, posable, core_energies,
                     probe.resyncs, peer_arrays)


# ---------------------------------------------------------------------------------------------
# aggregation


def _median(xs) -> Optional[float]:
    xs = np.asarray([x for x in np.ravel(xs) if x is not None and np.isfinite(x)], float)
    return float(np.median(xs)) if len(xs) else None


def _p95(xs) -> Optional[float]:
    xs = np.asarray(xs, float)
    return float(np.percentile(xs, 95)) if len(xs) else None


def _mean(xs) -> Optional[float]:
    return float(np.mean(xs)) if len(xs) else None


def _one_minus_mean(xs) -> Optional[float]:
    return 1.0 - float(np.mean(xs)) if len(xs) else None


def _row(solver: str, setting: str, family: str, default: bool, times, gaps, skel_mm, skel_frac,
         fp_err, **extra) -> dict:
    """One table row (times in s per frame; the other arrays per frame)."""
    times = np.asarray(times, float)
    row = {
        "solver": solver,
        "setting": setting,
        "default": default,
        "family": family,
        "frames": int(len(times)),
        "ms_per_frame_median": 1e3 * _median(times) if len(times) else None,
        "ms_per_frame_p95": 1e3 * _p95(times) if len(times) else None,
        "energy_gap_median": _median(gaps),
        "skeleton_error_mm_median": _median(skel_mm),
        "skeleton_error_frac_median": _median(skel_frac),
        "footprint_error_median": _median(fp_err),
        "ink_mask_iou_median": None,
    }
    row.update(extra)
    return row


def _pool_our_motion(pool: dict, motion: Motion, tr: Trajectory, ref: Reference) -> None:
    """Append to `pool` (key -> list, one entry per frame) the valid frames of our trajectory
    `tr` on `motion` against its reference `ref`."""
    model = motion.model()
    L = model.tuft_length
    e_floor = ENERGY_FLOOR * model.bend_stiffness
    v = ref.valid
    pool["t"] += list(tr.times[v])
    pool["its"] += list(tr.iterations[v])
    pool["conv"] += list(tr.converged[v])
    pool["kk"] += list(tr.kkt[v])
    pool["gaps"] += list(np.abs(tr.gaps[v]))
    for k in np.flatnonzero(v):
        d = skeleton_error(tr.skeletons[k], ref.skeletons[k])
        pool["sk"].append(d)
        pool["skf"].append(d / L)
        pool["fe"].append(footprint_error(tr.footprints[k], ref.footprints[k]))
        # the energy of our frame's own problem against the reference's (posable: polished)
        e_ref = ref.energies[k] if ref.posable[k] else ref.core_energies[k]
        pool["drift"].append(abs(tr.energies[k] - e_ref) / max(abs(e_ref), e_floor))


def _our_row(st: Setting, results: list) -> dict:
    """The row of our setting `st`, its per-frame errors pooled over the motions run at its rate."""
    if st.family == "float":
        return _row(OURS, st.label, st.family, False, [], [], [], [], [], kkt_median=None,
                    note=FLOAT_NOTE)
    pool = {key: [] for key in ("t", "gaps", "sk", "skf", "fe", "its", "conv", "kk", "drift")}
    for motion, rate, ours, ref in results:
        if rate == st.rate and st.label in ours:
            _pool_our_motion(pool, motion, ours[st.label], ref)
    label = default_label() if st.default else st.label
    gaps = pool["gaps"]
    return _row(OURS, label, st.family, st.default, pool["t"], gaps, pool["sk"], pool["skf"], pool["fe"],
                kkt_median=_median(pool["kk"]), energy_drift_median=_median(pool["drift"]),
                gap_unmeasured_frac=_mean(~np.isfinite(np.asarray(gaps, float))),
                mean_iterations=_mean(pool["its"]),
                unconverged_frac=_one_minus_mean(pool["conv"]),
                note="")


def _peer_row(p: Peer, tol: float, results: list) -> dict:
    """The row of peer `p` at tolerance `tol`, its one-frame errors pooled over the 1x motions."""
    pool = {key: [] for key in ("t", "gaps", "sk", "skf", "fe", "ok", "kk")}
    for motion, rate, _ours, ref in results:
        if rate != 1.0:
            continue
        rec = ref.peers[(p.name, tol)]
        L = motion.model().tuft_length
        v = ref.valid[rec["frame"].astype(int)] if len(rec["frame"]) else np.zeros(0, bool)
        for key, column in (("t", "times"), ("gaps", "gap"), ("sk", "skel_err"), ("fe", "fp_err"),
                            ("ok", "ok"), ("kk", "kkt")):
            pool[key] += list(rec[column][v])
        pool["skf"] += list(rec["skel_err"][v] / L)
    own = p.own_default is not None and tol == p.own_default
    note = "one-frame errors from the reference's previous frame"
    if p.stride > 1:
        note += f"; 1 posable frame in {p.stride}"
    return _row(p.name, f"{p.option}={tol:.0e}" + (" (its default)" if own else ""), "peer", False,
                pool["t"], pool["gaps"], pool["sk"], pool["skf"], pool["fe"],
                kkt_median=_median(pool["kk"]), failed_frac=_one_minus_mean(pool["ok"]), note=note)


def build_rows(results: list, setting_list: list, peer_runs: list) -> list[dict]:
    """Pool the per-frame errors of every motion into one row per solver and setting.

    results: (motion, rate, ours: label -> Trajectory, Reference) tuples."""
    return ([_our_row(st, results) for st in setting_list]
            + [_peer_row(p, tol, results) for p, tol in peer_runs])


def _err_key(row: dict) -> tuple:
    return (row["skeleton_error_mm_median"], row["energy_gap_median"], row["footprint_error_median"])


def _dominates(r: dict, d: dict) -> bool:
    """Row `r` is faster than row `d` by more than FASTER_MARGIN, no worse on the skeleton error,
    the energy gap and the footprint error medians, and better on at least one."""
    if r["ms_per_frame_median"] is None:
        return False
    faster = r["ms_per_frame_median"] < (1.0 - FASTER_MARGIN) * d["ms_per_frame_median"]
    pairs = [(a, b) for a, b in zip(_err_key(r), _err_key(d)) if a is not None and b is not None]
    return faster and all(a <= b for a, b in pairs) and any(a < b for a, b in pairs)


def front_check(rows: list[dict]) -> dict:
    """Is the default on the front of our settings at 1x poses (q_max, tolerance, Hessian)?  It is
    when no other such row dominates it (`_dominates`)."""
    d = next(r for r in rows if r["default"])
    rivals = [r for r in rows if r["solver"] == OURS and not r["default"]
              and r["family"] in ("q_max", "tolerance", "hessian")]
    dominated_by = [r["setting"] for r in rivals if _dominates(r, d)]
    return {"on_front": not dominated_by, "dominated_by": dominated_by}


def _at_least_as_accurate(r: dict, d: dict) -> bool:
    """Row `r`'s KKT residual and energy gap medians are no worse than row `d`'s."""
    return (r["kkt_median"] is not None and r["kkt_median"] <= d["kkt_median"]
            and r["energy_gap_median"] <= d["energy_gap_median"])


def _peer_ratio(prs: list[dict], d: dict) -> dict:
    """The speed verdict of one peer's rows `prs` against our default row `d`."""
    own = next((r for r in prs if "(its default)" in r["setting"]), None)
    if own is None:  # no default of its own: the 1e-6 setting, as SciPy's
        own = next((r for r in prs if "1e-06" in r["setting"]), prs[0])
    matching = [r for r in prs if _at_least_as_accurate(r, d)]
    cheapest = min(matching, key=lambda r: r["ms_per_frame_median"]) if matching else None
    return {
        "peer": own["solver"],
        "peer_setting": own["setting"],
        "time_ratio": own["ms_per_frame_median"] / d["ms_per_frame_median"],
        "ours_as_accurate": (d["kkt_median"] <= own["kkt_median"]
                             and d["energy_gap_median"] <= own["energy_gap_median"]),
        "cheapest_as_accurate_setting": cheapest["setting"] if cheapest else None,
        "cheapest_as_accurate_time_ratio": (cheapest["ms_per_frame_median"] / d["ms_per_frame_median"]
                                            if cheapest else None),
    }


def speed_ratios(rows: list[dict]) -> list[dict]:
    """Per peer: its own-default time / ours (default row), whether our default is at least as
    accurate (KKT residual on the problem each was given, and energy gap, medians: the skeleton and
    footprint errors are not head-to-head, ours along a trajectory, theirs over one frame), and
    the time ratio of the cheapest peer setting at least as accurate as our default."""
    d = next(r for r in rows if r["default"])
    names = dict.fromkeys(r["solver"] for r in rows if r["family"] == "peer")
    return [_peer_ratio([r for r in rows if r["solver"] == name], d) for name in names]


# ---------------------------------------------------------------------------------------------
# the seed's Table 1


def _table1_cell(tufts: int, q_max: int, warm: bool, frames: int, repeats: int) -> tuple[float, float]:
    """(mean iterations of the main tuft, frames per second of the whole brush by core time, best
    of `repeats`) for a six-segment `medium` brush of `tufts` tufts on press-drag-turn-lift."""
    from .solver import _one_run

    m = BrushModel.preset("medium")
    m.q_max, m.warm_hessian = q_max, warm
    m.tufts, m.sprout_spread = tufts - 1, 0.0
    poses = press_drag_turn_lift(m, frames=frames)
    best, its = math.inf, math.nan
    for _ in range(repeats):
        stats, _wall = _one_run(m, poses)
        core = sum(s.time for s in stats)
        if core < best:
            best, its = core, float(np.mean([s.iterations for s in stats]))
    return its, (frames / best if best > 0 else math.inf)


def table1(quick: bool) -> list[dict]:
    """Seed Table 1 redone for brushes of 1, 3 and 5 six-segment tufts (`medium`): mean iterations
    q and frames per second (core time, best of the runs) at q_max 20, 25, 30, fresh against
    carried Hessian, on the recorded press-drag-turn-lift stroke (320 frames; quick: 60, one run)."""
    frames, repeats = (60, 1) if quick else (320, 3)
    rows = []
    for tufts in (1, 3, 5):
        for q in (20, 25, 30):
            row = {"tufts": tufts, "q_max": q}
            for mode, warm in (("fresh", False), ("carried", True)):
                row[f"{mode}_mean_q"], row[f"{mode}_fps"] = _table1_cell(tufts, q, warm, frames, repeats)
            rows.append(row)
    return rows


# ---------------------------------------------------------------------------------------------
# the whole run


def machine_note() -> str:
    """One line: the machine and the solver versions of this run."""
    import importlib

    vers = []
    for mod, name in (("scipy", "SciPy"), ("nlopt", "NLopt"), ("cyipopt", "cyipopt")):
        try:
            vers.append(f"{name} {importlib.import_module(mod).__version__}")
        except ImportError:
            pass
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return (f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, "
            f"NumPy {np.__version__}" + (", " + ", ".join(vers) if vers else ""))


def _posable_kkt(ref: Reference) -> tuple[Optional[float], Optional[float]]:
    """(max, fraction <= 1e-10) of the polished KKT residuals over the valid posable frames."""
    kept = ref.posable & ref.valid
    if not kept.any():
        return None, None
    return float(np.nanmax(ref.kkt[kept])), float(np.mean(ref.kkt[kept] <= 1e-10))


def _reference_summary(motion: Motion, rate: float, frames: int, ref: Reference) -> dict:
    """One line of the reference table: how many frames were posable and valid, and how tight."""
    kkt_max, kkt_tight = _posable_kkt(ref)
    return {
        "motion": motion.name, "rate": rate, "frames": frames,
        "posable_frames": int(ref.posable.sum()),
        # over the valid frames (every statistic uses only those)
        "polished_kkt_max": kkt_max,
        "polished_kkt_le_1e-10_frac": kkt_tight,
        "core_kkt_median": float(np.median(ref.core_kkt)),
        "core_kkt_max": float(np.max(ref.core_kkt)),
        "probe_resyncs": ref.resyncs,
        "valid_frames": int(ref.valid.sum()),
        "reference_failed_at": (int(np.argmin(ref.valid)) if not ref.valid.all() else None),
        "failed_frames": int((~ref.valid).sum()),
    }


def _run_at_rate(motion: Motion, rate: float, setting_list: list, peer_runs: list, repeats: int,
                 say: Callable[[str], None]) -> tuple[dict, Reference, int]:
    """Replay `motion` at `rate` with every setting of ours at that rate, then its reference (and
    the peers, at 1x).  Returns (label -> Trajectory, the Reference, the number of frames)."""
    poses = motion.poses(rate)
    ours = {}
    for st in setting_list:
        if st.family == "float" or st.rate != rate:
            continue
        model = _model_for(motion, st.overrides)
        ours[st.label] = run_ours(model, poses, repeats)
        ours[st.label].gaps = own_problem_gaps(model, poses)
    say(f"{motion.name} at {rate:g}x ({len(poses)} frames): {len(ours)} settings of ours run")
    ref = run_reference(motion, poses, peer_runs if rate == 1.0 else [], say)
    return ours, ref, len(poses)


def _add_ink_iou(rows: list[dict], setting_list: list) -> None:
    """Fill in the ink-mask IoU column of our 1x q_max, tolerance and Hessian rows."""
    ink_iou = INK_MASK_IOU()
    # (the default's row carries the spelled-out label, default_label(), not its own)
    by_label = {(default_label() if st.default else st.label): st for st in setting_list}
    for row in rows:
        st = by_label.get(row["setting"]) if row["solver"] == OURS else None
        if st is not None and st.family in ("q_max", "tolerance", "hessian") and st.rate == 1.0:
            row["ink_mask_iou_median"] = ink_iou(dict(st.overrides))


def run(quick: bool = False, repeats: Optional[int] = None, peers: bool = True,
        progress: bool = True) -> dict:
    """Run the whole benchmark; returns {"rows", "front", "speed_ratios", "table1", "reference",
    "notes", "machine", ...} (see module docstring)."""
    def say(msg: str) -> None:
        if progress:
            print(f"[precision] {msg}", file=sys.stderr, flush=True)

    t_start = time.perf_counter()
    repeats = repeats if repeats is not None else (1 if quick else 3)
    setting_list = settings(quick)
    peer_runs, notes = available_peers(quick) if peers else ([], ["peers: skipped (--no-peers)"])
    for n in notes:
        say(n)
    results, ref_summary = [], []
    rates = sorted({s.rate for s in setting_list if s.family != "float"})
    for motion in motions(quick):
        for rate in rates:
            ours, ref, frames = _run_at_rate(motion, rate, setting_list, peer_runs, repeats, say)
            results.append((motion, rate, ours, ref))
            ref_summary.append(_reference_summary(motion, rate, frames, ref))
    rows = build_rows(results, setting_list, peer_runs)
    if INK_MASK_IOU is not None and not quick:
        say("ink-mask IoU of a written character per setting (the reference render takes a minute)")
        _add_ink_iou(rows, setting_list)
    say("Table 1")
    t1 = table1(quick)
    return {
        "benchmark": "precision",
        "quick": quick,
        "machine": machine_note(),
        "default_setting": default_label(),
        "footprint_iou": footprint_backend(),
        "rows": rows,
        "front": front_check(rows),
        "speed_ratios": speed_ratios(rows),
        "table1": t1,
        "table1_note": TUFTS_NOTE,
        "reference": ref_summary,
        "ink_mask_iou": {"available": INK_MASK_IOU is not None and not quick, "note": INK_NOTE},
        "notes": notes,
        "wall_seconds": time.perf_counter() - t_start,
    }


# ---------------------------------------------------------------------------------------------
# output


def table(result: dict) -> str:
    """The Markdown report: the main table, the verdicts, Table 1 and the reference summary."""
    from .report import format_value, markdown_table

    rows = [dict(r, default="**yes**" if r["default"] else "") for r in result["rows"]]
    for r in rows:
        if r["solver"] == OURS and r["family"] != "float":
            r["extra"] = (f"{format_value(r['mean_iterations'])} it/frame, "
                          f"{100 * r['unconverged_frac']:.0f}% unconverged")
        elif r["family"] == "peer":
            r["extra"] = (f"{100 * r['failed_frac']:.0f}% reported failure" if r.get("failed_frac") is not None
                          else "") + (f"; {r['frames']} frames" if r["frames"] else "")
        else:
            r["extra"] = r.get("note", "")
    out = [f"Machine: {result['machine']}.", ""]
    out.append(markdown_table(
        rows, ["solver", "setting", "default", "ms_per_frame_median", "ms_per_frame_p95",
               "kkt_median", "energy_gap_median", "skeleton_error_mm_median",
               "skeleton_error_frac_median", "footprint_error_median", "ink_mask_iou_median", "extra"],
        ["solver", "setting", "default", "ms/frame p50", "ms/frame p95", "KKT p50", "energy gap p50",
         "skeleton err p50 (mm)", "skeleton err p50 (/L)", "footprint 1-IoU p50", "character ink IoU", "notes"]))
    out.append("")
    out.append(f"Character ink IoU: {INK_NOTE}.")
    out.append(f"Footprint IoU by: {result['footprint_iou']}.")
    for n in result["notes"]:
        out.append(f"Note: {n}.")
    f = result["front"]
    out.append("")
    out.append("Shipped default on the front of our settings: " + (
        "yes (no setting of ours is both faster and more accurate)" if f["on_front"]
        else "NO, dominated by " + ", ".join(f["dominated_by"])) + ".")
    for s in result["speed_ratios"]:
        line = (f"{s['peer']} at {s['peer_setting']}: {format_value(s['time_ratio'])}x our default's "
                f"time per frame; our default {'is' if s['ours_as_accurate'] else 'is NOT'} at least "
                f"as accurate (KKT residual and energy gap medians)")
        if s["cheapest_as_accurate_setting"]:
            line += (f"; its cheapest setting as accurate as our default ({s['cheapest_as_accurate_setting']}) "
                     f"takes {format_value(s['cheapest_as_accurate_time_ratio'])}x")
        else:
            line += "; none of its settings is as accurate as our default"
        out.append(line + ".")
    out.append("")
    out.append("Seed Table 1, redone (six-segment tufts, `medium`, press-drag-turn-lift):")
    out.append("")
    out.append(markdown_table(
        result["table1"], ["tufts", "q_max", "fresh_mean_q", "fresh_fps", "carried_mean_q", "carried_fps"],
        ["tufts", "q_max", "fresh Hessian: mean q", "frames/s", "carried Hessian: mean q", "frames/s"]))
    out.append("")
    out.append(f"{TUFTS_NOTE}.")
    out.append("")
    out.append("References (core at tolerance 1e-10, then the Newton polish):")
    out.append("")
    out.append(markdown_table(
        result["reference"], ["motion", "rate", "frames", "posable_frames", "valid_frames",
                              "reference_failed_at", "core_kkt_median", "core_kkt_max",
                              "polished_kkt_max", "probe_resyncs"],
        ["motion", "rate", "frames", "posable", "valid", "first failed frame",
         "core KKT p50", "core KKT max", "polished KKT max (valid)", "probe resyncs"]))
    return "\n".join(out)


PLOT_FLOOR = 1e-12   # errors of exactly 0 are drawn at this height of the log axis
PLOT_METRICS = (("skeleton_error_mm_median", "skeleton error, median over frames (mm)",
                 "against the reference: ours along our own trajectory, peers over one frame\n"
                 "from the reference's previous frame (not head to head)"),
                ("energy_gap_median", "relative energy gap, median over frames",
                 "on the frame problem each solver was given, against its exact minimum\n"
                 "(head to head)"))
FAMILY_STYLES = {"q_max": ("tab:blue", "o"), "tolerance": ("tab:green", "s"), "hessian": ("tab:purple", "D"),
                 "rate": ("tab:brown", "^")}
PEER_COLORS = ["tab:red", "tab:orange", "tab:gray"]


def _curve_style(solver: str, family: str, peer_index: int) -> tuple[str, str, str]:
    """(colour, marker, legend name) of one curve; `peer_index` counts the peer curves drawn so far."""
    if solver == OURS:
        color, marker = FAMILY_STYLES.get(family, ("black", "o"))
        return color, marker, f"ours: {family} sweep" if family != "hessian" else "ours: fresh Hessian"
    return PEER_COLORS[peer_index % len(PEER_COLORS)], "x", solver


def _point_tag(r: dict) -> str:
    """The text beside one point: its setting, short (q20 for q_max=20), none for the default."""
    if r["default"]:
        return ""
    tag = r["setting"].split(" (")[0]
    return tag.replace("q_max=", "q") if r["solver"] == OURS and r["family"] == "q_max" else tag


def _plot_metric(ax, curves: dict, default_row: dict, metric: tuple) -> None:
    """Draw on `ax` one error `metric` (key, axis label, title) against the time per frame: one
    curve per (solver, family) in `curves`, the shipped default starred."""
    key, label, title = metric
    peer_index = 0
    for (solver, family), rs in curves.items():
        rs = sorted(rs, key=lambda r: r["ms_per_frame_median"])
        x = [r["ms_per_frame_median"] for r in rs]
        y = [max(r[key] if r[key] is not None else np.nan, PLOT_FLOOR) for r in rs]
        color, marker, name = _curve_style(solver, family, peer_index)
        peer_index += solver != OURS
        ax.plot(x, y, marker=marker, color=color, label=name, lw=1.2, ms=6)
        for r, xi, yi in zip(rs, x, y):
            ax.annotate(_point_tag(r), (xi, yi), textcoords="offset points", xytext=(4, 4), fontsize=7,
                        color=color)
    ax.plot([default_row["ms_per_frame_median"]], [max(default_row[key], PLOT_FLOOR)], marker="*", ms=18,
            color="gold", mec="black", ls="none", label="shipped default", zorder=5)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_title(title, fontsize=9)
    ax.set_xlabel("time per frame, median (ms)")
    ax.set_ylabel(label)
    ax.grid(True, which="both", alpha=0.3)


PLOT_HINT = "plot skipped: it needs matplotlib (pip install 'brushwork[plot]')"


def plot(result: dict, path: str) -> bool:
    """Log-log plot of the error medians against the median time per frame, one curve per
    solver and setting family, the shipped default starred; written atomically to `path` (PNG).
    False, and nothing written, when matplotlib is not installed."""
    try:
        import matplotlib
    except ImportError:
        return False
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .report import write_atomic

    rows = [r for r in result["rows"] if r["ms_per_frame_median"] is not None]
    curves: dict = {}
    for r in rows:
        curves.setdefault((r["solver"], r["family"]), []).append(r)
    default_row = next(r for r in rows if r["default"])
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5))
    for ax, metric in zip(axes, PLOT_METRICS):
        _plot_metric(ax, curves, default_row, metric)
    axes[0].legend(fontsize=8, loc="best")
    fig.suptitle("brushwork: error against time per frame (" + result["machine"].split(",")[0] + ")",
                 fontsize=10)
    fig.tight_layout()
    try:
        write_atomic(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"), suffix=".png")
    finally:
        plt.close(fig)
    return True


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The precision benchmark's options (shared with the `brushwork` CLI)."""
    parser.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")
    parser.add_argument("--out", metavar="DIR", default="bench_out",
                        help="folder for precision.png and precision.md (default bench_out)")
    parser.add_argument("--quick", action="store_true",
                        help="one short stroke, fewer settings, one run, each peer at its default")
    parser.add_argument("--repeats", type=int, default=None,
                        help="runs per setting of ours, least time per frame kept (default 3; quick 1)")
    parser.add_argument("--no-peers", action="store_true", help="do not run the peer solvers")
    parser.add_argument("--no-progress", action="store_true", help="no progress lines on stderr")


def handle(args: argparse.Namespace) -> int:
    """Run with parsed `args`: print the Markdown, write the plot (and JSON). Returns the exit code."""
    from .report import check_writable, write_atomic, write_json

    if args.repeats is not None and args.repeats < 1:
        raise ValueError(f"--repeats {args.repeats} must be at least 1")
    # fail on unwritable targets before the run, not after
    os.makedirs(args.out, exist_ok=True)
    png, md = os.path.join(args.out, "precision.png"), os.path.join(args.out, "precision.md")
    check_writable(png)
    if args.json:
        check_writable(args.json)
    result = run(quick=args.quick, repeats=args.repeats, peers=not args.no_peers,
                 progress=not args.no_progress)
    text = table(result)
    print(text)
    if not plot(result, png):
        print(PLOT_HINT)
        png = "none"

    def write_md(tmp: str) -> None:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text + "\n")

    write_atomic(md, write_md, suffix=".md")
    print(f"\nplot: {png}; table: {md} ({result['wall_seconds']:.0f} s)")
    if args.json:
        write_json(args.json, result)
    return 0


def main(argv: list[str] | None = None) -> int:
    """Command line: ``python -m brushwork.bench.precision``."""
    parser = argparse.ArgumentParser(prog="brushwork bench precision",
                                     description="Error against run time per frame, ours and peers.")
    add_arguments(parser)
    return handle(parser.parse_args(argv))


if __name__ == "__main__":
    sys.exit(main())
