"""A hand learned from fitted plans: for each stroke family, the plan to use as a function of the
stroke's median (its length, direction, curvature) and its neighbours (whether its ends join
another stroke, how many strokes it crosses), by k-nearest-neighbour averaging of the fitted
plans' channels sampled along s. A hand file carries the examples; `Hand.plan(glyph)` gives a
character's plans from its medians alone.
"""
from __future__ import annotations

import json
import math
from dataclasses import replace
from functools import lru_cache
from pathlib import Path

import numpy as np

from .targets import joins
from .fit import FRAME_SPEED, GESTURES, TURN, controls_count, response
from .plan import BOUNDS, CHANNELS, Flick, Gesture, GlyphPlan, Median, StrokePlan, fit_controls
from .style import PROFILE_FAMILIES, Style, family

HAND_VERSION = 2
S = np.linspace(0.0, 1.0, 9)                 # where a plan's channels are sampled for learning
LEARNED = ("press", "along", "across")       # the channels learned; the rest keep the style's
FEATURES = ("length", "chord_cos", "chord_sin", "start_cos", "start_sin", "end_cos", "end_sin", "turning",
            "corners", "joined_start", "joined_end", "crossings")
NEIGHBOURS = 7
_CACHE: dict = {}
MIN_FAMILY = 12          # fewer examples of a family: its strokes learn from every family's
# a hook is written with the flick gesture: on 4 mm past the median's end (which stops inside the
# hook) while the press eases from the last corner's to 0.1 L, the trailing tuft drawn out into the
# hook's point (without it, the press the fit found fell to nothing at the median's end and the
# hook ended in a round pad)
HOOK_FLICK = Flick(past_mm=4.0, press=0.1)
# a 捺 is written on into its blade foot: from the deepest press past 60% of the median on 4 mm
# past its end, easing to 0.1 L, the foot drawn out flat to a point (the fitted press lifted the
# brush at the median's end, inside the foot: a round cap and the tip's hairline past it)
FOOT_FLICK = Flick(past_mm=4.0, press=0.1)
FLICKS = {"hook": HOOK_FLICK, "flared": FOOT_FLICK}


def _crossings(medians: list, k: int) -> int:
    """How many other medians stroke k's median crosses (a segment of each properly intersecting)."""
    a = np.asarray(medians[k], dtype=float)
    return sum(int(_segments_cross(a, np.asarray(b, dtype=float))) for i, b in enumerate(medians) if i != k)


def _side(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> np.ndarray:
    """The cross product (q - p) x (r - p), broadcast: > 0 where r lies left of p -> q."""
    return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])


def _segments_cross(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether a segment of the polyline a (n, 2) and one of b (m, 2) cross: each segment's ends on
    strictly opposite sides of the other's line (every pair at once, (n - 1) x (m - 1))."""
    p, q = a[:-1, None, :], a[1:, None, :]
    r, s = b[None, :-1, :], b[None, 1:, :]
    return bool(np.any((_side(p, q, r) * _side(p, q, s) < 0) & (_side(r, s, p) * _side(r, s, q) < 0)))


def stroke_features(medians: list, k: int, width_mm: float) -> np.ndarray:
    """(len(FEATURES),) of stroke k among `medians` (mm polylines): length (mm), the chord's and
    the end tangents' directions, the total turning (rad), the turns of more than 45 deg, its
    ends on another stroke, the strokes it crosses."""
    m = Median(medians[k])
    chord = m.points[-1] - m.points[0]
    c = chord / max(np.linalg.norm(chord), 1e-9)
    d = np.diff(m.points, axis=0)
    ang = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
    turns = np.abs(np.diff(ang))
    j0, j1 = joins(medians, k, width_mm)
    return np.array([m.length, c[0], c[1], m.t0[0], m.t0[1], m.t1[0], m.t1[1], float(turns.sum()),
                     float((turns > math.radians(45)).sum()), float(j0), float(j1), float(_crossings(medians, k))])


ROW = 3 * len(S) + 3     # a plan row: LEARNED at S, the reach past the ends, the turn's run past corners


def plan_row(plan: StrokePlan) -> np.ndarray:
    """A plan's learned channels at S, then its reach past the median's start and end (mm) and
    its turn's run past corners (mm; the fit's when the plan has no turn)."""
    turn = plan.turn if plan.turn is not None else TURN
    return np.concatenate([plan.channel(c, S) for c in LEARNED] + [[plan.start_mm, plan.end_mm, turn.reach_mm]])


def medians_mm(glyph, em_mm: float) -> list:
    return [np.asarray(s.points, dtype=float) * em_mm for s in glyph.strokes]


class Hand:
    """Examples a stroke family: features X (n, F) and plan rows Y (n, ROW); width_em: the nominal
    stroke width of the style the examples were fitted for (None: whatever the style's)."""

    def __init__(self, style: str, families: dict, scale: np.ndarray, width_em: float | None = None):
        self.style, self.families, self.scale, self.width_em = style, families, scale, width_em

    @property
    def strokes(self) -> int:
        return sum(len(x) for x, _ in self.families.values())

    def save(self, path: str | Path) -> None:
        doc = {"version": HAND_VERSION, "style": self.style, "features": list(FEATURES),
               "samples": S.tolist(), "channels": list(LEARNED), "scale": self.scale.round(5).tolist(),
               "width_em": self.width_em, "families": {f: {"X": np.round(x, 4).tolist(), "Y": np.round(y, 4).tolist()}
                            for f, (x, y) in self.families.items()}}
        Path(path).write_text(json.dumps(doc, separators=(",", ":")) + "\n", encoding="utf-8")

    @classmethod
    def cached(cls, path: Path) -> "Hand":
        """The hand of `path`, read once a process."""
        key = str(path)
        if key not in _CACHE:
            _CACHE[key] = cls.load(path)
        return _CACHE[key]

    @classmethod
    def load(cls, path: str | Path) -> "Hand":
        try:
            doc = json.loads(Path(path).read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
            raise ValueError(f"{path}: not a hand file ({getattr(e, 'msg', e)})") from None
        if not isinstance(doc, dict) or doc.get("version") != HAND_VERSION or doc.get("features") != list(FEATURES):
            raise ValueError(f"{path}: not a hand file of version {HAND_VERSION} with features {', '.join(FEATURES)}")
        fams = {f: (np.asarray(v["X"], float).reshape(-1, len(FEATURES)), np.asarray(v["Y"], float).reshape(-1, ROW))
                for f, v in doc["families"].items()}
        width = doc.get("width_em")
        if width is not None and (isinstance(width, bool) or not isinstance(width, (int, float)) or not 0.0 < width <= 0.5):
            raise ValueError(f"{path}: width_em: expected a number in 0..0.5 or null, got {json.dumps(width)[:30]}")
        return cls(str(doc.get("style", "")), fams, np.asarray(doc["scale"], float), width)

    def _examples(self, fam: str) -> tuple:
        x, y = self.families.get(fam, (np.zeros((0, len(FEATURES))), None))
        if len(x) >= MIN_FAMILY:
            return x, y
        every = [v for v in self.families.values() if len(v[0])]
        return np.concatenate([v[0] for v in every]), np.concatenate([v[1] for v in every])

    def predict(self, fam: str, feats: np.ndarray) -> np.ndarray:
        """The plan row of a stroke of family `fam` with features `feats`: the inverse-distance
        weighted mean of its NEIGHBOURS nearest examples (features over `scale`)."""
        x, y = self._examples(fam)
        d = np.sqrt((((x - feats) / self.scale) ** 2).sum(axis=1))
        near = np.argsort(d)[:NEIGHBOURS]
        w = 1.0 / (d[near] + 0.1)
        return (w[:, None] * y[near]).sum(axis=0) / w.sum()

    def plan(self, glyph, st: Style, rng: np.random.Generator | None = None) -> GlyphPlan:
        """The character's plans from its medians alone; a style whose width_em differs from the
        hand's (a variable font's weight master) has every press widened to match (widened).
        `rng`: each stroke's width varied by the style's `jitter` (relative, normal), as a hand
        never writes a stroke twice alike; None: none."""
        width_em = st.width_em if self.width_em is None else self.width_em
        meds = medians_mm(glyph, st.em_mm)
        plans = []
        for k, stroke in enumerate(glyph.strokes):
            fam = family(stroke.kind)
            row = self.predict(fam, stroke_features(meds, k, width_em * st.em_mm))
            factor = st.width_em / width_em
            if rng is not None and st.jitter > 0.0:
                factor *= 1.0 + st.jitter * float(rng.standard_normal())
            plans.append(widened(_plan_from_row(row, Median(meds[k]).length, fam, st), factor, st))
        return GlyphPlan(glyph.char, plans, st.name)


@lru_cache(maxsize=None)
def _from_samples(k: int) -> np.ndarray:
    """(k, len(S)): k control values from a channel's values at S, as fit_controls finds them (a
    linear map, made once a k)."""
    return np.stack([fit_controls(S, e, k) for e in np.eye(len(S))], axis=1)


def _plan_from_row(row: np.ndarray, length: float, fam: str, st: Style) -> StrokePlan:
    k, n = controls_count(length), len(S)
    ctl = {c: _from_samples(k) @ row[i * n:(i + 1) * n] for i, c in enumerate(LEARNED)}
    ctl.update(tilt=[st.tilt_deg], azimuth=[0.0], twist=[0.0], speed=[FRAME_SPEED])
    (ef, eb), (xf, xm) = GESTURES[fam]
    return StrokePlan({c: [float(v) for v in ctl[c]] for c in CHANNELS}, float(row[-3]), float(row[-2]),
                      Gesture(ef, eb, 0.0), Gesture(xf, 0.0, xm), replace(TURN, reach_mm=float(row[-1])),
                      FLICKS.get(fam))


def widened(plan: StrokePlan, factor: float, st: Style) -> StrokePlan:
    """`plan` with each press control moved to the press whose steady width (the style's brush
    dragged straight, fit.response) is `factor` times its own, and the root's reach ahead of the
    footprint (`along`) moved by the response's change of it: the same stroke, broader or
    narrower (`plan` itself when factor is 1)."""
    if factor == 1.0:
        return plan
    resp = response(st.preset, float(st.tilt_deg), tuple(sorted(st.brush.items())))
    press = np.asarray(plan.controls["press"], dtype=float)
    # the width a press leaves, on the response's rising envelope (press_for's), on past the
    # table's deepest press at its slope there; a control with none (above the paper) stays
    env, deepest = np.maximum.accumulate(resp.width), resp.press[-1]
    slope = float(resp.slope(np.array([deepest]))[0])
    width = np.interp(press, resp.press, env) + np.maximum(press - deepest, 0.0) * slope
    target = factor * width
    moved = np.where(target <= env[-1], resp.press_for(np.minimum(target, env[-1])), deepest + (target - env[-1]) / slope)
    wider = np.where(width > 0.0, np.clip(moved, *BOUNDS["press"]), press)
    out = plan.copy()
    out.controls["press"] = [float(v) for v in wider]
    out.controls["along"] = [float(a + d) for a, d in zip(plan.controls["along"],
                                                       resp.at("behind_root", wider) - resp.at("behind_root", press))]
    return out


def learn_hand(pairs: list, st: Style) -> Hand:
    """A hand from (glyph, GlyphPlan) pairs: every stroke an example of its family."""
    fams: dict = {f: ([], []) for f in PROFILE_FAMILIES}
    for glyph, gp in pairs:
        meds = medians_mm(glyph, st.em_mm)
        for k, (stroke, plan) in enumerate(zip(glyph.strokes, gp.strokes)):
            xs, ys = fams[family(stroke.kind)]
            xs.append(stroke_features(meds, k, st.width_em * st.em_mm))
            ys.append(plan_row(plan))
    out = {f: (np.array(x).reshape(-1, len(FEATURES)), np.array(y).reshape(-1, ROW))
           for f, (x, y) in fams.items() if x}
    allx = np.concatenate([x for x, _ in out.values()])
    return Hand(st.name, out, np.maximum(allx.std(axis=0), 1e-3), st.width_em)
