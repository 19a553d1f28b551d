"""Solver robustness benchmark: hard and odd motions, one summary row per case.

Each case steps a fresh `Brush` (preset "medium" unless said) through a motion and records, per
frame, whether the skeleton or the energy went non-finite, the deepest penetration (mm and as a
fraction of the tuft length L), the SQP iterations, convergence and root clamping. An exception
inside a case is recorded in the row's ``raised`` field, never propagated.

Run it with ``brushwork bench stability`` or ``python -m brushwork.bench.stability``.
"""
from __future__ import annotations

import argparse
import math
import sys
import time
from collections import Counter
from typing import Callable

import numpy as np

from .. import BrushModel, Pose
from ..brush import Brush
from ..recorded import press_drag_turn_lift, root_height

# the row keys every case reports (the random and the still case add a few more)
ROW_KEYS = ("case", "frames", "nonfinite", "worst_penetration_frac", "worst_penetration_mm",
            "worst_iterations", "mean_iterations", "converged_frac", "raised")


class _Recorder:
    """Per-frame statistics of one case, folded into a row."""

    def __init__(self, case: str):
        self.case = case
        self.frames = 0
        self.nonfinite = 0
        self.worst_pen_frac = 0.0
        self.worst_pen_mm = 0.0
        self.worst_pen_at = -1
        self.worst_pen_later = 0.0
        self.worst_it = 0
        self.sum_it = 0
        self.converged = 0
        self.root_clamped = 0
        self.ls_failures = 0
        self.hessian_resets = 0
        self.worst_kkt = 0.0
        self.statuses: Counter = Counter()
        self.raised: list[str] = []
        self.extra: dict = {}

    def record(self, brush: Brush, s, tuft_length: float, first: bool = False) -> None:
        """Fold one solved frame `s` (StepStats) of `brush` (tuft length in mm) into the totals;
        `first` marks the first frame from the straight state (a fresh or reset brush)."""
        self.frames += 1
        # non-finite: the spine or the energy
        skel = np.concatenate(brush.tufts())  # every tuft's spine, a split brush's children too
        if not (np.all(np.isfinite(skel)) and math.isfinite(s.energy)):
            self.nonfinite += 1
        # penetration in mm and in tuft lengths (non-finite values are counted above, not here)
        pen = float(s.max_penetration)
        if math.isfinite(pen):
            if pen / tuft_length > self.worst_pen_frac:
                self.worst_pen_frac, self.worst_pen_at = pen / tuft_length, self.frames - 1
            self.worst_pen_mm = max(self.worst_pen_mm, pen)
            if not first:
                self.worst_pen_later = max(self.worst_pen_later, pen / tuft_length)
        # solver effort and outcome
        self.worst_it = max(self.worst_it, int(s.iterations))
        self.sum_it += int(s.iterations)
        self.converged += bool(s.converged)
        self.root_clamped += bool(s.root_clamped)
        self.ls_failures += int(s.line_search_failures)
        self.hessian_resets += int(s.hessian_resets)
        kkt = float(s.kkt_residual)
        self.worst_kkt = kkt if not math.isfinite(kkt) else max(self.worst_kkt, kkt)
        self.statuses[str(s.status)] += 1

    def row(self) -> dict:
        """The summary row (see ROW_KEYS) plus root_clamped_frames, line_search_failures,
        hessian_resets, worst_kkt_residual, statuses, worst_penetration_at (0-based frame of the
        deepest penetration relative to L, -1 if none), worst_penetration_frac_after_first (the same
        maximum leaving out first frames from the straight state) and any case-specific extras."""
        n = max(self.frames, 1)
        row = {
            "case": self.case,
            "frames": self.frames,
            "nonfinite": self.nonfinite,
            "worst_penetration_frac": self.worst_pen_frac,
            "worst_penetration_mm": self.worst_pen_mm,
            "worst_iterations": self.worst_it,
            "mean_iterations": self.sum_it / n,
            "converged_frac": self.converged / n,
            "raised": "; ".join(self.raised),
            "worst_penetration_at": self.worst_pen_at,
            "worst_penetration_frac_after_first": self.worst_pen_later,
            "root_clamped_frames": self.root_clamped,
            "line_search_failures": self.ls_failures,
            "hessian_resets": self.hessian_resets,
            "worst_kkt_residual": self.worst_kkt,
            "statuses": dict(self.statuses),
        }
        row.update(self.extra)
        return row


def _n(frames: int, scale: float, least: int = 5) -> int:
    """`frames` scaled by `scale`, at least `least`."""
    return max(least, int(round(frames * scale)))


def _ramp(a: float, b: float, n: int) -> list[float]:
    """n values from a toward b, the last one b (the start a itself is not included)."""
    return [a + (b - a) * (k + 1) / n for k in range(n)]


def _model(preset: str = "medium") -> BrushModel:
    return BrushModel.preset(preset)


def _step_all(rec: _Recorder, brush: Brush, poses) -> None:
    """Step `brush` through `poses`, recording every frame."""
    L = brush.model.tuft_length
    for k, p in enumerate(poses):
        rec.record(brush, brush.step(p), L, first=(k == 0))


# ---------------------------------------------------------------------------------------------
# the cases: each takes (recorder, frames_scale, rng) and steps its own fresh brushes


def _stiffness_case(stiffness_ratio: float, exponent: float) -> Callable:
    def case(rec: _Recorder, scale: float, rng) -> None:
        m = _model()
        m.stiffness_ratio = stiffness_ratio
        m.exponent = exponent
        # press_drag_turn_lift needs at least 50 frames
        _step_all(rec, Brush(m), press_drag_turn_lift(m, frames=_n(320, scale, least=50)))
    return case


def _press_deep(rec: _Recorder, scale: float, rng) -> None:
    # vertical; root from L+2 down to L - 1.5 L (below the paper: the core clamps it), hold, back up
    m = _model()
    L = m.tuft_length
    z_top, z_low = L + 2.0, L - 1.5 * L
    zs = _ramp(z_top, z_low, _n(60, scale)) + [z_low] * _n(60, scale) + _ramp(z_low, z_top, _n(60, scale))
    _step_all(rec, Brush(m), [Pose((0.0, 0.0, z), 0.0, 0.0) for z in zs])


def _drag_fast(rec: _Recorder, scale: float, rng) -> None:
    # tilt 20, pressed 0.25 L below contact; in place, then L per frame along +x, then instantly back
    m = _model()
    L = m.tuft_length
    tilt = 20.0
    z = root_height(m, tilt, 0.25)
    xs = [0.0] * _n(20, scale)
    xs += [L * (k + 1) for k in range(_n(100, scale))]
    xs += [xs[-1] - L * (k + 1) for k in range(_n(50, scale))]
    _step_all(rec, Brush(m), [Pose((x, 0.0, z), tilt, 180.0) for x in xs])


def _vertical_case(tilt_deg: float) -> Callable:
    def case(rec: _Recorder, scale: float, rng) -> None:
        # straight down from L+1 to 0.6 L, then hold
        m = _model()
        L = m.tuft_length
        zs = _ramp(L + 1.0, 0.6 * L, _n(80, scale)) + [0.6 * L] * _n(40, scale)
        _step_all(rec, Brush(m), [Pose((0.0, 0.0, z), tilt_deg, 0.0) for z in zs])
    return case


def _tilt85(rec: _Recorder, scale: float, rng) -> None:
    # nearly flat handle: lower from 0.2 L above contact to 0.1 L below it, then drag along -x
    m = _model()
    L = m.tuft_length
    tilt = 85.0
    contact = root_height(m, tilt, 0.0)
    z_low = root_height(m, tilt, 0.1)
    poses = [Pose((0.0, 0.0, z), tilt, 0.0) for z in _ramp(contact + 0.2 * L, z_low, _n(40, scale))]
    poses += [Pose((-0.05 * L * (k + 1), 0.0, z_low), tilt, 0.0) for k in range(_n(120, scale))]
    _step_all(rec, Brush(m), poses)


def _straight_start(rec: _Recorder, scale: float, rng) -> None:
    # the first frame jumps from the straight rest state straight into a deep press
    m = _model()
    L = m.tuft_length
    _step_all(rec, Brush(m), [Pose((0.0, 0.0, 0.7 * L), 0.0, 0.0)] * _n(100, scale))


def _still(rec: _Recorder, scale: float, rng) -> None:
    # one pressed pose held: later frames should cost ~nothing and the state should not drift
    m = _model()
    L = m.tuft_length
    tilt = 30.0
    pose = Pose((0.0, 0.0, root_height(m, tilt, 0.2)), tilt, 0.0)
    n = _n(1000, scale)
    k0 = min(int(round(200 * scale)), n - 1)
    b = Brush(m)
    it_after = 0
    state0 = None
    for k in range(n):
        s = b.step(pose)
        rec.record(b, s, L, first=(k == 0))
        if k >= k0:
            it_after += int(s.iterations)
        if k == k0:
            state0 = np.array(b.full_state(), dtype=float, copy=True)
    drift = float(np.max(np.abs(np.asarray(b.full_state(), dtype=float) - state0)))
    rec.extra.update({"iterations_after_200": it_after, "drift": drift, "drift_from_frame": k0})


class _Walk:
    """A random smooth pose walk of a brush of tuft length L: the position moves by a smoothed
    random velocity of at most vmax (0.02..0.3 L) a frame, its height reflected into [-0.2 L,
    1.3 L]; tilt, azimuth and twist take smoothed random steps, tilt reflected into [0, 85] deg
    and twist into [-90, 90] deg."""

    def __init__(self, rng, L: float):
        self.rng, self.L = rng, L
        self.vmax = float(rng.uniform(0.02, 0.3)) * L
        self.pos = np.array([0.0, 0.0, rng.uniform(-0.2, 1.3) * L])
        self.vel = np.zeros(3)
        self.tilt, self.azimuth, self.twist = rng.uniform(0.0, 85.0), rng.uniform(0.0, 360.0), rng.uniform(-30.0, 30.0)
        self.d_tilt = self.d_az = self.d_tw = 0.0

    def _move(self) -> None:
        # position: smoothed random velocity, at most vmax per frame
        self.vel = 0.7 * self.vel + 0.5 * self.vmax * self.rng.uniform(-1.0, 1.0, 3)
        speed = float(np.linalg.norm(self.vel))
        if speed > self.vmax:
            self.vel *= self.vmax / speed
        pos, vel = self.pos + self.vel, self.vel
        # z reflected into [-0.2 L, 1.3 L]
        lo, hi = -0.2 * self.L, 1.3 * self.L
        if pos[2] < lo:
            pos[2], vel[2] = 2 * lo - pos[2], -vel[2]
        if pos[2] > hi:
            pos[2], vel[2] = 2 * hi - pos[2], -vel[2]
        pos[2] = min(max(pos[2], lo), hi)
        self.pos = pos

    def _turn(self) -> None:
        # angles: smoothed random walks; tilt reflected into [0, 85], twist into [-90, 90]
        rng = self.rng
        self.d_tilt = float(np.clip(0.7 * self.d_tilt + rng.uniform(-2.5, 2.5), -8.0, 8.0))
        self.d_az = float(np.clip(0.7 * self.d_az + rng.uniform(-4.0, 4.0), -12.0, 12.0))
        self.d_tw = float(np.clip(0.7 * self.d_tw + rng.uniform(-2.0, 2.0), -6.0, 6.0))
        self.tilt += self.d_tilt
        if self.tilt < 0.0:
            self.tilt, self.d_tilt = -self.tilt, -self.d_tilt
        if self.tilt > 85.0:
            self.tilt, self.d_tilt = 170.0 - self.tilt, -self.d_tilt
        self.tilt = min(max(self.tilt, 0.0), 85.0)
        self.azimuth = (self.azimuth + self.d_az) % 360.0
        self.twist += self.d_tw
        if abs(self.twist) > 90.0:
            self.twist, self.d_tw = math.copysign(180.0, self.twist) - self.twist, -self.d_tw

    def pose(self) -> Pose:
        """The walk's next pose."""
        self._move()
        self._turn()
        return Pose((float(self.pos[0]), float(self.pos[1]), float(self.pos[2])), float(self.tilt),
                    float(self.azimuth), float(self.twist))


_EPISODE_FIELDS = ("frames", "nonfinite", "worst_penetration_frac", "worst_penetration_mm", "worst_penetration_at",
                   "worst_penetration_frac_after_first", "worst_iterations", "mean_iterations", "converged_frac",
                   "root_clamped_frames", "raised")


def _episode(rec: _Recorder, e: int, rng, presets: list, per: int, reset_every: int) -> dict:
    """One episode of `_random`: a brush of random preset, exponent and stiffness ratio walked for
    `per` frames (reset every `reset_every` in episode 0 and about a quarter of the others)."""
    preset = str(rng.choice(presets))
    exponent = float(rng.choice([2.0, 3.0]))
    stiffness = float(10.0 ** rng.uniform(0.0, 4.0))
    resets_here = e == 0 or rng.random() < 0.25
    m = _model(preset)
    m.exponent, m.stiffness_ratio = exponent, stiffness
    L = m.tuft_length
    walk = _Walk(rng, L)
    sub = _Recorder(f"random/{e}")
    info = {"episode": e, "preset": preset, "exponent": exponent, "stiffness_ratio": stiffness,
            "max_step_mm": walk.vmax, "resets": 0}
    try:
        b = Brush(m)
        for k in range(per):
            first = k == 0
            if resets_here and k > 0 and k % reset_every == 0:
                b.reset()
                info["resets"] += 1
                first = True
            s = b.step(walk.pose())
            rec.record(b, s, L, first)
            sub.record(b, s, L, first)
    except Exception as exc:  # noqa: BLE001 - recorded, the next episode goes on
        msg = f"episode {e} ({preset}, m={exponent:g}, k={stiffness:.3g}): {type(exc).__name__}: {exc}"
        rec.raised.append(msg)
        sub.raised.append(msg)
    r = sub.row()
    info.update({k: r[k] for k in _EPISODE_FIELDS})
    return info


def _random(rec: _Recorder, scale: float, rng) -> None:
    """20 episodes of random smooth pose walks (10,000 frames at scale 1), random preset, exponent
    and stiffness ratio each; episode 0 (and about a quarter of the others) resets the brush every
    ~100 frames. An exception ends its episode only; the next episode goes on."""
    n_ep = 20
    per = max(int(math.ceil(200 / n_ep)), int(round(500 * scale)))
    reset_every = max(5, int(round(100 * scale)))
    presets = list(BrushModel.presets())
    episodes = [_episode(rec, e, rng, presets, per, reset_every) for e in range(n_ep)]
    rec.extra.update({"episodes": episodes, "resets": sum(ep["resets"] for ep in episodes),
                      "frames_per_episode": per})


def _tufts_case(tufts: int) -> Callable:
    """A brush split into `tufts` tufts (the main one and its children, sprouting at half the
    default score): the press-drag-turn-lift stroke pressed 0.3 L, then random jumps of up to a
    tuft length per frame (root 1.5 L below to 1.3 L above the paper, tilts 0..85 deg)."""
    def case(rec: _Recorder, scale: float, rng) -> None:
        m = _model()
        m.tufts, m.sprout_spread = tufts - 1, 0.5
        L = m.tuft_length
        b = Brush(m)
        split = 0
        poses = press_drag_turn_lift(m, frames=_n(320, scale, least=50), press=0.3)
        pos = np.array([0.0, 0.0, 1.3 * L])
        for _ in range(_n(300, scale, least=20)):
            pos = np.clip(pos + rng.uniform(-L, L, 3) / math.sqrt(3.0), [-5 * L, -5 * L, -1.5 * L],
                          [5 * L, 5 * L, 1.3 * L])
            poses.append(Pose(tuple(float(v) for v in pos), float(rng.uniform(0.0, 85.0)),
                              float(rng.uniform(0.0, 360.0)), float(rng.uniform(-90.0, 90.0))))
        for k, p in enumerate(poses):
            s = b.step(p)
            split += s.tufts_active > 0
            rec.record(b, s, L, first=(k == 0))
        rec.extra["split_frames"] = split
    return case


def _random_extreme(rec: _Recorder, scale: float, rng) -> None:
    """Random jumps of up to a whole tuft length per frame in any direction, the root from 1.5 L
    below the paper to 1.3 L above it, tilts 0..85 deg, any azimuth and twist: 1,500 frames (at
    scale 1) on each preset, a fresh brush each."""
    per = _n(1500, scale, least=20)
    for preset in BrushModel.presets():
        m = _model(preset)
        L = m.tuft_length
        b, pos = Brush(m), np.array([0.0, 0.0, 1.3 * L])
        for k in range(per):
            jump = rng.normal(size=3)
            pos = pos + rng.uniform(0.0, L) * jump / max(float(np.linalg.norm(jump)), 1e-12)
            pos[2] = float(np.clip(pos[2], -1.5 * L, 1.3 * L))
            pos[:2] = np.clip(pos[:2], -5.0 * L, 5.0 * L)
            pose = Pose((float(pos[0]), float(pos[1]), float(pos[2])), float(rng.uniform(0.0, 85.0)),
                        float(rng.uniform(0.0, 360.0)), float(rng.uniform(-90.0, 90.0)))
            rec.record(b, b.step(pose), L, first=(k == 0))


# the case list, in the order they run
CASES: list[tuple[str, Callable]] = [
    ("stiffness 1e2 m=2", _stiffness_case(1e2, 2.0)),
    ("stiffness 1e4 m=2", _stiffness_case(1e4, 2.0)),
    ("stiffness 1e2 m=3", _stiffness_case(1e2, 3.0)),
    ("stiffness 1e4 m=3", _stiffness_case(1e4, 3.0)),
    ("press 1.5 L below contact", _press_deep),
    ("drag 1 L per frame", _drag_fast),
    ("exactly vertical", _vertical_case(0.0)),
    ("tilt 1e-8 deg", _vertical_case(1e-8)),
    ("tilt 85 deg", _tilt85),
    ("straight start", _straight_start),
    ("1000 frames without motion", _still),
    ("random", _random),
    ("random extreme jumps", _random_extreme),
    ("3 tufts", _tufts_case(3)),
    ("5 tufts", _tufts_case(5)),
]


def run(frames_scale: float = 1.0, seed: int = 0, progress: bool = True) -> list[dict]:
    """Run every case; return one row (dict) per case.

    frames_scale: multiplies every case's frame count (at least 5 frames per case, 50 for the
    press-drag-turn-lift replays, 200 random frames). seed: the random case's numpy seed.
    progress: print one line per case to stderr.

    Row keys: case, frames, nonfinite (frames whose skeleton or energy is non-finite),
    worst_penetration_frac (max penetration / tuft length), worst_penetration_mm (mm),
    worst_iterations, mean_iterations, converged_frac, raised ("" or the exception text), plus
    root_clamped_frames, line_search_failures, hessian_resets, worst_kkt_residual, statuses,
    worst_penetration_at, worst_penetration_frac_after_first, seconds (wall time of the case, s) and case-specific extras.
    """
    if not (frames_scale > 0 and math.isfinite(frames_scale)):
        raise ValueError(f"frames_scale = {frames_scale} must be a positive number")
    rows = []
    for name, case in CASES:
        rec = _Recorder(name)
        rng = np.random.default_rng(seed)
        t0 = time.perf_counter()
        # an exception ends the case and is recorded, never propagated
        try:
            case(rec, frames_scale, rng)
        except Exception as exc:  # noqa: BLE001
            rec.raised.append(f"{type(exc).__name__}: {exc}")
        row = rec.row()
        row["seconds"] = time.perf_counter() - t0
        rows.append(row)
        if progress:
            print(f"[stability] {name}: {row['frames']} frames in {row['seconds']:.1f} s, "
                  f"nonfinite {row['nonfinite']}, worst penetration "
                  f"{100 * row['worst_penetration_frac']:.3g}% L (after first frames "
                  f"{100 * row['worst_penetration_frac_after_first']:.3g}% L), max iterations {row['worst_iterations']}, "
                  f"root clamped {row['root_clamped_frames']}"
                  + (f", raised: {row['raised']}" if row["raised"] else ""),
                  file=sys.stderr, flush=True)
    return rows


def table(rows: list[dict]) -> str:
    """The Markdown summary table of `rows` from run()."""
    from .report import markdown_table

    shown = []
    for r in rows:
        shown.append({
            "case": r["case"],
            "frames": r["frames"],
            "nonfinite": r["nonfinite"],
            "pen": 100.0 * r["worst_penetration_frac"],
            "pen_later": 100.0 * r.get("worst_penetration_frac_after_first", float("nan")),
            "worst_it": r["worst_iterations"],
            "mean_it": r["mean_iterations"],
            "converged": f"{100.0 * r['converged_frac']:.1f}%",
            "clamped": r.get("root_clamped_frames"),
            "raised": r["raised"],
        })
    return markdown_table(
        shown, ["case", "frames", "nonfinite", "pen", "pen_later", "worst_it", "mean_it", "converged", "clamped", "raised"],
        ["case", "frames", "nonfinite", "worst penetration (% of L)",
         "same, after first frames (% of L)", "worst iterations",
         "mean iterations", "converged", "root clamped", "raised"])


def main(argv: list[str] | None = None) -> int:
    """Command line: run the cases, print the table, optionally write JSON. Returns the exit code."""
    parser = argparse.ArgumentParser(prog="brushwork bench stability",
                                     description="Solver robustness on hard and odd motions.")
    add_arguments(parser)
    return handle(parser.parse_args(argv))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The stability benchmark's options (shared with the `brushwork` CLI)."""
    parser.add_argument("--json", metavar="FILE", help="also write the rows as JSON to FILE")
    parser.add_argument("--quick", action="store_true", help="a tenth of the frames (frames_scale 0.1)")
    parser.add_argument("--scale", type=float, default=None, metavar="S",
                        help="frames_scale (overrides --quick)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the random case (default 0)")
    parser.add_argument("--no-progress", action="store_true", help="no per-case lines on stderr")


def handle(args: argparse.Namespace) -> int:
    """Run with parsed `args`; print the table; write JSON if asked. Returns the exit code."""
    from .report import check_writable, write_json

    # fail on an unwritable --json target before the run, not after
    if args.json:
        check_writable(args.json)
    scale = args.scale if getattr(args, "scale", None) is not None else (0.1 if args.quick else 1.0)
    t0 = time.perf_counter()
    rows = run(frames_scale=scale, seed=args.seed, progress=not getattr(args, "no_progress", False))
    wall = time.perf_counter() - t0
    print(table(rows))
    print(f"\n{sum(r['frames'] for r in rows)} frames in {wall:.1f} s (frames_scale {scale:g}, seed {args.seed})")
    if args.json:
        write_json(args.json, {"benchmark": "stability", "frames_scale": scale, "seed": args.seed,
                               "wall_seconds": wall, "rows": rows})
    return 0


if __name__ == "__main__":
    sys.exit(main())
