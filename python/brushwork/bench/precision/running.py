"""Work-precision benchmark: ours, the reference and the peers run along a motion, frame by frame."""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable, Optional, Sequence

import numpy as np

from ... import BrushModel
from ...brush import Brush
from .config import ENERGY_FLOOR, REF_CORE_KKT_OK, REF_KKT_OK, REF_Q_MAX, REF_TOLERANCE
from .errors import footprint_error, peer_kkt, polish, skeleton_error
from .motions import Motion
from .peers import FrameProblem


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
