"""Chains as brush motions: a stroke's width and press profiles, line widths made presses by a
calibration of the brush, and the drawing.  The style's fields are in `style` (OutlineStyle)."""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .. import _core
from ..brush import Brush, Pose
from ..paper import make_paper
from ..recorded import HOVER, along_path
from ..scene import Scene
from ..writing.driver import PRESS_MAX
from .lines import KINDS
from .style import OutlineStyle

APPROACH_FRAMES = 2     # frames of the descent onto the first point
LIFT_FRAMES = 1         # frames of the lift after the last (one: the tip leaves at once, not flicked forward)
ENTRY_START = 0.0       # of the line's press where the tip first touches
ENTRY_PEAK = 0.4        # of the entry where its width is greatest
OFFSET_GAIN = 0.25      # of the footprint centre's miss added to the root's offset each frame
REHEARSAL_MM = 40.0     # length of the stroke that learns the offset before the first chain
CALIBRATION = (0.3, 0.45, 0.6, 0.75, 0.9, 1.0, 1.15, 1.35, 1.6, 1.9, 2.3, 2.8)   # of the style's press
CALIBRATION_MM = 48.0   # length of each straight stroke that measures a press's width
INK_SEEN = 0.25         # coverage from which a line's ink is seen (a light grey)
LEAD_MARGIN_MM = 5.0    # paper round the stroke that measures the lead
END_PX = 0.5            # the footprint's front stops this far short of the end: the pixel it reaches into is inked
LEAD_HEADING_MM = 1.0   # the direction a path sets off in is taken over this much of it


def weight_profile(s: np.ndarray, style: OutlineStyle) -> np.ndarray:
    """(k,) the line's width (times its weight) at arc lengths s (mm) of a stroke: widening to
    `entry_weight` ENTRY_PEAK of the way into `entry_mm` and easing back to 1 by its end; over
    the last `exit_mm` tapering to `exit_weight`.  The wider of the two envelopes never wins:
    a stroke shorter than its entry and exit stays narrower."""
    total = float(s[-1]) if len(s) else 0.0
    entry = np.interp(s, [0.0, ENTRY_PEAK * style.entry_mm, style.entry_mm], [1.0, style.entry_weight, 1.0])
    exit_ = np.interp(total - s, [0.0, style.exit_mm], [style.exit_weight, 1.0])
    return np.minimum(entry, exit_)


def press_ramp(s: np.ndarray, style: OutlineStyle) -> np.ndarray:
    """(k,) factor of the press at arc lengths s (mm): the tip touches down light (ENTRY_START)
    while already moving and presses in evenly over `entry_mm` (a press rising faster, before
    the tuft trails, splays it into a blot)."""
    return np.interp(s, [0.0, style.entry_mm], [ENTRY_START, 1.0])


def lead_in(pts: np.ndarray, weight: np.ndarray, lead_mm: float) -> tuple[np.ndarray, np.ndarray]:
    """An open path (k, 2) mm and its weights with a straight lead of `lead_mm` put before its
    first point, along the direction it sets off in (over its first LEAD_HEADING_MM)."""
    if lead_mm <= 0.0:
        return pts, weight
    along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
    k = min(int(np.searchsorted(along, LEAD_HEADING_MM)), len(pts) - 1)
    back = pts[0] - pts[k]
    back = back / max(float(np.hypot(*back)), 1e-12)
    return np.vstack([pts[0] + lead_mm * back, pts]), np.concatenate([weight[:1], weight])


@dataclass
class StrokeTimes:
    brush: float = 0.0     # s in Brush.step
    deposit: float = 0.0   # s in Paper.deposit
    strokes: int = 0
    frames: int = 0


class OutlineDrawer:
    """Draws chains (px, y down, on a W x H image) with one brush on one paper."""

    _calibrations: dict = {}     # (preset, tilt, step, press) -> the calibration's presses and widths

    def __init__(self, style: OutlineStyle, size: tuple[int, int], ink: str = "gl", stroke_regions: bool = False):
        """ink: the paper's ink path (paper.INK_PATHS); stroke_regions: keep each stroke's own
        region as geometry (`stroke_loops`) where the ink is geometry."""
        self.style = style
        w, h = size
        self.ppm = max(w, h) / style.paper_mm
        self.height_px = h
        scene = Scene(**style.scene)
        self.paper = make_paper(w / self.ppm, h / self.ppm, self.ppm, scene, ink)
        # a second geometry paper that holds the stroke being drawn only, deposited without ink
        # (so none is spent twice), cleared as its region is taken
        geometry = stroke_regions and self.paper.inked_by == "geometry"
        self.stroke_paper = _core.VectorPaper(self.paper.width_mm, self.paper.height_mm, self.ppm, scene,
                                              self.paper.tolerance) if geometry else None
        self.brush = Brush(style.preset)
        self.times = StrokeTimes()
        self._since_dip = None
        self.offset = np.zeros(2)      # mm, root - footprint centre along and across the heading
        key = (style.preset, style.tilt_deg, style.step_mm, style.press)
        if key not in self._calibrations:
            self._calibrations[key] = self._calibrate()
        self.presses, self.widths = self._calibrations[key]
        self._rehearse()

    def _dip(self, alpha: float, length_mm: float) -> None:
        st = self.style
        if self._since_dip is None or st.dip_mm <= 0 or self._since_dip >= st.dip_mm:
            self.brush.load_ink(total_mm2=st.ink_mm2, ramp=[(0.0, 0.0, 0.0, 1.0)])
            self._since_dip = 0.0
        self.brush.ink.ramp = [(0.0, 0.0, 0.0, float(alpha))]
        self._since_dip += length_mm

    def press_for(self, weight: np.ndarray) -> np.ndarray:
        """The press depths (L) whose steady line is `weight` times as wide as the style's press
        draws (the calibration's widths, kept rising, interpolated; clamped to its range)."""
        unit = float(np.interp(self.style.press, self.presses, self.widths))
        return np.interp(np.asarray(weight, dtype=float) * unit, self.widths, self.presses)

    def draw(self, chain, weight: np.ndarray | None = None) -> None:
        """One chain as one stroke: descend, move along it with the style's press, lift.
        weight: (k,) per point of the chain, its width against the kind's (None: all 1), to
        which the kind's weight and, for a hidden line, the hidden weight are applied."""
        st = self.style
        pts = np.column_stack([chain.points[:, 0], self.height_px - chain.points[:, 1]]) / self.ppm
        weight = np.ones(len(pts)) if weight is None else np.asarray(weight, dtype=float)
        if chain.closed:
            # round the loop again over its light entry and on for the exit's taper: no gap at the seam
            along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
            k = min(int(np.searchsorted(along, st.entry_mm + st.exit_mm)) + 1, len(pts))
            pts, weight = np.vstack([pts, pts[1:k]]), np.concatenate([weight, weight[1:k]])
        else:
            pts, weight = lead_in(pts, weight, self.lead_mm)
        s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
        if s[-1] <= 0:
            return
        weight = weight * st.weight[KINDS[chain.kind]] * (1.0 if chain.visible else st.hidden_weight)
        self._dip(1.0 if chain.visible else st.hidden_alpha, float(s[-1]))
        press = self.press_for(weight_profile(s, st) * weight) * press_ramp(s, st)
        poses = along_path(self.brush.model, pts, press, st.tilt_deg, None,
                           step_mm=st.step_mm, approach_frames=APPROACH_FRAMES, lift_frames=LIFT_FRAMES, hover=HOVER)
        self._follow(poses, self.paper)
        self.paper.end_stroke()
        if self.stroke_paper is not None:
            self.stroke_paper.end_stroke()
        self.times.strokes += 1
        self.times.frames += len(poses)

    def stroke_loops(self) -> list:
        """The region of the strokes drawn since the last call (geometry ink, `stroke_regions`)
        as closed loops (k, 2) px, x right, y down; none overlapping, holes inside."""
        loops = [np.column_stack([p[:, 0], self.paper.height_mm - p[:, 1]]) * self.ppm
                 for p in self.stroke_paper.outlines()]
        self.stroke_paper.clear()
        return loops

    def _scratch(self, press: np.ndarray, length_mm: float, paper=None) -> list:
        """The footprint spans (see _follow) a frame of a straight stroke of `length_mm` at the
        presses (k,) at k points evenly along it, with a scratch brush (the offset learnt with it), from
        (LEAD_MARGIN_MM, LEAD_MARGIN_MM) along x on `paper` (None: on none)."""
        st = self.style
        brush, times = self.brush, self.times
        self.brush, self.times = Brush(st.preset), StrokeTimes()
        self.brush.load_ink(total_mm2=st.ink_mm2, ramp=[(0.0, 0.0, 0.0, 1.0)])
        path = np.column_stack([np.linspace(0.0, length_mm, len(press)), np.zeros(len(press))]) + LEAD_MARGIN_MM
        spans = self._follow(along_path(self.brush.model, path, press, st.tilt_deg, None, step_mm=st.step_mm,
                                        approach_frames=APPROACH_FRAMES, lift_frames=LIFT_FRAMES, hover=HOVER), paper)
        self.brush, self.times = brush, times
        return spans

    def _calibrate(self) -> tuple[np.ndarray, np.ndarray]:
        """Presses (L) and the width (mm) of the steady line each draws: the median footprint
        width over the last third of a straight stroke of CALIBRATION_MM (the tuft settles
        over the first)."""
        presses = np.unique(np.clip(self.style.press * np.array(CALIBRATION), 1e-3, PRESS_MAX))
        widths = []
        for p in presses:
            w = [span[1] for span in self._scratch(np.array([p, p]), CALIBRATION_MM)]
            widths.append(float(np.median(w[-max(1, len(w) // 3):])) if w else 0.0)
        return presses, np.maximum.accumulate(np.asarray(widths)) + 1e-9 * np.arange(len(widths))

    def _rehearse(self) -> None:
        """Learn the root's offset from the footprint's centre before the first stroke: a straight
        stroke of REHEARSAL_MM at the style's press, with a scratch brush and no paper, so that
        the first chain starts where it should and not a trailing tuft's length early; and the
        lead the entry needs (`lead`)."""
        s = np.linspace(0.0, REHEARSAL_MM, int(REHEARSAL_MM / self.style.step_mm) + 1)
        press = self.press_for(weight_profile(s, self.style)) * press_ramp(s, self.style)
        self._scratch(press, REHEARSAL_MM)
        self.lead_mm = self._lead(press)

    def _lead(self, press: np.ndarray) -> float:
        """How far (mm) before its chain's start a stroke sets off so that its ink begins at the
        start (the light entry's first frames leave too little ink to see): where the
        rehearsal's stroke, drawn again (the offset learnt) on a scratch paper of the drawing's
        kind, first inks a pixel past INK_SEEN, behind its start."""
        st = self.style
        side = REHEARSAL_MM + 2.0 * LEAD_MARGIN_MM
        paper = make_paper(side, 2.0 * LEAD_MARGIN_MM, self.ppm, Scene(**st.scene), self.paper.inked_by)
        self._scratch(press, REHEARSAL_MM, paper)
        paper.end_stroke()
        cols = np.flatnonzero((paper.ink() > INK_SEEN).any(axis=0))
        return max(0.0, (cols[0] + 0.5) / self.ppm - LEAD_MARGIN_MM) if len(cols) else 0.0

    def _follow(self, poses: list, paper=None) -> list:
        """Step and deposit along `poses`, the root shifted so that the footprint's centre (not
        the root, which the tilted, trailing tuft leaves behind and beside the line) follows the
        path.  The shift is kept in the path's frame (along, across the heading), where it hardly
        changes, learns OFFSET_GAIN of each frame's miss there, and carries over from stroke to
        stroke; it never exceeds a tuft length.  The footprint's front stops at the path's end:
        the first frame whose centre would come nearer the end than the footprint reaches ahead
        of its centre (last frame's reach) is held back by the difference, the frames after it
        up to the lift are left out, so a line ends where its chain ends instead of overshooting it (two lines
        meeting at a point would cross there) and the tuft does not linger there, pressed (a
        bead).  Returns each frame's footprint_span (centre (2,) mm, width across the heading,
        reach behind and ahead of the centre, mm)."""
        reach = self.brush.model.tuft_length
        ahead = 0.0
        spans = []
        xy = np.array([p.position[:2] for p in poses], dtype=float)
        along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(xy, axis=0), axis=1))])
        lift, held = len(poses) - LIFT_FRAMES, False
        for k, (pose, s) in enumerate(zip(poses, along)):
            if k < lift and along[-1] - s < ahead:
                if held:
                    continue                # the front has reached the end: on to the lift
                held = True
            a = np.radians(pose.azimuth_deg)
            frame = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])   # columns: along, across
            target = np.asarray(pose.position[:2], dtype=float) - frame[:, 0] * max(0.0, ahead - (along[-1] - s))
            root = target + frame @ self.offset
            t0 = time.perf_counter()
            self.brush.step(Pose((root[0], root[1], pose.position[2]), pose.tilt_deg, pose.azimuth_deg))
            t1 = time.perf_counter()
            if paper is not None:
                paper.deposit(self.brush)
                if self.stroke_paper is not None and paper is self.paper:
                    self.stroke_paper.deposit(self.brush)
            loops = self.brush.footprint()
            seen = _core.footprint_span(loops, float(a)) if loops else None
            if seen is not None:
                self.offset += OFFSET_GAIN * (frame.T @ (target - np.asarray(seen[0])))
                self.offset *= min(1.0, reach / max(float(np.hypot(*self.offset)), 1e-12))
                ahead = float(seen[3]) + END_PX / self.ppm
                spans.append(seen)
            self.times.brush += t1 - t0
            self.times.deposit += time.perf_counter() - t1
        return spans
