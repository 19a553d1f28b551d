"""The gallery of the seed's Figure 11: sample strokes made by brush motions, on one PNG.

Every panel is a recorded motion of the medium brush (positions, pressure, tilt, azimuth) and an
ink set-up; nothing is drawn by hand. One paper with every rendering feature on holds them all,
so the picture also shows split, dry, grain, soaked-tip, colour-ramp and depletion effects where
the motion calls for them and nowhere else.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass, field

import numpy as np

from . import BrushModel
from .brush import Brush
from .files import write_image
from .paper import Paper
from .recorded import along_path
from .scene import Scene

CELL_W, CELL_H = 70.0, 50.0   # mm per panel
COLUMNS = 3


@dataclass
class Sample:
    """One panel: `strokes` are (points (k, 2) mm in the panel, press (k,) in L, tilt_deg,
    azimuth_deg or None to trail the tip) and the ink the brush is dipped in."""
    key: str
    title: str
    strokes: list
    ink_fraction: float = 1.0          # of a full load
    ink_total_mm2: float | None = None
    ramp: list | None = None
    excess: float = 0.0
    flatten: float = 0.0               # press straight down this deep (L) first, to flatten the tuft
    model: dict = field(default_factory=dict)  # BrushModel fields that differ from the medium brush
    notes: str = ""
    extra: dict = field(default_factory=dict)


def _line(x0, y0, x1, y1, k=6):
    t = np.linspace(0.0, 1.0, k)[:, None]
    return (1 - t) * np.array([x0, y0]) + t * np.array([x1, y1])


def _arc(cx, cy, r, a0, a1, k=12):
    a = np.radians(np.linspace(a0, a1, k))
    return np.stack([cx + r * np.cos(a), cy + r * np.sin(a)], axis=1)


def samples() -> list[Sample]:
    """The panels of Figure 11 (the seed skips a panel (g); so do we)."""
    rise = lambda k, top: np.concatenate([np.linspace(0.0, top, 2), np.full(k - 4, top), np.linspace(top, 0.0, 2)])
    petal = np.array([0.0, 0.12, 0.25, 0.32, 0.3, 0.2, 0.08, -0.02])
    wave_x = np.linspace(22.0, 64.0, 15)
    wave = np.stack([wave_x, 26.0 + 7.0 * np.sin((wave_x - 22.0) / 42.0 * 2.0 * np.pi)], axis=1)
    return [
        Sample("a", "central tip", [(_line(32, 25, 68, 25), rise(6, 0.28), 4.0, None)]),
        Sample("b", "pushed", [(_line(52, 25, 12, 25), rise(6, 0.22), 25.0, 0.0)],
               notes="the handle leans back against the travel: the tip is pushed and splits"),
        Sample("c", "biased tip", [(_line(16, 30, 58, 30), rise(6, 0.25), 40.0, 90.0)]),
        Sample("d", "blade-like", [(_line(22, 32, 64, 18, 8),
                                     np.array([0.0, 0.32, 0.32, 0.26, 0.18, 0.1, 0.03, -0.02]), 15.0, None)],
               excess=1.0, notes="pressed, then lifted while moving: a blade-like end"),
        Sample("e", "dry rubbing", [(_line(14, 30, 58, 30), rise(6, 0.3), 50.0, 90.0)],
               ink_fraction=0.12),
        Sample("f", "gradient petals", [(_arc(35, 6, 24, 150, 98, 8), petal, 20.0, None),
                                        (_arc(35, 6, 24, 30, 82, 8), petal, 20.0, None)],
               ramp=[(0.95, 0.85, 0.88, 0.7), (0.85, 0.25, 0.45, 1.0), (0.55, 0.05, 0.2, 1.0)]),
        Sample("h", "flattened brush", [(_line(35, 10, 35, 44), rise(6, 0.2), 10.0, 0.0)],
               flatten=0.45, notes="pressed hard straight down first: plasticity keeps it flat"),
        Sample("i", "dots", [(_line(x, 30, x + 3, 27, 4), np.array([0.0, 0.18, 0.22, -0.02]), 30.0, None)
                             for x in (20, 40, 60)]),
        Sample("j", "drying brush", [(wave, 0.26 * np.ones(len(wave)), 20.0, None)],
               ink_total_mm2=450.0, notes="ink depletes: streaks open as the brush dries"),
        Sample("k", "split brush", [(_line(20, 25, 68, 25), rise(6, 0.2), 20.0, None)],
               flatten=0.45, model={"tufts": 5, "sprout_spread": 0.5},
               notes="pressed and spread, the tuft splits into five tufts that leave separate streaks"),
        Sample("l", "even split", [(_line(20, 25, 68, 25), rise(6, 0.2), 20.0, None)],
               flatten=0.45, model={"tufts": 4, "sprout_spread": 0.5, "even_tufts": True},
               notes="the same motion; the tuft splits into four even tufts in place of satellites"),
    ]


def _draw_sample(paper: Paper, sample: Sample, origin: tuple[float, float]) -> None:
    model = BrushModel.preset("medium")
    for name, value in sample.model.items():
        setattr(model, name, value)
    brush = Brush(model)
    L = brush.model.tuft_length
    ink = brush.load_ink(total_mm2=sample.ink_total_mm2, ramp=sample.ramp or [(0.02, 0.02, 0.02, 1.0)],
                         excess=sample.excess)
    if sample.ink_fraction < 1.0:
        ink.load = ink.capacity * sample.ink_fraction
        brush.wetness = np.full(brush.model.n_segments + 1, sample.ink_fraction)
    ox, oy = origin
    if sample.flatten > 0:
        # flatten the tuft away from the paper's panel (no ink laid: a separate scrap paper)
        scrap = Paper(40, 40, 2)
        from .brush import Pose
        for k in range(30):
            z = L * (1.1 - (k + 1) / 30 * (0.1 + sample.flatten))
            brush.step(Pose((20.0, 20.0, z), 0.0, 90.0))
        for k in range(10):
            brush.step(Pose((20.0, 20.0, L * (1.0 - sample.flatten) + (k + 1) / 10 * (sample.flatten + 0.15) * L), 0.0, 90.0))
        del scrap
        ink.load = ink.capacity.copy()
        brush.wetness = np.ones(brush.model.n_segments + 1)
    for points, press, tilt, azimuth in sample.strokes:
        pts = np.asarray(points) + np.array([ox, oy])
        for pose in along_path(brush.model, pts, press, tilt, azimuth, step_mm=0.5):
            brush.step(pose)
            paper.deposit(brush)
        paper.end_stroke()


def render_gallery(path: str | os.PathLike, px_per_mm: float = 10.0, progress=None) -> str:
    """Render every sample into one PNG at `px_per_mm`, with labels; returns the path."""
    import cv2

    items = samples()
    rows = math.ceil(len(items) / COLUMNS)
    paper = Paper(COLUMNS * CELL_W, rows * CELL_H, px_per_mm, scene=Scene.full())
    for i, sample in enumerate(items):
        col, row = i % COLUMNS, i // COLUMNS
        origin = (col * CELL_W, (rows - 1 - row) * CELL_H)
        _draw_sample(paper, sample, origin)
        if progress:
            progress(f"({sample.key}) {sample.title}: {i + 1}/{len(items)}")
    img = cv2.cvtColor(paper.image(8, "white"), cv2.COLOR_RGB2BGR)
    # labels and panel borders, in pixels
    scale = px_per_mm / 10.0
    for i, sample in enumerate(items):
        col, row = i % COLUMNS, i // COLUMNS
        x0, y0 = int(col * CELL_W * px_per_mm), int(row * CELL_H * px_per_mm)
        cv2.rectangle(img, (x0, y0), (x0 + int(CELL_W * px_per_mm) - 1, y0 + int(CELL_H * px_per_mm) - 1),
                      (200, 200, 200), max(1, int(scale)))
        cv2.putText(img, f"({sample.key}) {sample.title}", (x0 + int(12 * scale), y0 + int(34 * scale)),
                    cv2.FONT_HERSHEY_SIMPLEX, 0.9 * scale, (90, 90, 90), max(1, int(2 * scale)), cv2.LINE_AA)
    return write_image(path, img)


def render_views(path: str | os.PathLike, width_px: int = 480, height_px: int = 360) -> str:
    """The brush over its stroke in the three brush-view modes, side by side (seed Figure 8)."""
    import cv2

    from .recorded import straight_stroke
    from .view import BrushView

    brush = Brush("medium")
    brush.load_ink(ramp=[(0.1, 0.1, 0.1, 1.0)])
    paper = Paper(120, 80, 8)
    for pose in straight_stroke(brush.model, start=(40, 40), length_mm=50, press=0.3)[:45]:
        brush.step(pose)
        paper.deposit(brush)
    view = BrushView(width_px, height_px)
    images = [view.render(brush, paper, mode=mode) for mode in ("shaded", "outlined", "transparent")]
    return write_image(path, cv2.cvtColor(np.hstack(images), cv2.COLOR_RGBA2BGR))
