"""Glyph and Stroke: a character as strokes in writing order, centrelines in em units."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


# limits on a glyph, checked as it is read (glyphs/schema.json documents them)
MAX_POINTS = 10_000       # points per stroke's centreline (an SVG path's after flattening)
MAX_STROKES = 100         # strokes per glyph
MAX_COORD = 1e6           # |coordinate| in file units, the em box's too
EM_REACH = 1.0            # em: a centreline point lies at most this far outside the em box
MAX_STROKE_EM = 20.0      # em: the longest centreline (the driver takes one frame per step_mm of it)


class GlyphError(ValueError):
    """Bad glyph input. The message is "WHERE: PROBLEM", WHERE being the file (or source) at fault."""

    def __init__(self, where, problem: str | None = None):
        self.where = str(where)
        self.problem = problem
        super().__init__(self.where if problem is None else f"{self.where}: {problem}")


# The CJK Strokes block (U+31C0..U+31E3): the stroke char -> a short English name (Chinese pinyin).
STROKE_TYPES: dict[str, str] = {
    "㇀": "rising (ti)",
    "㇁": "curved hook (wangou)",
    "㇂": "slanting hook (xiegou)",
    "㇃": "lying hook (wogou)",
    "㇄": "vertical-bend (shuwan)",
    "㇅": "horizontal-turn-turn (hengzhezhe)",
    "㇆": "horizontal-turn-hook (hengzhegou)",
    "㇇": "horizontal-falling-left (hengpie)",
    "㇈": "horizontal-turn-bend-hook (hengzhewangou)",
    "㇉": "vertical-turn-turn-hook (shuzhezhegou)",
    "㇊": "horizontal-turn-rising (hengzheti)",
    "㇋": "horizontal-turn-turn-falling-left (hengzhezhepie)",
    "㇌": "horizontal-falling-left-curved-hook (hengpiewangou)",
    "㇍": "horizontal-turn-bend (hengzhewan)",
    "㇎": "horizontal-turn-turn-turn (hengzhezhezhe)",
    "㇏": "falling right (na)",
    "㇐": "horizontal (heng)",
    "㇑": "vertical (shu)",
    "㇒": "falling left (pie)",
    "㇓": "vertical-falling-left (shupie)",
    "㇔": "dot (dian)",
    "㇕": "horizontal-turn (hengzhe)",
    "㇖": "horizontal-hook (henggou)",
    "㇗": "vertical-turn (shuzhe)",
    "㇘": "vertical-bend-left (shuwanzuo)",
    "㇙": "vertical-rising (shuti)",
    "㇚": "vertical hook (shugou)",
    "㇛": "falling-left-dot (piedian)",
    "㇜": "falling-left-turn (piezhe)",
    "㇝": "rising-falling-right (tina)",
    "㇞": "vertical-turn-turn (shuzhezhe)",
    "㇟": "vertical-bend-hook (shuwangou)",
    "㇠": "horizontal-slanting-bend-hook (hengxiewangou)",
    "㇡": "horizontal-turn-turn-turn-hook (hengzhezhezhegou)",
    "㇢": "falling-left-hook (piegou)",
    "㇣": "circle (quan)",
}


def _array(name: str, value, shape_tail: tuple, k: int | None) -> np.ndarray:
    """value as float64 of shape (k,) + shape_tail, finite; ValueError naming the field otherwise."""
    try:
        a = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise GlyphError("Stroke", f"{name}: not an array of numbers") from None
    want = ((k if k is not None else -1),) + shape_tail
    if a.ndim != len(want) or (k is not None and a.shape[0] != k) or a.shape[1:] != shape_tail:
        raise GlyphError("Stroke", f"{name}: shape {a.shape}, expected ({'k' if k is None else k}"
                         + "".join(f", {n}" for n in shape_tail) + ")")
    if not np.all(np.isfinite(a)):
        raise GlyphError("Stroke", f"{name}[{int(np.argwhere(~np.isfinite(a))[0][0])}]: not finite")
    return a


@dataclass(eq=False)
class Stroke:
    """One stroke. Arrays are per point along the centreline, in writing direction."""
    points: np.ndarray                  # (k, 2) float64, k >= 2: centreline in em units ([0,1]^2, x right, y up)
    kind: str                           # a CJK Strokes char (U+31C0..U+31E3), see STROKE_TYPES
    pressure: np.ndarray | None = None  # (k,) in [0, 1]
    tilt_deg: np.ndarray | None = None  # (k,) degrees
    speed: np.ndarray | None = None     # (k,) relative, 1 = normal, >= 0
    outline: str | None = None          # filled outline, SVG path in SOURCE units (Make Me a Hanzi)

    def __post_init__(self):
        if np.size(self.points) == 0:
            raise GlyphError("Stroke", "points: empty stroke (no points)")
        self.points = _array("points", self.points, (2,), None)
        k = len(self.points)
        _check_extent(self.points)
        if k < 2 or not np.any(np.abs(np.diff(self.points, axis=0)) > 0):
            raise GlyphError("Stroke", "points: empty stroke (fewer than 2 distinct points)")
        if not isinstance(self.kind, str) or self.kind not in STROKE_TYPES:
            raise GlyphError("Stroke", f"kind: {self.kind!r} is not a CJK stroke (U+31C0..U+31E3)")
        for name in ("pressure", "tilt_deg", "speed"):
            if getattr(self, name) is not None:
                setattr(self, name, _array(name, getattr(self, name), (), k))
        if self.pressure is not None and (self.pressure.min() < 0 or self.pressure.max() > 1):
            raise GlyphError("Stroke", "pressure: outside [0, 1]")
        if self.speed is not None and self.speed.min() < 0:
            raise GlyphError("Stroke", "speed: negative")

    def __repr__(self) -> str:
        extras = "".join(f", {n}" for n in ("pressure", "tilt_deg", "speed", "outline") if getattr(self, n) is not None)
        return f"Stroke({self.kind} {STROKE_TYPES[self.kind]}, {len(self.points)} points{extras})"


@dataclass(eq=False)
class Glyph:
    """A character: strokes in writing order, and the frame of the source it came from."""
    char: str
    codepoint: int
    strokes: list[Stroke]
    source: str                                   # "glyphs:PATH", "mmah:PATH", "kanjivg[:PATH]"
    em_box: tuple[float, float, float, float]     # (x0, y0, x1, y1) in source units, y as the source has it
    source_y_down: bool = False                   # True: source y grows downward (KanjiVG, SVG)
    metadata: dict = field(default_factory=dict)  # free-form provenance (e.g. the file's "source" text)

    def __post_init__(self):
        if len(self.char) != 1 or ord(self.char) != self.codepoint:
            raise GlyphError(self.source or "Glyph", f"char {self.char!r} does not match codepoint {self.codepoint}")
        x0, y0, x1, y1 = (float(v) for v in self.em_box)
        if not (np.isfinite([x0, y0, x1, y1]).all() and x1 > x0 and y1 > y0):
            raise GlyphError(self.source or "Glyph", f"em_box {self.em_box}: needs x1 > x0 and y1 > y0")
        self.em_box = (x0, y0, x1, y1)

    def __repr__(self) -> str:
        kinds = "".join(s.kind for s in self.strokes)
        return f"Glyph({self.char!r} U+{self.codepoint:04X}, {len(self.strokes)} strokes {kinds}, {self.source})"

    def to_em(self, xy_source: np.ndarray) -> np.ndarray:
        """(..., 2) source units -> (..., 2) em units: the em box to [0, 1]^2, y up."""
        xy = np.asarray(xy_source, dtype=np.float64)
        x0, y0, x1, y1 = self.em_box
        u = (xy[..., 0] - x0) / (x1 - x0)
        v = (xy[..., 1] - y0) / (y1 - y0)
        return np.stack([u, 1.0 - v if self.source_y_down else v], axis=-1)

    def from_em(self, xy_em: np.ndarray) -> np.ndarray:
        """(..., 2) em units -> (..., 2) source units; the inverse of to_em."""
        uv = np.asarray(xy_em, dtype=np.float64)
        x0, y0, x1, y1 = self.em_box
        v = 1.0 - uv[..., 1] if self.source_y_down else uv[..., 1]
        return np.stack([x0 + uv[..., 0] * (x1 - x0), y0 + v * (y1 - y0)], axis=-1)


def _check_extent(points: np.ndarray) -> None:
    """The limits on a centreline (k, 2) in em units: MAX_POINTS points within EM_REACH of the
    em box, at most MAX_STROKE_EM long; GlyphError otherwise."""
    if len(points) > MAX_POINTS:
        raise GlyphError("Stroke", f"points: {len(points)} points, more than {MAX_POINTS}")
    if np.any(np.abs(points - 0.5) > 0.5 + EM_REACH):
        raise GlyphError("Stroke", f"points: a point lies more than {EM_REACH:g} em outside the em box")
    length = float(np.sum(np.hypot(*np.diff(points, axis=0).T)))
    if length > MAX_STROKE_EM:
        raise GlyphError("Stroke", f"points: the centreline is {length:.3g} em long, more than {MAX_STROKE_EM:g}")


def check_number(where: str, name: str, v) -> None:
    """One coordinate of a file: a finite number within MAX_COORD; GlyphError otherwise."""
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise GlyphError(where, f"{name}: {v!r:.20} is not a number")
    if v != v:
        raise GlyphError(where, f"{name}: NaN")
    if not -MAX_COORD <= v <= MAX_COORD:
        raise GlyphError(where, f"{name}: {v:.3g} is beyond the limit of +-{MAX_COORD:g}")


def check_points(where: str, name: str, value) -> np.ndarray:
    """A JSON polyline [[x, y], ...] -> (k, 2) float64; GlyphError(where, "name[i]: problem") at the
    first bad point, or when fewer than 2 distinct points remain (an empty stroke)."""
    if not isinstance(value, (list, tuple)):
        raise GlyphError(where, f"{name}: expected a list of [x, y] points, got {type(value).__name__}")
    if len(value) > MAX_POINTS:
        raise GlyphError(where, f"{name}: {len(value)} points, more than {MAX_POINTS}")
    for i, pt in enumerate(value):
        if not isinstance(pt, (list, tuple)) or len(pt) != 2:
            raise GlyphError(where, f"{name}[{i}]: expected [x, y], got {pt!r:.40}")
        for v in pt:
            check_number(where, f"{name}[{i}]", v)
    p = np.array(value, dtype=np.float64).reshape(-1, 2)
    if len(p) < 2 or not np.any(np.diff(p, axis=0) != 0):
        raise GlyphError(where, f"{name}: empty stroke ({len(p)} points, fewer than 2 distinct)")
    return p
