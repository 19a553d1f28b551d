"""Render benchmark: the per-frame cost of depositing ink, minimal scene against full scene.

The recorded press-drag-turn-lift stroke of the medium brush is simulated and deposited into a
canvas `px` pixels wide (2048 by default, 100 mm square); per-frame wall times of `Brush.step`
and `Paper.deposit` are taken separately, and "frames/s" is the two together.
"""
from __future__ import annotations

import time

import numpy as np

from ..brush import Brush, Pose
from ..motions import press_drag_turn_lift
from ..paper import Paper, render_info
from ..scene import Scene

SCENES = (("minimal", Scene.minimal), ("full", Scene.full))
PAPER_MM = 100.0


def _poses(brush: Brush, frames: int) -> list[Pose]:
    # the stroke, moved into the paper (it starts at the origin and spans about 3 x 1.5 L)
    L = brush.model.tuft_length
    poses = press_drag_turn_lift(brush.model, frames=frames)
    return [Pose((p.position[0] + 0.6 * L, p.position[1] + 0.6 * L, p.position[2]), p.tilt_deg,
                 p.azimuth_deg, p.twist_deg) for p in poses]


def run(px: int = 2048, frames: int = 320, repeats: int = 3, progress=None) -> dict:
    """Time the stroke in each scene; best of `repeats` by total time. Returns {"px", "frames",
    "renderer", "backend", "rows": [{scene, features, step_ms_p50, deposit_ms_p50,
    deposit_ms_p95, readback_ms, fps}]}."""
    if px < 64 or px > 8192:
        raise ValueError(f"px = {px}: expected 64..8192")
    if repeats < 1:
        raise ValueError(f"repeats = {repeats} must be at least 1")
    info = render_info()
    rows = []
    for name, make in SCENES:
        best = None
        for r in range(repeats):
            scene = make()
            brush = Brush("medium")
            brush.load_ink(ramp=[(0.05, 0.05, 0.05, 1.0), (0.25, 0.22, 0.2, 0.9)])
            brush.wetness = np.full(brush.model.n_segments + 1, 1.0)
            paper = Paper(PAPER_MM, PAPER_MM, px / PAPER_MM, scene=scene)
            steps, deps = [], []
            for pose in _poses(brush, frames):
                t0 = time.perf_counter()
                brush.step(pose)
                t1 = time.perf_counter()
                paper.deposit(brush)
                t2 = time.perf_counter()
                steps.append(t1 - t0)
                deps.append(t2 - t1)
            t0 = time.perf_counter()
            paper.ink()
            readback = time.perf_counter() - t0
            total = sum(steps) + sum(deps)
            if best is None or total < best[0]:
                best = (total, np.array(steps), np.array(deps), readback)
            if progress:
                progress(f"{name}: run {r + 1}/{repeats}, {frames / total:.0f} frames/s")
        total, steps, deps, readback = best
        rows.append({
            "scene": name,
            "features": ", ".join(scene.features()) or "none",
            "step_ms_p50": float(np.median(steps) * 1e3),
            "deposit_ms_p50": float(np.median(deps) * 1e3),
            "deposit_ms_p95": float(np.percentile(deps, 95) * 1e3),
            "readback_ms": readback * 1e3,
            "fps": frames / total,
        })
    return {"px": px, "frames": frames, "repeats": repeats, "backend": info["backend"],
            "renderer": info["renderer"], "rows": rows}


def table(result: dict) -> str:
    from .report import markdown_table

    text = markdown_table(
        result["rows"],
        ["scene", "features", "step_ms_p50", "deposit_ms_p50", "deposit_ms_p95", "readback_ms", "fps"],
        ["scene", "features", "step ms (p50)", "deposit ms (p50)", "deposit ms (p95)",
         f"readback ms ({result['px']} px)", "frames/s (step + deposit)"])
    return (text + f"\n\n{result['px']} x {result['px']} px canvas, {result['frames']} frames, "
            f"best of {result['repeats']}; {result['backend']}: {result['renderer']}")
