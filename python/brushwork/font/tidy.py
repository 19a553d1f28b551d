"""An outline made tidy for a type designer's tools: the extremes of every curve on-curve (a
curve split at an x or y extreme inside it that bulges past its ends by more than EXTREME_UNITS,
the handles of a smaller bulge pulled back within the ends' span where that moves the curve by
at most CLAMP_UNITS, else the curve split there too once it bulges past ROUND_UNITS), and no
degenerate segment (one whose points all lie within MIN_SEGMENT of where it starts, a line
closing a contour onto its first point, which closePath draws, or a hair: two segments out and
back, or a whole contour, enclosing no ink), and no speck (a contour under SPECK_UNITS2)."""
from __future__ import annotations

import numpy as np

MIN_SEGMENT = 1.0       # font units: a segment whose points all lie this close to its start is dropped
EXTREME_UNITS = 1.0     # font units: a curve bulging past its ends by more than this is split at the extreme
ROUND_UNITS = 0.25      # font units: ... or by more than this where its handles cannot be pulled in
SPECK_UNITS2 = 16.0     # square units: a contour enclosing less (a speck of 2 x 2 px at 512 px) is dropped
FLAT_UNITS = 0.5        # font units: a curve whose handles lie this close to its chord is drawn as a line
SPIKE_WIDTH = 1.0       # font units: an out-and-back pair of segments enclosing less width than this is dropped
REJOIN_UNITS = 0.05     # font units: how far two parts may lie from the parts of the cubic they join into
EDGE_T = 0.02           # extremes this near a curve's ends (in its parameter) count as at the ends
CLAMP_UNITS = 2.0       # font units: the most pulling a curve's handles within its ends' span may move it
_CLAMP_T = np.linspace(0.0, 1.0, 17)     # the parameters at which a clamped curve is checked against the curve
CLAMP_WEIGHTS = np.stack([3 * (1 - _CLAMP_T) ** 2 * _CLAMP_T, 3 * (1 - _CLAMP_T) * _CLAMP_T ** 2], axis=1)  # (17, 2)


def _extreme_ts(c: np.ndarray, axis: int) -> list:
    """Parameters in (EDGE_T, 1 - EDGE_T) where the cubic c (4, 2) turns along axis: the roots
    of its derivative's quadratic a t^2 + b t + k."""
    p0, p1, p2, p3 = c[:, axis]
    a, b, k = -p0 + 3 * p1 - 3 * p2 + p3, 2 * (p0 - 2 * p1 + p2), p1 - p0
    if abs(a) < 1e-12:
        roots = [-k / b] if abs(b) > 1e-12 else []
    else:
        disc = b * b - 4 * a * k
        roots = [] if disc < 0 else [(-b + s * np.sqrt(disc)) / (2 * a) for s in (1.0, -1.0)]
    return sorted(float(t) for t in roots if EDGE_T < t < 1 - EDGE_T)


def _point(c: np.ndarray, t: float) -> np.ndarray:
    s = 1.0 - t
    return s ** 3 * c[0] + 3 * s * s * t * c[1] + 3 * s * t * t * c[2] + t ** 3 * c[3]


def _split(c: np.ndarray, t: float) -> tuple:
    """The cubic c cut at t into two (de Casteljau)."""
    a, b, d = c[:3] + t * (c[1:] - c[:3])
    e, f = a + t * (b - a), b + t * (d - b)
    g = e + t * (f - e)
    return np.array([c[0], a, e, g]), np.array([g, f, d, c[3]])


def _clamp(c: np.ndarray, axis: int) -> np.ndarray:
    """c with its handles' coordinates along axis pulled within its ends' span."""
    lo, hi = sorted((c[0, axis], c[3, axis]))
    out = c.copy()
    out[1:3, axis] = np.clip(out[1:3, axis], lo, hi)
    return out


def _joined(a: np.ndarray, b: np.ndarray) -> np.ndarray | None:
    """The cubic that a and b (each (4, 2), b starting where a ends) are the two parts of, cut at
    some t (as skia-pathops cuts curves into monotone pieces), or None when they are not: the
    cubic the handles' lengths imply, cut again at that t, must give a and b back within
    REJOIN_UNITS."""
    ha, hb = np.linalg.norm(a[3] - a[2]), np.linalg.norm(b[1] - b[0])
    if ha < 1e-9 or hb < 1e-9:
        return None
    t = ha / (ha + hb)
    c = np.array([a[0], a[0] + (a[1] - a[0]) / t, b[3] + (b[2] - b[3]) / (1 - t), b[3]])
    first, second = _split(c, t)
    close = max(np.abs(first - a).max(), np.abs(second - b).max()) <= REJOIN_UNITS
    return c if close else None


def rejoin(curves: list) -> list:
    """The cubics of a contour, in order, with neighbours that are parts of one cubic joined."""
    out: list = []
    for c in curves:
        whole = _joined(out[-1], c) if out else None
        if whole is None:
            out.append(c)
        else:
            out[-1] = whole
    return out


def on_curve_extremes(c: np.ndarray) -> list:
    """The cubic c (4, 2) as cubics whose x and y extremes lie at their ends: split at an extreme
    bulging past its ends by more than EXTREME_UNITS, or by more than ROUND_UNITS where pulling
    its handles in would move the curve too far (_clamped keeps it as it is)."""
    for axis in (0, 1):
        for t in _extreme_ts(c, axis):
            bulge = _point(c, t)[axis]
            lo, hi = sorted((c[0, axis], c[3, axis]))
            over = max(lo - bulge, bulge - hi)
            if over > EXTREME_UNITS or (over > ROUND_UNITS and _clamped(c, axis) is c):
                first, second = _split(c, t)
                first[3, axis] = second[0, axis] = bulge
                # the handles either side of the new point lie level with it: the extreme
                first[2, axis] = second[1, axis] = bulge
                return on_curve_extremes(first) + on_curve_extremes(second)
        c = _clamped(c, axis)
    return [c]


def _clamped(c: np.ndarray, axis: int) -> np.ndarray:
    """c with its handles pulled within its ends' span along axis (_clamp), where that moves no
    point of the curve by more than CLAMP_UNITS; else c as it is (a long handle past an end, as
    a rejoined S-shaped curve can have, pulled in would drag the curve off the ink)."""
    out = _clamp(c, axis)
    # only the handles moved, along axis: the curve moves by their Bernstein weights' share
    moved = np.abs(CLAMP_WEIGHTS @ (out[1:3, axis] - c[1:3, axis])).max()
    return out if moved <= CLAMP_UNITS else c


def _contours(rec) -> list:
    """The contours of a RecordingPen as [start point, [(op, points as (k, 2) arrays)], closing op]."""
    out: list = []
    for op, args in rec.value:
        if op == "moveTo":
            out.append([np.array(args[0], dtype=float), [], None])
        elif op in ("lineTo", "curveTo"):
            out[-1][1].append((op, np.array(args, dtype=float)))
        elif op in ("closePath", "endPath"):
            out[-1][2] = op
    return out


def _drawn(seg: np.ndarray) -> np.ndarray:
    """Points along a segment ((2, 2) line or (4, 2) cubic, its start first)."""
    return seg if len(seg) == 2 else np.array([_point(seg, t) for t in np.linspace(0.0, 1.0, 9)])


def _hair(segs: list, speck: float = 0.0) -> bool:
    """Whether the closed run of segments segs (each (k, 2) from its start) encloses less than
    SPIKE_WIDTH units of width (its area under SPIKE_WIDTH times half its length: no ink), or
    less than `speck` square units."""
    p = np.concatenate([_drawn(seg) for seg in segs])
    area = 0.5 * abs(float(np.dot(p[:, 0], np.roll(p[:, 1], -1)) - np.dot(np.roll(p[:, 0], -1), p[:, 1])))
    length = float(np.sum(np.linalg.norm(np.diff(np.concatenate([p, p[:1]]), axis=0), axis=1)))
    return area < max(SPIKE_WIDTH * length / 2, speck)


def _spike(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether segment a, then b, go out and come back (b ending within MIN_SEGMENT of a's start)
    as a hair."""
    return np.abs(b[-1] - a[0]).max() < MIN_SEGMENT and _hair([a, b])


def _drop_spikes(segs: list) -> list:
    """segs [(op, points from its start)] without the out-and-back pairs _spike finds, the
    segment after one starting where the pair did."""
    out: list = []
    begin = None            # where a dropped pair started: the next segment starts there
    for op, pts in segs:
        if begin is not None:
            pts, begin = np.concatenate([[begin], pts[1:]]), None
        if out and _spike(out[-1][1], pts):
            begin = out.pop()[1][0]
            continue
        out.append((op, pts))
    return out


def _segments(start: np.ndarray, segments: list) -> list:
    """The contour's segments as ("curveTo", (4, 2)) and ("lineTo", (2, 2)) arrays from their
    start points, the degenerate ones dropped, curves rejoined, their extremes put on-curve and the
    flat ones straightened."""
    out: list = []
    here = start
    for op, pts in segments:
        if np.abs(pts - here).max() < MIN_SEGMENT:
            continue
        out.append((op, np.concatenate([[here], pts])))
        here = pts[-1]
    if out and out[-1][0] == "lineTo" and np.abs(out[-1][1][1] - start).max() < MIN_SEGMENT:
        out.pop()          # closePath draws the line back to the start
    joined = _rejoined(_drop_spikes(out))
    out = _merge_lines([_straightened(op, c) for op, pts in joined
                        for c in (on_curve_extremes(pts) if op == "curveTo" else [pts])])
    if len(out) > 1 and out[-1][0] == "lineTo" and np.abs(out[-1][1][-1] - start).max() < MIN_SEGMENT:
        out.pop()          # a straightened line back to the start: closePath draws it
    return out


def _rejoined(segs: list) -> list:
    """segs [(op, points from its start)] with neighbouring curves that are parts of one cubic joined."""
    joined: list = []
    for op, pts in segs:
        if op == "curveTo" and joined and joined[-1][0] == "curveTo":
            whole = _joined(joined[-1][1], pts)
            if whole is not None:
                joined[-1] = ("curveTo", whole)
                continue
        joined.append((op, pts))
    return joined


def _merge_lines(segs: list) -> list:
    """segs with each run of lines that goes on in one direction (the point between two of them
    within FLAT_UNITS of the line joining their far ends, and between them) drawn as one line."""
    out: list = []
    for op, pts in segs:
        if op == "lineTo" and out and out[-1][0] == "lineTo":
            a, b = out[-1][1][0], pts[-1]
            chord = b - a
            length = float(np.hypot(*chord))
            mid = out[-1][1][-1] - a
            if length > 0 and abs(mid @ np.array([-chord[1], chord[0]])) / length <= FLAT_UNITS \
                    and 0.0 < mid @ chord / length < length:
                out[-1] = ("lineTo", np.array([a, b]))
                continue
        out.append((op, pts))
    return out


def _straightened(op: str, pts: np.ndarray) -> tuple:
    """(op, points) as given, or a curve whose handles lie within FLAT_UNITS of its chord and
    between its ends as the line it draws (one point stored where the curve took three)."""
    if op != "curveTo":
        return op, pts
    chord = pts[3] - pts[0]
    length = float(np.hypot(*chord))
    if length < MIN_SEGMENT:
        return op, pts
    rel = pts[1:3] - pts[0]
    across = np.abs(rel @ np.array([-chord[1], chord[0]])) / length
    along = rel @ chord / length
    if across.max() <= FLAT_UNITS and along.min() >= 0.0 and along.max() <= length:
        return "lineTo", pts[[0, 3]]
    return op, pts


def tidy(rec):
    """The RecordingPen rec (moveTo, lineTo, curveTo, closePath) with the parts of one curve that
    skia-pathops cut apart joined again, each curve's extremes on-curve and the degenerate
    segments dropped, as a new RecordingPen."""
    from fontTools.pens.recordingPen import RecordingPen

    out = RecordingPen()
    for start, segments, close in _contours(rec):
        kept = _segments(start, segments)
        if not kept or _hair([pts for _, pts in kept], SPECK_UNITS2):
            continue
        out.moveTo(tuple(start.tolist()))
        for op, pts in kept:
            getattr(out, op)(*map(tuple, pts[1:].tolist()))
        out.closePath() if close == "closePath" else out.endPath()
    return out
