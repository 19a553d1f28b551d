"""Work-precision benchmark: the seed's Table 1 (frames per second of 1, 3 and 5 tufts, carried
and fresh Hessian)."""
from __future__ import annotations

import math

import numpy as np

from ... import BrushModel
from ...recorded import press_drag_turn_lift


def _table1_cell(tufts: int, q_max: int, warm: bool, frames: int, repeats: int) -> tuple[float, float]:
    """(mean iterations of the main tuft, frames per second of the whole brush by core time, best
    of `repeats`) for a six-segment `medium` brush of `tufts` tufts on press-drag-turn-lift."""
    from ..solver import _one_run

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
