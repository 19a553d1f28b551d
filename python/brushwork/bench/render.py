"""Render benchmark: the per-frame cost of depositing ink, minimal scene against full scene,
and the render mesh's ink error against its deposit time.

The recorded press-drag-turn-lift stroke of the medium brush is simulated and deposited into a
canvas `px` pixels wide (2048 by default, 100 mm square); per-frame wall times of `Brush.step`
and `Paper.deposit` are taken separately, and "frames/s" is the two together.

The mesh sweep (`mesh_sweep`) deposits one recorded stroke of the glyph driver's brush (the
small preset, at a batch's 1024 px per 100 mm em) through render meshes of decreasing fineness
(`Scene.mesh_mm`) and scores each against a much finer mesh: the ink's L1 error relative to the
reference's ink, the ink lost (the chords of a coarse ring lie inside the surface), and the
deposit's time.
"""
from __future__ import annotations

import argparse
import time

import numpy as np

from ..brush import Brush, Pose
from ..recorded import press_drag_turn_lift
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


MESH_MM = (0.0, 0.3, 0.4, 0.6, 0.8, 1.2, 1.6)   # 0: the caps (6 rings per segment, 48 around)
REFERENCE_MESH = {"mesh_rings": 16, "mesh_around": 128, "mesh_mm": 0.0}


def _mesh_stroke_ink(scene: Scene, poses: list, px_per_mm: float, repeats: int) -> tuple[np.ndarray, float]:
    """(ink (H, W) float32, median deposit ms over the best of `repeats` runs) of the small brush
    along `poses`; no depletion, so every mesh sees the very same brush states."""
    best, ink = None, None
    for _ in range(repeats):
        brush = Brush("small")
        paper = Paper(PAPER_MM, PAPER_MM, px_per_mm, scene=scene)
        deps = []
        for pose in poses:
            brush.step(pose)
            t0 = time.perf_counter()
            paper.deposit(brush)
            deps.append(time.perf_counter() - t0)
        paper.end_stroke()
        ms = float(np.median(deps) * 1e3)
        if best is None or ms < best:
            best, ink = ms, paper.ink()
    return ink, best


def mesh_sweep(px: int = 1024, frames: int = 320, repeats: int = 3, progress=None) -> dict:
    """Ink error against deposit time for each `Scene.mesh_mm` in MESH_MM (the default marked),
    against REFERENCE_MESH. Returns {"px", "frames", "default_mesh_mm", "rows": [{mesh_mm,
    rings, around, deposit_ms_p50, ink_l1_rel, ink_lost_rel, default}]}."""
    if px < 64 or px > 8192:
        raise ValueError(f"px = {px}: expected 64..8192")
    ppm = px / PAPER_MM
    poses = _poses(Brush("small"), frames)
    ref, ref_ms = _mesh_stroke_ink(Scene(**REFERENCE_MESH), poses, ppm, 1)
    ref_sum = float(ref.sum())
    default = Scene().mesh_mm
    rows = []
    for mesh_mm in MESH_MM:
        scene = Scene(mesh_mm=mesh_mm)
        ink, ms = _mesh_stroke_ink(scene, poses, ppm, repeats)
        opt = Paper(10.0, 10.0, ppm, scene=scene).mesh_options(Brush("small").model)
        rows.append({"mesh_mm": mesh_mm, "rings": opt.rings_per_segment, "around": opt.around,
                     "deposit_ms_p50": ms,
                     "ink_l1_rel": float(np.abs(ink - ref).sum()) / ref_sum,
                     "ink_lost_rel": 1.0 - float(ink.sum()) / ref_sum,
                     "default": mesh_mm == default})
        if progress:
            progress(f"mesh_mm {mesh_mm:g}: {ms:.2f} ms a deposit, ink error {rows[-1]['ink_l1_rel']:.4f}")
    return {"px": px, "frames": frames, "repeats": repeats, "default_mesh_mm": default,
            "reference": REFERENCE_MESH, "reference_deposit_ms_p50": ref_ms, "rows": rows}


def mesh_table(result: dict) -> str:
    from .report import markdown_table

    rows = [{**r, "mesh_mm": f"{r['mesh_mm']:g}" + (" (default)" if r["default"] else "") +
             (" = the caps" if r["mesh_mm"] == 0 else "")} for r in result["rows"]]
    text = markdown_table(
        rows, ["mesh_mm", "rings", "around", "deposit_ms_p50", "ink_l1_rel", "ink_lost_rel"],
        ["mesh_mm", "rings per segment", "around", "deposit ms (p50)", "ink L1 error (rel.)",
         "ink lost (rel.)"])
    ref = result["reference"]
    return (text + f"\n\nsmall brush, press-drag-turn-lift, {result['frames']} frames, {result['px']} px per "
            f"{PAPER_MM:g} mm, best of {result['repeats']}; reference mesh {ref['mesh_rings']} rings x "
            f"{ref['mesh_around']} around ({result['reference_deposit_ms_p50']:.2f} ms a deposit)")


def table(result: dict) -> str:
    from .report import markdown_table

    text = markdown_table(
        result["rows"],
        ["scene", "features", "step_ms_p50", "deposit_ms_p50", "deposit_ms_p95", "readback_ms", "fps"],
        ["scene", "features", "step ms (p50)", "deposit ms (p50)", "deposit ms (p95)",
         f"readback ms ({result['px']} px)", "frames/s (step + deposit)"])
    text += (f"\n\n{result['px']} x {result['px']} px canvas, {result['frames']} frames, "
             f"best of {result['repeats']}; {result['backend']}: {result['renderer']}")
    if "mesh" in result:
        text += "\n\nrender mesh: ink error against deposit time\n\n" + mesh_table(result["mesh"])
    return text


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")
    p.add_argument("--px", type=int, default=2048, help="canvas size in pixels (default 2048)")
    p.add_argument("--frames", type=int, default=320, help="frames of the stroke (default 320)")
    p.add_argument("--repeats", type=int, default=3, help="runs per scene, best kept (default 3)")


def handle(args: argparse.Namespace) -> int:
    from .report import progress, run_benchmark

    def both() -> dict:
        result = run(px=args.px, frames=args.frames, repeats=args.repeats, progress=progress)
        result["mesh"] = mesh_sweep(frames=args.frames, repeats=args.repeats, progress=progress)
        return result

    return run_benchmark("render", args, both, table)
