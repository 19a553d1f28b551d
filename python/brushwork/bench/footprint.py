"""Footprint under pressure: area and width of the footprint against press depth and tilt,
static and dragged (the figures behind the README's "Footprint under pressure" table).

A brush is lowered at the origin to `depth` L below first contact over 40 frames and held 5
frames ("static"); the "dragged" figure is the mean over frames 31-40 of a drag along +x at
0.02 L per frame with the handle leaning toward +x (the tip trails).

`--sweep` lowers the brush in steps of 0.05 mm from 0.02 L above first contact to 0.45 L below it
and raises it back, one frame a step, held in place or dragged along +x at 1 mm a frame, and
reports how the width and area follow the press: steps where the width falls as the press
deepens, the largest rise in one step, and the longest stretch of press over which the width
stands (rises less than 0.01 mm).  `--lift` drags at 0.25 L for 30 frames, then raises the root
to 0.05 L above contact over 2, 4, 8 or 16 frames while it moves on, and reports the tip's
largest jump forward (relative to the root) while the brush still inks, and how often the tip
comes back down onto the paper after it has left it.
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


SWEEP_STEP_MM = 0.05   # press step of --sweep, mm
SWEEP_DEPTH = 0.45     # deepest press of --sweep, L below first contact
STAND_MM = 0.01        # a width that rises less than this over a step stands still, mm


def _model(preset: str, settings: dict | None) -> BrushModel:
    model = BrushModel.preset(preset)
    known = {row["name"] for row in BrushModel.parameters()}
    for name, value in (settings or {}).items():
        if name not in known:
            raise ValueError(f"unknown brush parameter {name!r} (see `brushwork params`)")
        setattr(model, name, value)
    return model


def sweep(model: BrushModel, tilt: float = 15.0, speed_mm: float = 0.0) -> np.ndarray:
    """(frames, 3) press (L below first contact), width (mm), area (mm^2) of a press down to
    SWEEP_DEPTH and back up in SWEEP_STEP_MM steps, one frame a step, the root moving `speed_mm`
    along +x a frame."""
    b = Brush(model)
    L = model.tuft_length
    top, contact = root_height(model, tilt, -0.02), root_height(model, tilt, 0.0)
    down = top - SWEEP_STEP_MM * np.arange(int(round((top - root_height(model, tilt, SWEEP_DEPTH)) / SWEEP_STEP_MM)) + 1)
    rows = []
    for k, z in enumerate(np.concatenate([down, down[-2::-1]])):
        b.step(Pose((speed_mm * k, 0.0, float(z)), tilt, 0.0))
        area, width = _measure(b)
        rows.append(((contact - z) / L, width, area))
    return np.array(rows)


def _stands(press: np.ndarray, width: np.ndarray) -> float:
    """The longest run of press (L) over which the width rises less than STAND_MM a step, from
    where it is first a millimetre wide."""
    start = int(np.argmax(width > 1.0))
    best = run = 0.0
    for k in range(start + 1, len(width)):
        run = run + press[k] - press[k - 1] if width[k] - width[k - 1] < STAND_MM else 0.0
        best = max(best, run)
    return best


def sweep_rows(model: BrushModel, progress=None) -> list[dict]:
    rows = []
    for motion, speed in (("static", 0.0), ("dragged 1 mm/frame", 1.0)):
        r = sweep(model, speed_mm=speed)
        half = len(r) // 2 + 1
        up, back = r[:half], r[half - 1:]
        dw, db = np.diff(up[:, 1]), np.diff(back[:, 1])
        rows.append({"motion": motion, "falling steps": int((dw < -1e-3).sum()),
                     "largest fall (mm)": float(max(0.0, -dw.min())), "largest rise (mm)": float(dw.max()),
                     "standing (L)": _stands(up[:, 0], up[:, 1]),
                     "width at 0.2/0.3/0.4 L (mm)": " / ".join(
                         f"{np.interp(d, up[:, 0], up[:, 1]):.2f}" for d in (0.2, 0.3, 0.4)),
                     "rises on the way up (mm)": float(max(0.0, db.max()))})
        if progress:
            progress(f"sweep {motion}")
    return rows


def lift(model: BrushModel, frames: int, press: float = 0.25, tilt: float = 15.0) -> tuple[float, int]:
    """(largest forward jump of the tip relative to the root in one frame while the brush inks,
    mm; times the tip comes back down, below 0.05 mm, after rising above 0.1 mm) for a lift over
    `frames` frames at 1 mm a frame."""
    b = Brush(model)
    za, zp = root_height(model, tilt, -0.05), root_height(model, tilt, press)
    for k in range(10):
        b.step(Pose((0.0, 0.0, za + (zp - za) * (k + 1) / 10), tilt, 0.0))
    x = 0.0
    for _ in range(30):
        x += 1.0
        b.step(Pose((x, 0.0, zp), tilt, 0.0))
    rel, tip_z, inks = [], [], []
    for k in range(frames + 6):
        x += 1.0
        b.step(Pose((x, 0.0, zp + (za - zp) * min(1.0, (k + 1) / frames)), tilt, 0.0))
        tip = b.skeleton()[-1]
        rel.append(tip[0] - x)
        tip_z.append(tip[2])
        inks.append(b.footprint_area() > 1e-3)
    jumps = np.diff(rel)[np.array(inks[1:])]
    z = np.array(tip_z)
    return float(jumps.max() if len(jumps) else 0.0), int(((z[:-1] > 0.1) & (z[1:] < 0.05)).sum())


def lift_rows(model: BrushModel, progress=None) -> list[dict]:
    rows = []
    for frames in (2, 4, 8, 16):
        jump, back = lift(model, frames)
        rows.append({"lift frames": frames, "tip jump while inking (mm/frame)": jump, "tip comes back": back})
    if progress:
        progress("lifts")
    return rows


def run(preset: str = "medium", progress=None, settings: dict | None = None) -> dict:
    """Rows {tilt, motion, depth_<d>: "area / width"}, the raw numbers, and the flicker of a
    15°, 0.25 L drag; `settings` overrides model fields (name -> value)."""
    model = _model(preset, settings)
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


def run_detail(preset: str, settings: dict | None, sweep_on: bool, lift_on: bool, progress=None) -> dict:
    """The --sweep and --lift figures (either may be off)."""
    model = _model(preset, settings)
    return {"preset": preset, "settings": settings or {},
            "sweep": sweep_rows(model, progress) if sweep_on else [],
            "lift": lift_rows(model, progress) if lift_on else []}


def detail_table(result: dict) -> str:
    from .report import markdown_table

    extra = "".join(f", {k} = {v}" for k, v in result["settings"].items())
    out = []
    if result["sweep"]:
        out += [markdown_table(result["sweep"], list(result["sweep"][0])),
                f"\n{result['preset']} brush{extra}, tilt 15°: footprint width across +x against the press, "
                f"{SWEEP_STEP_MM} mm a step down to {SWEEP_DEPTH} L below first contact and back\n"]
    if result["lift"]:
        out += [markdown_table(result["lift"], list(result["lift"][0])),
                f"\n{result['preset']} brush{extra}, tilt 15°: a 0.25 L drag at 1 mm/frame lifted to 0.05 L "
                "above contact over the given frames"]
    return "\n".join(out)


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
    p.add_argument("--sweep", action="store_true",
                   help=f"instead: width against press in {SWEEP_STEP_MM} mm steps, down and back up, static and dragged")
    p.add_argument("--lift", action="store_true",
                   help="instead: the tip during lifts over 2, 4, 8 and 16 frames (with --sweep: both)")


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
    if args.sweep or args.lift:
        return run_benchmark("footprint", args, lambda: run_detail(args.preset, settings, args.sweep, args.lift,
                                                                   progress=progress), detail_table)
    return run_benchmark("footprint", args, lambda: run(args.preset, progress=progress, settings=settings), table)
