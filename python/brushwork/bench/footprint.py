"""Footprint under pressure: area and width of the footprint against press depth and tilt,
static and dragged (the figures behind the README's "Footprint under pressure" table).

A brush is lowered at the origin to `depth` L below first contact over 40 frames and held 5
frames ("static"); the "dragged" figure is the mean over frames 31-40 of a drag along +x at
0.02 L per frame with the handle leaning toward +x (the tip trails).
"""
from __future__ import annotations

import argparse
import numpy as np

from ..brush import Brush, Pose
from .. import BrushModel
from ..recorded import root_height

DEPTHS = (0.05, 0.1, 0.2, 0.3, 0.4)
TILTS = (0.0, 15.0, 30.0)


def _measure(brush: Brush) -> tuple[float, float]:
    loops = brush.footprint()
    if not loops:
        return 0.0, 0.0
    pts = np.vstack(loops)                          # (k, 2) mm
    return brush.footprint_area(), float(np.ptp(pts[:, 1]))   # mm^2, width across +x in mm


def measure(model: BrushModel, tilt: float, depth: float, drag_frames: int = 0) -> tuple[float, float]:
    """(area mm^2, width mm) static, or the mean over the last 10 of `drag_frames`."""
    b = Brush(model)
    L = model.tuft_length
    z0, z1 = root_height(model, tilt, 0.0) + 0.05 * L, root_height(model, tilt, depth)
    for k in range(40):
        b.step(Pose((0.0, 0.0, z0 + (z1 - z0) * (k + 1) / 40), tilt, 0.0))
    for _ in range(5):
        b.step(Pose((0.0, 0.0, z1), tilt, 0.0))
    if not drag_frames:
        return _measure(b)
    rec = []
    for k in range(drag_frames):
        b.step(Pose((0.02 * L * (k + 1), 0.0, z1), tilt, 0.0))
        if k >= drag_frames - 10:
            rec.append(_measure(b))
    a, w = np.mean(rec, axis=0)
    return float(a), float(w)


def flicker(model: BrushModel, tilt: float = 15.0, press: float = 0.25) -> float:
    """Mean frame-to-frame change of the footprint area over 24 frames of a drag at half a belly
    radius per frame, relative to the mean area (0: steady; 1.7: the area flips every frame)."""
    from ..recorded import straight_stroke

    b = Brush(model)
    areas = []
    poses = straight_stroke(model, start=(0.0, 0.0), length_mm=60.0, step_mm=model.belly_radius / 2,
                            press=press, tilt_deg=tilt)
    for k, pose in enumerate(poses):
        b.step(pose)
        if 20 <= k < 44:
            areas.append(b.footprint_area())
    a = np.array(areas)
    return float(np.abs(np.diff(a)).mean() / max(a.mean(), 1e-12))


def run(preset: str = "medium", progress=None, settings: dict | None = None) -> dict:
    """Rows {tilt, motion, depth_<d>: "area / width"}, the raw numbers, and the flicker of a
    15°, 0.25 L drag; `settings` overrides model fields (name -> value)."""
    model = BrushModel.preset(preset)
    known = {row["name"] for row in BrushModel.parameters()}
    for name, value in (settings or {}).items():
        if name not in known:
            raise ValueError(f"unknown brush parameter {name!r} (see `brushwork params`)")
        setattr(model, name, value)
    rows, raw = [], []
    for tilt in TILTS:
        for motion, frames in (("static", 0), ("dragged", 40)):
            row = {"tilt": f"{tilt:g}°", "motion": motion}
            for d in DEPTHS:
                a, w = measure(model, tilt, d, frames)
                row[f"{d:g} L"] = f"{a:.1f} / {w:.1f}"
                raw.append({"tilt_deg": tilt, "motion": motion, "depth_L": d, "area_mm2": a, "width_mm": w})
            rows.append(row)
            if progress:
                progress(f"tilt {tilt:g}, {motion}")
    return {"preset": preset, "settings": settings or {}, "rows": rows, "raw": raw,
            "flicker_15deg_025L": flicker(model)}


def table(result: dict) -> str:
    from .report import markdown_table

    cols = ["tilt", "motion"] + [f"{d:g} L" for d in DEPTHS]
    extra = "".join(f", {k} = {v}" for k, v in result["settings"].items())
    return (markdown_table(result["rows"], cols) +
            f"\n\n{result['preset']} brush{extra}: footprint area (mm²) / width across the travel "
            "(mm) against the press depth below first contact\n"
            f"frame-to-frame change of the footprint area, 15°, 0.25 L drag: "
            f"{100 * result['flicker_15deg_025L']:.0f}% of its mean")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")
    p.add_argument("--preset", default="medium", help="brush preset (default medium)")
    p.add_argument("--set", metavar="NAME=VALUE", action="append", default=[],
                   help="override a model field, e.g. --set internal_friction=0.3 (repeatable)")


def parse_settings(items: list[str]) -> dict:
    """--set NAME=VALUE items -> {name: bool | int | float}."""
    settings = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep:
            raise ValueError(f"--set {item!r}: expected NAME=VALUE")
        text = value.strip().lower()
        if text in ("true", "false"):
            settings[name.strip()] = text == "true"
        else:
            settings[name.strip()] = int(text) if text.lstrip("-").isdigit() else float(text)
    return settings


def handle(args: argparse.Namespace) -> int:
    from .report import check_preset, progress, run_benchmark

    check_preset(args.preset)
    settings = parse_settings(args.set)
    return run_benchmark("footprint", args, lambda: run(args.preset, progress=progress, settings=settings), table)
