"""Fitting a character's plans to its stroke outlines (`brushwork fit`).

Each stroke is fitted in writing order over the ink already laid, the brush's state carried from
the stroke before. A plan starts from the outline: its width along the median (measured across
it) inverted through the brush's width-vs-press response, the root ahead of the footprint by
the response's offset, its centre across the median where the outline's is. Then corrective
passes write the stroke on a GL-free grid (InkGrid), compare the ink's width, centre and reach
past the ends with the outline's along s and move the control values by the errors (projected
back onto the splines, which keeps the plan smooth); the plan whose ink overlaps the outline best
(IoU of the stroke alone) is kept, then a small local search over its overall press and its
reach past the ends.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np

from ..brush import Brush, Pose
from ..glyphs.score import iou, stroke_masks
from .plan import BOUNDS, CHANNELS, Gesture, GlyphPlan, Median, StrokePlan, Turn, corners_mm, fit_controls
from .planned import InkGrid, PlanWriter
from .regions import add_tally, stroke_tally
from .style import brush_model
from .style import Style, family

FIT_PX = 512              # px of the grid the passes compare on (the fit's IoU is reported at 512 px too)
SAMPLES = 24              # points along the median where widths are compared, at least
SAMPLE_MM = 1.0           # ... and at most this far apart
PASSES = 10               # corrective passes a stroke
MAX_PRESS_STEP = 0.08     # L: most press change a pass
# frames half the style's step apart: the render sweeps straight between frames, and 1 mm frames
# leave a tooth a frame on a curve's sides at 1024 px
FRAME_SPEED = 0.5
MAX_ACROSS_STEP = 1.5     # mm: most move of the root across the stroke a pass
PRESS_RESPONSE = np.linspace(0.0, 0.5, 26)     # L: presses of the response table
# the turn gesture every fitted plan starts from: the root on the median's tangent (heading over
# +-1 mm), run on 2 mm further at a corner, no extra press there
TURN = Turn(mm=1.0, press=0.0, reach_mm=2.0)
# the local search's changes: the whole press scaled, the travel's ends and the run past corners moved
POLISH = (("press", 1.06), ("press", 0.94), ("start_mm", 1.0), ("start_mm", -1.0), ("end_mm", 1.0),
          ("end_mm", -1.0), ("turn.reach_mm", 1.5), ("turn.reach_mm", -1.5))


@dataclass
class Response:
    """The brush's steady response to a straight drag at constant press: width (mm), the
    footprint centre's distance behind the root (mm) and its reach behind / ahead of its centre (mm)."""
    press: np.ndarray
    width: np.ndarray
    behind_root: np.ndarray
    reach_back: np.ndarray
    reach_ahead: np.ndarray

    def press_for(self, width: np.ndarray) -> np.ndarray:
        """The least press whose steady width reaches `width` (the response's rising envelope)."""
        env = np.maximum.accumulate(self.width)
        idx = np.searchsorted(env, np.asarray(width, dtype=float))
        lo = np.clip(idx - 1, 0, len(env) - 1)
        hi = np.clip(idx, 0, len(env) - 1)
        span = np.maximum(env[hi] - env[lo], 1e-6)
        t = np.clip((np.asarray(width) - env[lo]) / span, 0.0, 1.0)
        return self.press[lo] + t * (self.press[hi] - self.press[lo])

    def slope(self, press: np.ndarray) -> np.ndarray:
        """mm of width per L of press around `press` (the envelope's, at least 5 mm/L)."""
        env = np.maximum.accumulate(self.width)
        g = np.gradient(env, self.press)
        smooth = np.convolve(np.pad(g, 2, mode="edge"), np.ones(5) / 5, mode="valid")
        return np.maximum(np.interp(press, self.press, smooth), 5.0)

    def at(self, name: str, press: np.ndarray) -> np.ndarray:
        return np.interp(press, self.press, getattr(self, name))


@lru_cache(maxsize=8)
def response(preset: str, tilt_deg: float, changes: tuple = ()) -> Response:
    """Drag the brush (the preset, with the (field, value) pairs of `changes` set) straight along
    +x at each press of PRESS_RESPONSE and read its footprint once it is steady."""
    b = Brush(brush_model(preset, dict(changes)))
    L = b.model.tuft_length
    rows = []
    for p in PRESS_RESPONSE:
        b.reset()
        z = L * math.cos(math.radians(tilt_deg)) - p * L
        for k in range(10):
            b.step(Pose((0.0, 0.0, z + (1.0 - (k + 1) / 10) * 0.1 * L), tilt_deg, 0.0))
        seen = []
        for k in range(40):
            b.step(Pose((float(k), 0.0, z), tilt_deg, 0.0))
            loops = b.footprint()
            if k >= 25 and loops:
                pts = np.concatenate([np.asarray(lp)[:, :2] for lp in loops])
                cx = 0.5 * (pts[:, 0].min() + pts[:, 0].max())
                seen.append((pts[:, 1].max() - pts[:, 1].min(), k - cx, cx - pts[:, 0].min(), pts[:, 0].max() - cx))
        rows.append(np.mean(seen, axis=0) if seen else (0.0, 0.0, 0.0, 0.0))
    a = np.array(rows)
    return Response(PRESS_RESPONSE.copy(), a[:, 0], a[:, 1], a[:, 2], a[:, 3])


class Profile:
    """A mask measured along a median (px): at each sample, the extent of the mask across the
    median on either side (left, right px, NaN where the mask misses the median), and how far
    the mask reaches before the start and past the end along the end tangents (px)."""

    def __init__(self, mask: np.ndarray, pts: np.ndarray, normal: np.ndarray, t0: np.ndarray, t1: np.ndarray,
                 reach_px: float):
        h, w = mask.shape
        steps = np.arange(-reach_px, reach_px + 0.25, 0.5)
        xy = pts[:, None, :] + steps[None, :, None] * normal[:, None, :]          # (M, T, 2)
        inside = _lookup(mask, xy)
        c = len(steps) // 2
        self.left, self.right = np.full(len(pts), np.nan), np.full(len(pts), np.nan)
        for i, row in enumerate(inside):
            hits = np.flatnonzero(row)
            if len(hits) == 0:
                continue
            j = hits[np.argmin(np.abs(hits - c))]
            lo, hi = _run(row, j)
            self.left[i], self.right[i] = steps[hi], -steps[lo]   # +normal is left
        self.before = _reach(mask, pts[0], -t0, reach_px * 3)
        self.after = _reach(mask, pts[-1], t1, reach_px * 3)

    @property
    def width(self) -> np.ndarray:
        return self.left + self.right

    @property
    def centre(self) -> np.ndarray:
        return 0.5 * (self.left - self.right)


def _lookup(mask: np.ndarray, xy: np.ndarray) -> np.ndarray:
    h, w = mask.shape
    x = np.round(xy[..., 0]).astype(int)
    y = np.round(xy[..., 1]).astype(int)
    ok = (x >= 0) & (x < w) & (y >= 0) & (y < h)
    out = np.zeros(x.shape, bool)
    out[ok] = mask[y[ok], x[ok]]
    return out


def _run(row: np.ndarray, j: int) -> tuple[int, int]:
    """The run of True in `row` holding index j: (first, last)."""
    lo = j
    while lo > 0 and row[lo - 1]:
        lo -= 1
    hi = j
    while hi < len(row) - 1 and row[hi + 1]:
        hi += 1
    return lo, hi


def _reach(mask: np.ndarray, p: np.ndarray, d: np.ndarray, far: float) -> float:
    """px the mask runs from p along direction d (0 when p is outside it)."""
    steps = np.arange(0.0, far, 0.5)
    inside = _lookup(mask, p[None, :] + steps[:, None] * d[None, :])
    if not inside[0]:
        return 0.0
    off = np.flatnonzero(~inside)
    return float(steps[off[0]] if len(off) else steps[-1])


class _StrokeFrame:
    """A median's sample points, normals and end tangents in a grid's px (row 0 at the top)."""

    def __init__(self, median: Median, ppm: float, em_mm: float, step_mm: float = SAMPLE_MM):
        self.median, self.ppm = median, ppm
        n = max(SAMPLES, int(median.length / step_mm) + 1)
        self.a = np.linspace(0.0, median.length, n)                             # mm along the median
        mm = median.at(self.a)
        head = median.heading(self.a)
        self.pts = np.stack([mm[:, 0] * ppm, (em_mm - mm[:, 1]) * ppm], axis=1)
        # in px (y down) the median's left normal (-sin, cos) flips its y
        self.normal = np.stack([-np.sin(head), -np.cos(head)], axis=1)
        self.t0 = np.array([median.e0[0], -median.e0[1]])
        self.t1 = np.array([median.e1[0], -median.e1[1]])

    def profile(self, mask: np.ndarray, reach_mm: float) -> Profile:
        return Profile(mask, self.pts, self.normal, self.t0, self.t1, reach_mm * self.ppm)


# the gestures a stroke family starts from: (entry frames, 藏锋 back_mm), (exit frames, move_mm)
GESTURES = {"plain": ((6, 0.0), (6, -2.0)), "tapered": ((6, 0.0), (4, 3.0)), "flared": ((6, 0.0), (4, 3.0)),
            "rising": ((6, 0.0), (4, 3.0)), "dot": ((4, 0.0), (4, -1.0)), "hook": ((6, 0.0), (4, 3.0))}


def controls_count(length_mm: float) -> int:
    """Control values a channel of a stroke this long: one each ~6 mm, 5..16 (fewer leave the
    outline's swell and thinning along a long stroke unmatched)."""
    return int(np.clip(round(length_mm / 6.0) + 4, 5, 16))


def initial_plan(target: Profile, frame: _StrokeFrame, resp: Response, st: Style, kind: str) -> StrokePlan:
    """A stroke's first plan read off its outline's profile through the brush's response."""
    med = frame.median
    width = np.nan_to_num(target.width / frame.ppm, nan=float(np.nanmedian(target.width)) / frame.ppm
                          if np.any(np.isfinite(target.width)) else st.width_em * st.em_mm)
    press = resp.press_for(width)
    centre = np.nan_to_num(target.centre / frame.ppm)
    k = controls_count(med.length)
    start = target.before / frame.ppm - float(resp.at("reach_back", press[:1])[0])
    end = target.after / frame.ppm - float(resp.at("reach_ahead", press[-1:])[0])
    span = max(med.length + start + end, 1e-3)
    s = np.clip((frame.a + start) / span, 0.0, 1.0)
    (ef, eb), (xf, xm) = GESTURES[family(kind)]
    ctl = {"press": fit_controls(s, press, k), "along": fit_controls(s, resp.at("behind_root", press), k),
           "across": fit_controls(s, centre, k), "tilt": [st.tilt_deg], "azimuth": [0.0], "twist": [0.0],
           "speed": [FRAME_SPEED]}
    return _bounded(StrokePlan(ctl, start, end, Gesture(ef, eb, 0.0), Gesture(xf, 0.0, xm), TURN))


def _bounded(plan: StrokePlan) -> StrokePlan:
    for name in CHANNELS:
        lo, hi = BOUNDS[name]
        plan.controls[name] = [float(v) for v in np.clip(plan.controls[name], lo, hi)]
    plan.start_mm = float(np.clip(plan.start_mm, -20.0, 20.0))
    plan.end_mm = float(np.clip(plan.end_mm, -20.0, 20.0))
    return plan


def _slope(resp: Response, press: np.ndarray, width: np.ndarray, seen: dict) -> np.ndarray:
    """mm of width per L of press at each sample: the secant through this pass's and the last
    pass's (press, ink width) where the press moved and the width rose with it, else the
    response's slope. `seen` keeps the last pass's."""
    slope = resp.slope(press)
    if "press" in seen:
        dp, dw = press - seen["press"], width - seen["width"]
        ok = (np.abs(dp) > 0.005) & np.isfinite(dw)
        secant = np.where(ok, dw / np.where(ok, dp, 1.0), 0.0)
        slope = np.where(ok & (secant > 2.0), np.clip(secant, 5.0, 80.0), slope)
    seen.update(press=press, width=width)
    return slope


def corrected(plan: StrokePlan, target: Profile, ink: Profile, frame: _StrokeFrame, resp: Response,
              gain: float = 0.7, seen: dict | None = None) -> StrokePlan:
    """The plan moved by its ink's errors against the target along the median: press by the
    width error over the width's slope in the press (`_slope`; `seen` carries the last pass's),
    across by the centre error, the travel's ends by the reach errors."""
    med, ppm = frame.median, frame.ppm
    span = max(med.length + plan.start_mm + plan.end_mm, 1e-3)
    s = np.clip((frame.a + plan.start_mm) / span, 0.0, 1.0)
    press = plan.channel("press", s)
    across = plan.channel("across", s)
    ok = np.isfinite(target.width)
    dw = np.where(ok & np.isfinite(ink.width), (target.width - np.nan_to_num(ink.width)) / ppm, 0.0)
    dw = np.where(ok & ~np.isfinite(ink.width), 0.3 * target.width / ppm, dw)
    dc = np.where(ok & np.isfinite(ink.width), (target.centre - np.nan_to_num(ink.centre)) / ppm, 0.0)
    k_p, k_a = len(plan.controls["press"]), len(plan.controls["across"])
    new = plan.copy()
    new.start_mm = plan.start_mm + gain * (target.before - ink.before) / ppm
    new.end_mm = plan.end_mm + gain * (target.after - ink.after) / ppm
    # a pass moves the press at most MAX_PRESS_STEP and the root at most MAX_ACROSS_STEP mm (the
    # width is not monotone in the press: a full step across a plateau overshoots)
    slope = _slope(resp, press, np.nan_to_num(ink.width / ppm), {} if seen is None else seen)
    step = np.clip(gain * dw / slope, -MAX_PRESS_STEP, MAX_PRESS_STEP)
    new.controls["press"] = fit_controls(s, press + step, k_p, smooth=0.01)
    new.controls["across"] = fit_controls(s, across + np.clip(gain * dc, -MAX_ACROSS_STEP, MAX_ACROSS_STEP), k_a,
                                          smooth=0.01)
    return _bounded(new)


class GlyphFitter:
    """Fits a glyph's plans stroke by stroke over the ink already laid (see the module)."""

    def __init__(self, style: Style, size: int = FIT_PX, passes: int = PASSES):
        self.style, self.size, self.passes = style, size, passes
        self.resp = response(style.preset, float(style.tilt_deg), tuple(sorted(style.brush.items())))
        self.regions: dict | None = None    # {family: tally} (writing/regions.py) when kept

    def fit(self, glyph) -> GlyphPlan:
        st = self.style
        masks = stroke_masks(glyph, self.size)
        grid = InkGrid(self.size, st.em_mm)
        writer = PlanWriter(st, grid)
        writer.brush.load_ink(total_mm2=st.ink_mm2, excess=0.0)
        plans = []
        for stroke, median, mask in zip(glyph.strokes, writer.medians_mm(glyph), masks):
            plans.append(self._fit_stroke(writer, grid, median, mask, stroke.kind))
        return GlyphPlan(glyph.char, plans, st.name, iou(grid.ink(), np.any(masks, axis=0)))

    def _try(self, writer: PlanWriter, grid: InkGrid, state, plan: StrokePlan, median: Median,
             mask: np.ndarray) -> tuple[float, np.ndarray]:
        """Write `plan` from the brush state `state` on a blank stroke layer: (IoU, its ink)."""
        writer.brush.set_state(state.copy())
        grid.stroke[:] = 0
        grid.last = None
        writer.write_stroke(plan, median, finish=False)
        ink = grid.stroke.astype(bool)
        return iou(ink, mask), ink

    def _fit_stroke(self, writer: PlanWriter, grid: InkGrid, median: Median, mask: np.ndarray,
                    kind: str) -> StrokePlan:
        st = self.style
        frame = _StrokeFrame(median, grid.ppm, st.em_mm)
        reach = 0.25 * st.em_mm
        target = frame.profile(mask, reach)
        state = writer.brush.state().copy()
        plan = initial_plan(target, frame, self.resp, st, kind)
        best, seen = (-1.0, plan), {}
        for _ in range(self.passes):
            score, ink = self._try(writer, grid, state, plan, median, mask)
            best = max(best, (score, plan), key=lambda t: t[0])
            plan = corrected(plan, target, frame.profile(ink, reach), frame, self.resp, seen=seen)
        best = self._polish(writer, grid, state, best, median, mask)
        # lay the best plan's ink for good, and leave the brush as that stroke left it
        _, ink = self._try(writer, grid, state, best[1], median, mask)
        if self.regions is not None:
            add_tally(self.regions, family(kind), stroke_tally(ink, mask, median, kind, grid.ppm, st.em_mm))
        grid.end_stroke()
        return best[1]

    def _polish(self, writer, grid, state, best: tuple, median: Median, mask: np.ndarray) -> tuple:
        """A small local search (POLISH), each change kept when it raises the IoU (the turn's only
        where the median has a corner)."""
        cornered = len(corners_mm(median)) > 0
        for change in POLISH:
            if change[0].startswith("turn.") and not cornered:
                continue
            trial = _changed(best[1], *change)
            score, _ = self._try(writer, grid, state, trial, median, mask)
            if score > best[0]:
                best = (score, trial)
        return best


def _changed(plan: StrokePlan, what: str, by: float) -> StrokePlan:
    new = plan.copy()
    if what == "press":
        new.controls["press"] = [v * by for v in plan.controls["press"]]
    elif what.startswith("turn.") and new.turn is not None:
        new.turn = replace(new.turn, **{what[5:]: getattr(new.turn, what[5:]) + by})
    elif not what.startswith("turn."):
        setattr(new, what, getattr(plan, what) + by)
    return _bounded(new)


def ink_widths(ink: np.ndarray, points_em: np.ndarray, size: int, covered_by: np.ndarray,
               em_mm: float = 100.0) -> tuple:
    """The ink's width across a stroke's median (em points, y up) on a (size, size) mask of an em
    box em_mm wide, every px along it: (s (n,), width px (n,) NaN where the ink misses the
    median, (n,) bool: the median point lies in `covered_by`). The median is followed as the
    writing follows it, in mm (its smoothing is in mm)."""
    med = Median(np.asarray(points_em, dtype=float) * em_mm)
    frame = _StrokeFrame(med, size / em_mm, em_mm, step_mm=em_mm / size)
    prof = frame.profile(ink, 0.1 * em_mm)
    return frame.a / max(med.length, 1e-9), prof.width, _lookup(covered_by, frame.pts)
