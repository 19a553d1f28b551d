"""Writing from plans: a glyph's strokes, each sampled from its plan (writing/plan.py) and written
open-loop, no per-frame feedback, onto a Paper or onto an `InkGrid` (a fast ink without GL: the
footprints and the band between consecutive ones filled on a pixel grid).

The em box is drawn as Make Me a Hanzi's SVG recipe draws it (the box fills the image, no style
offset), so ink and outlines compare pixel for pixel.
"""
from __future__ import annotations

import math

import cv2
import numpy as np

from ..brush import Brush, Pose, between, solver_tally, tally_step
from ..glyphs.score import tally_bead
from ..paper import Paper
from .plan import GlyphPlan, Median, StrokePlan, sample
from .style import Style, family
from .targets import _centroid_and_width, loop_area

TRAVEL_STEP_MM = 4.0      # mm the root moves a frame in the air between strokes
TRAVEL_FRAMES = (2, 10)   # frames of one travel, fewest and most
# On a paper whose ink the EGL pass renders, a frame in which the tuft changes its shape by more
# than SNAP_MM (a joint's move relative to the root's) is solved again in up to MAX_SUBSTEPS even
# substeps, each deposited. Between two frames that pass sweeps the ink along a linear blend of
# their surfaces, which follows a tuft that bends a little, not one that snaps (a spread belly
# springing back as the press eases, a tail flicking round): a blend of the two shapes pinches in
# the middle, a neck and a bead at a stroke's exit. Ink as geometry takes the blends a tolerance
# asks for between the two frames and joins them by their support bands; split there too, the
# substeps' own solves left edges rougher (the 61 held-out characters at 2048 px: excess corners
# 6.2 against 5.3 whole, roughness at sigma 12 px 0.072 against 0.068)
SNAP_MM = 1.0
MAX_SUBSTEPS = 8
_SHIFT = 4                # cv2.fillPoly fixed-point bits


class InkGrid:
    """A GL-free ink: a (size, size) uint8 mask whose em box (em_mm square, y up) fills the grid.
    deposit(brush) fills the footprint's outer loops and the convex hull of this footprint with
    the last one of the same stroke (the band the tuft swept between the frames)."""

    def __init__(self, size: int, em_mm: float):
        self.size, self.ppm, self.em_mm = int(size), size / em_mm, em_mm
        self.mask = np.zeros((self.size, self.size), np.uint8)
        self.stroke = np.zeros_like(self.mask)   # the current stroke's ink alone
        self.last: np.ndarray | None = None      # (k, 2) px points of the last footprint, this stroke

    def _px(self, loop: np.ndarray) -> np.ndarray:
        p = np.stack([loop[:, 0] * self.ppm, (self.em_mm - loop[:, 1]) * self.ppm], axis=1)
        return np.round(p * (1 << _SHIFT)).astype(np.int32)

    def deposit(self, brush: Brush) -> bool:
        """The ink under the brush; True when it touches the paper."""
        loops = [np.asarray(lp)[:, :2] for lp in brush.footprint()]
        outer = [self._px(lp) for lp in loops if len(lp) >= 3 and loop_area(lp) > 0.0]
        if not outer:
            self.last = None
            return False
        cv2.fillPoly(self.stroke, outer, 1, cv2.LINE_8, _SHIFT)
        pts = np.concatenate(outer)
        if self.last is not None:
            hull = cv2.convexHull(np.concatenate([self.last, pts]))
            cv2.fillPoly(self.stroke, [hull], 1, cv2.LINE_8, _SHIFT)
        self.last = pts
        return True

    def end_stroke(self) -> None:
        self.mask |= self.stroke
        self.stroke[:] = 0
        self.last = None

    def ink(self) -> np.ndarray:
        """(size, size) bool, row 0 at the top."""
        return (self.mask | self.stroke).astype(bool)


class PlanWriter:
    """Writes glyphs from plans with one brush, its state (bend, plasticity, ink) carried from
    stroke to stroke; `sink` is a Paper (deposit, end_stroke) or an InkGrid. `solver`: a
    brush.solver_tally that receives every step's figures (a new one when None). `beads`: a dict
    that receives, by stroke family, [strokes ending in a bead, strokes] of the strokes `write`
    writes, from the footprint's width across the travel a frame (glyphs.score.beaded; a
    footprint a frame, ~10% of the time); None: not counted."""

    def __init__(self, style: Style, sink, brush: Brush | None = None, origin_mm=(0.0, 0.0),
                 solver: dict | None = None, beads: dict | None = None):
        self.style, self.sink = style, sink
        self.origin = np.asarray(origin_mm, dtype=float)
        self.brush = brush if brush is not None else Brush(style.model())
        self.L = self.brush.model.tuft_length
        self.frames = 0
        self.solver = solver if solver is not None else solver_tally()
        self.beads = beads
        self.pose: Pose | None = None      # the last frame's pose

    def medians_mm(self, glyph) -> list[Median]:
        """The glyph's medians in mm, the em box's bottom-left corner at `origin_mm`."""
        return [Median(self.origin + np.asarray(s.points, dtype=float) * self.style.em_mm) for s in glyph.strokes]

    def travel(self, to: np.ndarray, azimuth: float, tilt: float) -> None:
        """Lift (if down) and carry the root in the air to `to` (3,) mm."""
        here = np.asarray(self.brush.skeleton()[0], dtype=float)
        dist = float(np.linalg.norm(to[:2] - here[:2]))
        n = int(np.clip(math.ceil(dist / TRAVEL_STEP_MM), *TRAVEL_FRAMES))
        z_air = max(here[2], to[2])
        for j in range(n):
            t = (j + 1) / n
            p = here + (to - here) * t
            self._step(Pose((p[0], p[1], z_air if j < n - 1 else to[2]), tilt, azimuth))
        self._end()

    def _step(self, pose: Pose, split: bool = False) -> bool:
        """One frame at `pose`, deposited; `split`: in substeps where the tuft snaps (SNAP_MM).
        Returns whether the brush touched the paper."""
        last, self.pose = self.pose, pose
        self.frames += 1
        if not split or last is None:
            self._solve(pose)
            return self._deposit()
        saved, shape = self.brush.state().copy(), self._shape()
        stats = self.brush.step(pose)
        jump = float(np.max(np.linalg.norm(self._shape() - shape, axis=1)))
        k = min(math.ceil(jump / SNAP_MM), MAX_SUBSTEPS)
        if k <= 1:
            tally_step(self.solver, stats)
            return self._deposit()
        self.brush.set_state(saved)
        touched = False
        for j in range(1, k + 1):
            self._solve(between(last, pose, j / k))
            touched = self._deposit() or touched
        return touched

    def _solve(self, pose: Pose) -> None:
        tally_step(self.solver, self.brush.step(pose))

    def _shape(self) -> np.ndarray:
        """(n, 3) mm: the tuft's joints relative to its root."""
        joints = np.asarray(self.brush.skeleton(), dtype=float)
        return joints - joints[0]

    def _deposit(self) -> bool:
        return bool(self.sink.deposit(self.brush) if isinstance(self.sink, InkGrid)
                    else self.sink.deposit(self.brush).contact)

    def _end(self) -> None:
        self.sink.end_stroke()

    def write_stroke(self, plan: StrokePlan, median: Median, finish: bool = True) -> list[float]:
        """Travel to the stroke's first pose and write it; `finish`: end the stroke on the sink.
        Returns, when beads are counted, the footprint's width across the travel (mm) a frame
        from the first touch on; else []."""
        st = self.style
        f = sample(plan, median, self.L, st.step_mm, st.hover)
        self.travel(f.root[0], float(f.azimuth[0]), float(f.tilt[0]))
        # the descent to the paper is written frame by frame (its tip's first touches are the
        # plan's entry); from the travel's first frame on, a frame whose tuft snaps is split on a
        # paper the EGL pass inks. An InkGrid fills the hull of two frames' footprints, which no
        # blend pinches
        landed = int(np.argmax(f.on)) if f.on.any() else len(f.on)
        split = isinstance(self.sink, Paper)
        widths: list[float] = []
        for j in range(1, len(f.press)):
            pose = Pose(tuple(f.root[j]), float(f.tilt[j]), float(f.azimuth[j]), float(f.twist[j]))
            self._step(pose, split=split and j > landed)
            if self.beads is not None:
                seen = _centroid_and_width(self.brush.footprint(), math.radians(f.azimuth[j]))
                if seen is not None or widths:
                    widths.append(0.0 if seen is None else seen[1])
        if finish:
            self._end()
        return widths

    def write(self, glyph, plan: GlyphPlan, on_stroke=None) -> None:
        """glyph's strokes from their plans, in order; on_stroke(k), when given, is called once
        stroke k is written and ended on the sink."""
        if len(plan.strokes) != len(glyph.strokes):
            raise ValueError(f"{glyph.char}: {len(plan.strokes)} stroke plans for {len(glyph.strokes)} strokes")
        self.brush.load_ink(total_mm2=self.style.ink_mm2, excess=0.0)
        for k, (p, m) in enumerate(zip(plan.strokes, self.medians_mm(glyph))):
            widths = self.write_stroke(p, m)
            if self.beads is not None:
                tally_bead(self.beads, family(glyph.strokes[k].kind), widths)
            if on_stroke is not None:
                on_stroke(k)
