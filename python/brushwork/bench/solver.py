"""Solver speed benchmark: the press-drag-turn-lift stroke with the seed's solver (BFGS at q_max 20)
carrying its Hessian across frames and starting it afresh each frame, and with the shipped solver
(the preset's q_max and Newton refresh).  With ``tufts`` (the seed's Table 1 rows for 1, 3 and
5 six-segment tufts), the same stroke with the brush split into that many tufts (the main one and
its children, sprouting on the first touch) at q_max 20, carried and fresh.

Speeds are solved frames per second on one core: ``frames / sum(s.time)`` uses the core's own
per-frame timing (no Python), and the wall-clock figure includes the Python loop around it.
"""
from __future__ import annotations

import argparse
import math
import time

import numpy as np

from .. import BrushModel
from ..brush import Brush
from ..recorded import press_drag_turn_lift

# the modes compared: name -> model overrides (None: the preset as shipped)
MODES = (("carried", {"q_max": 20, "newton_after": 0, "warm_hessian": True}),
         ("fresh", {"q_max": 20, "newton_after": 0, "warm_hessian": False}),
         ("shipped", None))


def _one_run(model: BrushModel, poses) -> tuple[list, float]:
    """Replay `poses` on a fresh brush; return (StepStats list, wall seconds of the loop)."""
    b = Brush(model)
    t0 = time.perf_counter()
    stats = [b.step(p) for p in poses]
    return stats, time.perf_counter() - t0


def _timed_row(m: BrushModel, poses, repeats: int) -> dict:
    """The best of `repeats` replays of `poses` on model `m`: iterations, convergence and speed
    (see run()); with child tufts also their mean iterations per sprouted child and frame."""
    frames = len(poses)
    best_core, best_wall, best_times, stats = math.inf, math.inf, None, None
    # best of `repeats`: least summed core time, least wall time (each on its own)
    for _ in range(repeats):
        stats, wall = _one_run(m, poses)
        times = np.array([s.time for s in stats], dtype=float)
        core = float(times.sum())
        if core < best_core:
            best_core, best_times = core, times
        best_wall = min(best_wall, wall)
    children = sum(int(s.tufts_active) for s in stats)
    return {
        "warm_hessian": m.warm_hessian,
        "q_max": m.q_max,
        "newton_after": m.newton_after,
        "mean_iterations": float(np.mean([int(s.iterations) for s in stats])),
        "mean_child_iterations": sum(int(s.tuft_iterations) for s in stats) / children if children else 0.0,
        "split_frac": sum(s.tufts_active > 0 for s in stats) / frames,
        "converged_frac": sum(bool(s.converged) for s in stats) / frames,
        "fps_core": frames / best_core if best_core > 0 else math.inf,
        "fps_wall": frames / best_wall if best_wall > 0 else math.inf,
        "p50_us": float(np.percentile(best_times, 50) * 1e6),
        "p95_us": float(np.percentile(best_times, 95) * 1e6),
        "core_seconds": best_core,
        "wall_seconds": best_wall,
    }


def _tuft_rows(preset: str, frames: int, repeats: int, tufts: list[int]) -> list[dict]:
    """Rows for each total tuft count k (1 main + k-1 children, sprout_spread 0: split from the
    first touch to the lift), carried and fresh Hessian at q_max 20."""
    rows = []
    for k in tufts:
        if not 1 <= k <= 9:
            raise ValueError(f"tufts = {k}: a brush has 1 to 9 tufts (the main one and up to 8 children)")
        for mode, overrides in MODES[:2]:
            m = BrushModel.preset(preset)
            for name, value in {**overrides, "tufts": k - 1, "sprout_spread": 0.0}.items():
                setattr(m, name, value)
            rows.append({"tufts": k, "mode": mode, **_timed_row(m, press_drag_turn_lift(m, frames=frames), repeats)})
    return rows


def run(preset: str = "medium", frames: int = 320, repeats: int = 5, tufts: list[int] | None = None) -> dict:
    """Time press_drag_turn_lift(frames) on `preset` with the seed's solver (q_max 20, BFGS without
    a Newton refresh), carried and fresh Hessian, and with the shipped solver.

    Returns {"preset", "frames", "repeats", "q_max", "rows": [one dict per mode], "iteration_ratio"}
    and, with `tufts`, "tuft_rows": one dict per tuft count and mode (tufts: the main tuft and its
    children; mean_child_iterations per sprouted child and frame; split_frac: frames split)
    where each row has mode, warm_hessian, q_max, newton_after, mean_iterations, converged_frac, fps_core (frames per
    second from the core's own timing), fps_wall (frames per second including the Python loop),
    p50_us and p95_us (per-frame core time in microseconds, from the run with the least core time).
    The speed figures are the best of `repeats` runs; iteration_ratio = carried / fresh mean
    iterations.
    """
    if frames < 50:
        raise ValueError(f"frames = {frames} is too few (press_drag_turn_lift needs at least 50)")
    if repeats < 1:
        raise ValueError(f"repeats = {repeats} must be at least 1")
    rows = []
    for mode, overrides in MODES:
        # the model for this mode: the seed's plain BFGS at q_max 20 (its Table 1), or as shipped
        m = BrushModel.preset(preset)
        for name, value in (overrides or {}).items():
            setattr(m, name, value)
        rows.append({"mode": mode, **_timed_row(m, press_drag_turn_lift(m, frames=frames), repeats)})
    carried, fresh = rows[0]["mean_iterations"], rows[1]["mean_iterations"]
    result = {"preset": preset, "frames": frames, "repeats": repeats, "q_max": 20, "rows": rows,
              "iteration_ratio": carried / fresh if fresh > 0 else math.nan}
    if tufts:
        result["tuft_rows"] = _tuft_rows(preset, frames, repeats, tufts)
    return result


def table(result: dict) -> str:
    """The Markdown table of run()'s result plus the ratio line."""
    from .report import format_value, markdown_table

    text = markdown_table(
        result["rows"], ["mode", "q_max", "newton_after", "mean_iterations", "converged_frac", "fps_core",
                         "fps_wall", "p50_us", "p95_us"],
        ["mode", "q_max", "Newton after", "mean iterations", "converged", "frames/s (core)", "frames/s (wall)",
         "p50 µs", "p95 µs"])
    text += (f"\n\niterations carried/fresh: {format_value(result['iteration_ratio'])} "
             f"at q_max 20 ({result['preset']}, {result['frames']} frames, "
             f"best of {result['repeats']})")
    if result.get("tuft_rows"):
        text += "\n\n" + markdown_table(
            result["tuft_rows"], ["tufts", "mode", "mean_iterations", "mean_child_iterations", "split_frac",
                                  "fps_core", "fps_wall", "p95_us"],
            ["tufts", "Hessian", "mean q (main)", "mean q (child)", "split", "frames/s (core)", "frames/s (wall)",
             "p95 µs"])
    return text


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")
    p.add_argument("--preset", default="medium", help="brush preset (default medium)")
    p.add_argument("--frames", type=int, default=320, help="frames of the stroke (default 320)")
    p.add_argument("--repeats", type=int, default=5, help="runs per mode, best kept (default 5)")
    p.add_argument("--tufts", type=int, nargs="+", metavar="K",
                   help="also time the brush split into K tufts (the seed's Table 1: 1 3 5)")


def handle(args: argparse.Namespace) -> int:
    from .report import check_preset, run_benchmark

    check_preset(args.preset)
    return run_benchmark("solver", args, lambda: run(preset=args.preset, frames=args.frames, repeats=args.repeats,
                                                     tufts=args.tufts), table)
