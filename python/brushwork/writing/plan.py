"""A stroke's motion as a plan: smooth functions of the stroke's normalised arc length s in [0, 1]
(clamped cubic B-splines of a few control values), with the entry and exit gestures, sampled into
the brush's poses frame by frame and written open-loop (docs/plans.md describes the file).

The reference point of frame j lies at arc length u_j = -start_mm + s_j (length + start_mm +
end_mm) along the stroke's median (extended straight past its ends); the root stands `along(s)` mm
further along the median and `across(s)` mm to its left, pressed `press(s)` tuft lengths below first
contact, the handle tilted `tilt(s)` deg toward the median's heading turned by `azimuth(s)` deg
and twisted `twist(s)` deg; frames lie `speed(s)` frame steps apart. The entry comes down from
`hover` over `entry.frames` frames, landing `entry.back_mm` ahead of the start and drawn back to it
(藏锋) as it presses; the exit lifts over `exit.frames` frames while the root moves `exit.move_mm`
along the stroke (negative: drawn back over the ink, 回锋; positive: flicked out, 出锋).

A plan with a `turn` gesture stands the root `along(s)` mm ahead of the reference point on the
median's tangent there (the heading smoothed over `turn.mm`), not on the median: at a corner (折,
a hook's turn) the root runs on past it, so the trailing tuft reaches into the corner, and swings
round while the reference point passes it, pressed `turn.press` L deeper at the corner (the press
rising and falling linearly over `turn.mm` either side).

A plan with a `flick` gesture (a hook's 钩) runs its travel on `flick.past_mm` past the median's end,
straight along it, while from the median's last corner on the press eases in a straight line from
the corner's to `flick.press` there: the trailing tuft is drawn out into the hook's point.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

PLAN_VERSION = 1
CHANNELS = ("along", "across", "press", "tilt", "azimuth", "twist", "speed")
# the bounds every channel's control values keep (unit): the root's reach, the press, the handle
BOUNDS = {"along": (-40.0, 40.0), "across": (-20.0, 20.0), "press": (-0.2, 0.6), "tilt": (0.0, 60.0),
          "azimuth": (-180.0, 180.0), "twist": (-180.0, 180.0), "speed": (0.2, 5.0)}
MAX_CONTROLS = 32


class PlanError(ValueError):
    """A bad plan file: "FILE: where: what was expected"."""


def bspline_basis(s: np.ndarray, k: int) -> np.ndarray:
    """(len(s), k) clamped uniform cubic B-spline basis over [0, 1] with k >= 1 control values
    (k < 4 lowers the degree to k - 1: one value is a constant, two a line). Rows sum to 1."""
    s = np.clip(np.asarray(s, dtype=float), 0.0, 1.0)
    deg = min(3, k - 1)
    if deg == 0:
        return np.ones((len(s), 1))
    inner = np.linspace(0.0, 1.0, k - deg + 1)
    t = np.concatenate([np.zeros(deg), inner, np.ones(deg)])
    # Cox-de Boor: degree 0 on the knot spans, the last span closed at s = 1
    b = np.zeros((len(s), len(t) - 1))
    for i in range(len(t) - 1):
        if t[i] < t[i + 1]:
            b[:, i] = (s >= t[i]) & ((s < t[i + 1]) | ((t[i + 1] == 1.0) & (s == 1.0)))
    for d in range(1, deg + 1):
        nb = np.zeros((len(s), len(t) - 1 - d))
        for i in range(len(t) - 1 - d):
            left = (s - t[i]) / (t[i + d] - t[i]) * b[:, i] if t[i + d] > t[i] else 0.0
            right = (t[i + d + 1] - s) / (t[i + d + 1] - t[i + 1]) * b[:, i + 1] if t[i + d + 1] > t[i + 1] else 0.0
            nb[:, i] = left + right
        b = nb
    return b


def fit_controls(s: np.ndarray, values: np.ndarray, k: int, smooth: float = 1e-3) -> np.ndarray:
    """(k,) control values whose spline comes closest to `values` at `s` (least squares, with a
    penalty `smooth` on the controls' second differences)."""
    a = bspline_basis(s, k)
    d2 = np.diff(np.eye(k), 2, axis=0) if k > 2 else np.zeros((0, k))
    lhs = a.T @ a + smooth * len(s) * d2.T @ d2 + 1e-9 * np.eye(k)
    return np.linalg.solve(lhs, a.T @ np.asarray(values, dtype=float))


@dataclass
class Gesture:
    """An entry or an exit: frames, and how far the root moves along the stroke meanwhile (mm)."""
    frames: int = 4
    back_mm: float = 0.0      # entry: the tip lands this far ahead of the start (藏锋)
    move_mm: float = 0.0      # exit: the root moves this far along while lifting (< 0: 回锋, > 0: 出锋)


@dataclass
class Turn:
    """The corner gesture: the window (mm) the heading turns over and the extra press (L) at a corner."""
    mm: float = 1.0
    press: float = 0.0
    reach_mm: float = 0.0


@dataclass
class Flick:
    """The hook's gesture: how far past the median's end the travel runs (mm) and the press it
    eases to there (L) from the median's last corner."""
    past_mm: float = 4.0
    press: float = 0.1


FLICK_FROM = 0.6       # a flick (the plan's, the driver's) eases from the median's last corner past this fraction of it
CORNER_DEG = 45.0      # a corner: the median turns more than this ...
CORNER_MM = 3.0        # ... between its chords this far behind and ahead


def corners_mm(median: "Median", step_mm: float = 0.25) -> np.ndarray:
    """Arc lengths (mm) of the median's corners: the local maxima of the turn between the chord
    CORNER_MM behind and the chord CORNER_MM ahead, where it exceeds CORNER_DEG."""
    u = np.arange(0.0, median.length + step_mm, step_mm)
    if len(u) < 3:
        return np.zeros(0)
    p = median.at(np.r_[u - CORNER_MM, u, u + CORNER_MM]).reshape(3, len(u), 2)
    back, ahead = p[1] - p[0], p[2] - p[1]
    turn = np.degrees(np.abs(np.arctan2(back[:, 0] * ahead[:, 1] - back[:, 1] * ahead[:, 0],
                                        (back * ahead).sum(axis=1))))
    peak = (turn > CORNER_DEG) & (turn >= np.r_[0.0, turn[:-1]]) & (turn > np.r_[turn[1:], 0.0])
    return u[peak]


@dataclass
class StrokePlan:
    """One stroke's plan: control values a channel, the travel's reach past the median's ends
    (mm) and the gestures."""
    controls: dict = field(default_factory=dict)
    start_mm: float = 0.0
    end_mm: float = 0.0
    entry: Gesture = field(default_factory=Gesture)
    exit: Gesture = field(default_factory=Gesture)
    turn: Turn | None = None
    flick: Flick | None = None

    def channel(self, name: str, s: np.ndarray) -> np.ndarray:
        """The channel's values at s (array in [0, 1])."""
        c = np.asarray(self.controls[name], dtype=float)
        return bspline_basis(s, len(c)) @ c

    def to_json(self) -> dict:
        doc = {"controls": {k: [round(float(v), 5) for v in self.controls[k]] for k in CHANNELS},
               "start_mm": round(self.start_mm, 4), "end_mm": round(self.end_mm, 4),
               "entry": {"frames": self.entry.frames, "back_mm": round(self.entry.back_mm, 4)},
               "exit": {"frames": self.exit.frames, "move_mm": round(self.exit.move_mm, 4)}}
        if self.turn is not None:
            doc["turn"] = {"mm": round(self.turn.mm, 4), "press": round(self.turn.press, 4),
                           "reach_mm": round(self.turn.reach_mm, 4)}
        if self.flick is not None:
            doc["flick"] = {"past_mm": round(self.flick.past_mm, 4), "press": round(self.flick.press, 4)}
        return doc

    def copy(self) -> "StrokePlan":
        """A copy whose controls may be replaced without touching this plan's."""
        return StrokePlan(dict(self.controls), self.start_mm, self.end_mm, self.entry, self.exit, self.turn, self.flick)


def _number(v, where: str, lo: float, hi: float) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or not lo <= v <= hi:
        raise PlanError(f"{where}: expected a number in {lo:g}..{hi:g}, got {json.dumps(v)[:30]}")
    return float(v)


def stroke_plan_from_json(doc, where: str) -> StrokePlan:
    """A stroke's plan from its parsed JSON object; PlanError naming `where` and the field."""
    if not isinstance(doc, dict) or not isinstance(doc.get("controls"), dict):
        raise PlanError(f"{where}: expected an object with controls")
    controls = {}
    for name in CHANNELS:
        vals = doc["controls"].get(name)
        if not isinstance(vals, list) or not 1 <= len(vals) <= MAX_CONTROLS:
            raise PlanError(f"{where}: controls.{name}: expected a list of 1..{MAX_CONTROLS} numbers")
        controls[name] = [_number(v, f"{where}: controls.{name}", *BOUNDS[name]) for v in vals]
    gest = []
    for key in ("entry", "exit"):
        g = doc.get(key, {})
        if not isinstance(g, dict):
            raise PlanError(f"{where}: {key}: expected an object")
        frames = g.get("frames", 4)
        if isinstance(frames, bool) or not isinstance(frames, int) or not 0 <= frames <= 100:
            raise PlanError(f"{where}: {key}.frames: expected an integer 0..100")
        gest.append(Gesture(frames, _number(g.get("back_mm", 0.0), f"{where}: {key}.back_mm", -50, 50),
                            _number(g.get("move_mm", 0.0), f"{where}: {key}.move_mm", -50, 50)))
    return StrokePlan(controls, _number(doc.get("start_mm", 0.0), f"{where}: start_mm", -50, 50),
                      _number(doc.get("end_mm", 0.0), f"{where}: end_mm", -50, 50), *gest,
                      _turn_from_json(doc.get("turn"), where), _flick_from_json(doc.get("flick"), where))


def _turn_from_json(doc, where: str) -> Turn | None:
    if doc is None:
        return None
    if not isinstance(doc, dict):
        raise PlanError(f"{where}: turn: expected an object")
    return Turn(_number(doc.get("mm", 1.0), f"{where}: turn.mm", 0.1, 20),
                _number(doc.get("press", 0.0), f"{where}: turn.press", -0.3, 0.3),
                _number(doc.get("reach_mm", 0.0), f"{where}: turn.reach_mm", -20, 20))


def _flick_from_json(doc, where: str) -> Flick | None:
    if doc is None:
        return None
    if not isinstance(doc, dict):
        raise PlanError(f"{where}: flick: expected an object")
    return Flick(_number(doc.get("past_mm", 4.0), f"{where}: flick.past_mm", 0.0, 30.0),
                 _number(doc.get("press", 0.1), f"{where}: flick.press", *BOUNDS["press"]))


@dataclass
class GlyphPlan:
    """A character's plans, one a stroke in writing order, and what they were made for."""
    char: str
    strokes: list
    style: str = "kai"
    iou: float | None = None    # the fit's IoU against the outlines, when fitted

    def to_json(self) -> dict:
        doc = {"version": PLAN_VERSION, "character": self.char, "style": self.style,
               "strokes": [p.to_json() for p in self.strokes]}
        if self.iou is not None:
            doc["iou"] = round(self.iou, 4)
        return doc

    def save(self, folder: str | Path) -> Path:
        """Write FOLDER/U+XXXX.json atomically; returns its path."""
        path = plan_path(folder, self.char)
        tmp = path.with_suffix(".json.tmp")
        tmp.write_text(json.dumps(self.to_json(), ensure_ascii=False) + "\n", encoding="utf-8")
        tmp.replace(path)
        return path


def plan_path(folder: str | Path, char: str) -> Path:
    return Path(folder) / f"U+{ord(char):04X}.json"


def load_plan(folder: str | Path, char: str, strokes: int | None = None) -> GlyphPlan:
    """The plan of `char` in `folder` (PlanError when missing or bad; `strokes`: the number the
    glyph has, which the plan must match)."""
    path = plan_path(folder, char)
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise PlanError(f"{path}: no plan for {char} (brushwork fit makes one)") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        raise PlanError(f"{path}: not a plan file ({getattr(e, 'msg', e)})") from None
    if not isinstance(doc, dict) or doc.get("version") != PLAN_VERSION:
        raise PlanError(f"{path}: version: expected {PLAN_VERSION}")
    if doc.get("character") != char or not isinstance(doc.get("strokes"), list):
        raise PlanError(f"{path}: expected the character {char} and a list of strokes")
    if strokes is not None and len(doc["strokes"]) != strokes:
        raise PlanError(f"{path}: {len(doc['strokes'])} stroke plans, but {char} has {strokes} strokes")
    plans = [stroke_plan_from_json(p, f"{path}: strokes[{i}]") for i, p in enumerate(doc["strokes"])]
    return GlyphPlan(char, plans, str(doc.get("style", "kai")), doc.get("iou"))


SMOOTH_STEP_MM = 0.2    # mm between the points the median's curve is sampled at
SMOOTH_SIGMA_MM = 1.5   # mm of arc its heading is smoothed over (Gaussian sigma) between corners


def lowpass(a: np.ndarray, sigma: float) -> np.ndarray:
    """(m, ...) values along a stroke (its frames, or points of its median) convolved with a
    Gaussian of `sigma` samples along the first axis, the ends held."""
    if sigma <= 0.0 or len(a) < 2:
        return a.copy()
    r = int(math.ceil(3.0 * sigma))
    kernel = np.exp(-0.5 * (np.arange(-r, r + 1) / sigma) ** 2)
    kernel /= kernel.sum()
    padded = a[np.clip(np.arange(-r, len(a) + r), 0, len(a) - 1)]
    flat = padded.reshape(len(padded), -1)
    return np.stack([np.convolve(flat[:, k], kernel, mode="valid") for k in range(flat.shape[1])],
                    axis=1).reshape(a.shape)


def _smooth_run(pts: np.ndarray, step_mm: float) -> np.ndarray:
    """The polyline pts (k, 2) (no corner inside) resampled about step_mm apart with its heading
    smoothed over SMOOTH_SIGMA_MM of arc and integrated again: its curvature continuous, its
    straight runs straight, each vertex's turn spread over a few mm; pinned to both ends."""
    u = np.r_[0.0, np.cumsum(np.hypot(*np.diff(pts, axis=0).T))]
    n = max(int(math.ceil(u[-1] / step_mm)), 2)
    uu = np.linspace(0.0, u[-1], n + 1)
    dense = np.stack([np.interp(uu, u, pts[:, 0]), np.interp(uu, u, pts[:, 1])], axis=1)
    d = np.diff(dense, axis=0)
    heading = lowpass(np.unwrap(np.arctan2(d[:, 1], d[:, 0])), SMOOTH_SIGMA_MM / (u[-1] / n))
    ds = np.hypot(*d.T)[:, None]
    walk = dense[0] + np.r_[np.zeros((1, 2)), np.cumsum(ds * np.stack([np.cos(heading), np.sin(heading)], axis=1), axis=0)]
    # what the walk misses the far end by, taken out along the arc
    return walk + (uu / u[-1])[:, None] * (dense[-1] - walk[-1])


def smooth_polyline(pts: np.ndarray, step_mm: float = SMOOTH_STEP_MM) -> np.ndarray:
    """The polyline pts (k, 2) mm as a curve whose heading turns smoothly (_smooth_run) between its
    corners (vertices turning more than CORNER_DEG), which stay sharp: a root held ahead on the
    median's tangent (the turn gesture) then swings round no vertex of a coarse median at once,
    while a straight stroke stays straight and a 折 keeps its corner."""
    if len(pts) < 3:
        return pts
    d = np.diff(pts, axis=0)
    d /= np.linalg.norm(d, axis=1)[:, None]
    cut = np.flatnonzero(np.sum(d[:-1] * d[1:], axis=1) < math.cos(math.radians(CORNER_DEG))) + 1
    ends = [0, *cut.tolist(), len(pts) - 1]
    runs = [_smooth_run(pts[a:b + 1], step_mm) for a, b in zip(ends[:-1], ends[1:])]
    return np.vstack([r[:-1] for r in runs] + [pts[-1:]])


class Median:
    """A stroke's median as a function of arc length u (mm): its points (k, 2) mm as a curve
    (smooth_polyline: `curve`; `points` keeps them as given, t0 and t1 their end segments'
    directions), extended straight past its ends along the curve's own end directions (e0, e1);
    its heading smoothed over `smooth_mm`."""

    def __init__(self, points: np.ndarray, smooth_mm: float = 2.0):
        pts = np.asarray(points, dtype=float)
        keep = np.r_[True, np.hypot(*np.diff(pts, axis=0).T) > 1e-9]
        pts = pts[keep]
        if len(pts) == 1:
            pts = np.vstack([pts, pts + [1e-3, 0.0]])
        self.points = pts
        self.curve = smooth_polyline(pts)
        self.u = np.r_[0.0, np.cumsum(np.hypot(*np.diff(self.curve, axis=0).T))]
        self.length = float(self.u[-1])
        d0, d1 = pts[1] - pts[0], pts[-1] - pts[-2]
        self.t0, self.t1 = d0 / np.linalg.norm(d0), d1 / np.linalg.norm(d1)
        e0, e1 = self.curve[1] - self.curve[0], self.curve[-1] - self.curve[-2]
        self.e0, self.e1 = e0 / np.linalg.norm(e0), e1 / np.linalg.norm(e1)
        self.smooth = smooth_mm

    def at(self, u: np.ndarray) -> np.ndarray:
        """(len(u), 2) mm: points at arc lengths u, straight on past the ends."""
        u = np.asarray(u, dtype=float)
        p = np.stack([np.interp(u, self.u, self.curve[:, 0]), np.interp(u, self.u, self.curve[:, 1])], axis=1)
        p += np.minimum(u, 0.0)[:, None] * self.e0 + np.maximum(u - self.length, 0.0)[:, None] * self.e1
        return p

    def heading(self, u: np.ndarray, smooth_mm: float | None = None) -> np.ndarray:
        """(len(u),) rad: the direction of travel at u, from the chord over +-smooth_mm (default
        the median's)."""
        u = np.asarray(u, dtype=float)
        h = max(self.smooth if smooth_mm is None else smooth_mm, 1e-3)
        d = self.at(u + h) - self.at(u - h)
        return np.unwrap(np.arctan2(d[:, 1], d[:, 0]))


@dataclass
class Frames:
    """A stroke's sampled poses: root (m, 3) mm, tilt, azimuth, twist (m,) deg, press (m,) L;
    `on` (m,) the frames of the travel (False: entry and exit); s (m,) the travel's s."""
    root: np.ndarray
    tilt: np.ndarray
    azimuth: np.ndarray
    twist: np.ndarray
    press: np.ndarray
    on: np.ndarray
    s: np.ndarray


def _travel_s(plan: StrokePlan, span: float, step_mm: float) -> np.ndarray:
    """The travel's s values: frames speed(s) * step_mm apart (at least 0.05 mm) over `span` mm."""
    grid = np.linspace(0.0, 1.0, 513)
    gap = np.maximum(plan.channel("speed", grid) * step_mm, 0.05) / max(span, 1e-6)   # s a frame
    s, out = 0.0, [0.0]
    while s < 1.0:
        s = min(1.0, s + float(np.interp(s, grid, gap)))
        out.append(s)
    return np.array(out)


def _roots(plan: StrokePlan, median: Median, ref: np.ndarray, along: np.ndarray,
           across: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(len(ref), 2) mm roots and (len(ref),) rad headings for reference points at arc lengths
    `ref`: `along` mm ahead on the median (no turn gesture) or on its tangent (a turn gesture),
    `across` mm to its left."""
    if plan.turn is None:
        u = ref + along
        head = median.heading(u)
        base = median.at(u)
    else:
        head = median.heading(ref, plan.turn.mm)
        base = median.at(ref) + along[:, None] * np.stack([np.cos(head), np.sin(head)], axis=1)
    return base + across[:, None] * np.stack([-np.sin(head), np.cos(head)], axis=1), head


def _at_corners(plan: StrokePlan, median: Median, ref: np.ndarray, width: float) -> np.ndarray:
    """(len(ref),) in [0, 1]: 1 at each corner of the median, falling linearly to 0 `width` mm
    either side (0 everywhere without a turn gesture)."""
    near = np.zeros(len(ref))
    if plan.turn is not None:
        for c in corners_mm(median):
            near = np.maximum(near, np.clip(1.0 - np.abs(ref - c) / width, 0.0, 1.0))
    return near


def _flicked(flick: Flick, median: Median, ref: np.ndarray, s: np.ndarray,
             ch: dict) -> tuple[np.ndarray, np.ndarray]:
    """The travel's reference points `ref` (mm of arc) and s run on to flick.past_mm past the
    median's end at their last spacing, every channel in `ch` held there, and the press eased in a
    straight line to flick.press at the end from the median's last corner past FLICK_FROM of it (a
    hook's turn), or with no such corner from the deepest press past FLICK_FROM (a 捺's foot)."""
    corners = corners_mm(median)
    corners = corners[corners > FLICK_FROM * median.length]
    if len(corners) == 0:
        late = (ref > FLICK_FROM * median.length) & (ref <= median.length)
        if not late.any():
            return ref, s
        corners = np.array([float(ref[late][np.argmax(ch["press"][late])])])
    gap = float(ref[-1] - ref[-2]) if len(ref) > 1 else 0.5
    extra = np.arange(ref[-1] + gap, median.length + flick.past_mm + 1e-9, max(gap, 0.05))
    ref, s = np.r_[ref, extra], np.r_[s, np.ones(len(extra))]
    for k in ch:
        ch[k] = np.r_[ch[k], np.full(len(extra), ch[k][-1])]
    corner, end = float(corners[-1]), median.length + flick.past_mm
    at_corner = float(np.interp(corner, ref, ch["press"]))
    f = np.clip((ref - corner) / max(end - corner, 1e-6), 0.0, 1.0)
    ch["press"] = np.where(ref >= corner, at_corner + (flick.press - at_corner) * f, ch["press"])
    return ref, s


def sample(plan: StrokePlan, median: Median, shape_length: float, step_mm: float, hover: float) -> Frames:
    """The plan's poses along `median`: the entry, the travel (frames `step_mm` x speed apart) and
    the exit. shape_length: the tuft length L (mm; the press's unit); hover: L above first contact
    where the entry starts and the exit ends."""
    span = median.length + plan.start_mm + plan.end_mm
    s = _travel_s(plan, span, step_mm)
    ch = {k: plan.channel(k, s) for k in CHANNELS}
    ref = -plan.start_mm + s * span
    if plan.turn is not None:
        ch["press"] = ch["press"] + plan.turn.press * _at_corners(plan, median, ref, plan.turn.mm)
        ch["along"] = ch["along"] + plan.turn.reach_mm * _at_corners(plan, median, ref, CORNER_MM)
    if plan.flick is not None:
        ref, s = _flicked(plan.flick, median, ref, s, ch)
    travel_press = ch["press"]
    # entry: hovering over the landing point, then pressed while drawn back to the start
    e = plan.entry.frames
    te = np.arange(1, e + 1) / max(e, 1)
    r_in = np.r_[ref[0] + plan.entry.back_mm, ref[0] + plan.entry.back_mm * (1.0 - te)]
    p_in = np.r_[-hover, -hover + (travel_press[0] + hover) * te]
    # exit: lifted while moving along
    x = plan.exit.frames
    tx = np.arange(1, x + 1) / max(x, 1)
    r_out = ref[-1] + plan.exit.move_mm * tx
    p_out = travel_press[-1] + (-hover - travel_press[-1]) * tx
    n_in, n_out = len(r_in), len(r_out)
    def pad(a):
        return np.r_[np.full(n_in, a[0]), a, np.full(n_out, a[-1])]
    root, head = _roots(plan, median, np.r_[r_in, ref, r_out], pad(ch["along"]), pad(ch["across"]))
    tilt = pad(ch["tilt"])
    press = np.r_[p_in, travel_press, p_out]
    z = shape_length * np.cos(np.radians(tilt)) - press * shape_length
    on = np.r_[np.zeros(n_in, bool), np.ones(len(s), bool), np.zeros(n_out, bool)]
    return Frames(np.column_stack([root, z]), tilt, np.degrees(head) + pad(ch["azimuth"]), pad(ch["twist"]),
                  press, on, pad(s))
