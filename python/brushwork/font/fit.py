"""Cubic Bezier curves through a closed polyline within a tolerance: the contour is cut at its
corners and its x and y extremes (the points a type designer puts on-curve), and each piece between two corners is fitted by least squares with its end tangents
fixed, split where it strays most and fitted again until it lies within the tolerance (the
scheme of P. J. Schneider, "An algorithm for automatically fitting digitized curves", Graphics
Gems, 1990). A piece's error is measured as an area: the mean distance of its points from the
curve (the area between the two over the piece's length) must be at most the tolerance, and no
point may stray more than MAX_RATIO tolerances. The grain of the ink's edge (pixel-sized bumps)
thus costs no curves of its own, while a bulge the width of a stroke still does.
A curve is a (4, 2) array of control points P0, P1, P2, P3."""
from __future__ import annotations

import numpy as np

CORNER_DEG = 55.0      # a turn sharper than this over CORNER_REACH is a corner
CORNER_REACH = 1.5     # contour units each side of a point over which its turn is measured
NEWTON_STEPS = 4       # reparametrisations tried before a piece is split
MAX_RATIO = 4.0        # the farthest any point may lie from its curve, in tolerances
LOOP_RATIO = 1.25      # a curve longer than this many times its piece of edge (plus LOOP_SLACK) loops or overshoots
LOOP_SLACK = 0.5       # contour units
EXTREME_PX = 0.5       # how far an extreme must stand out (px) ...
EXTREME_REACH_PX = 10.0  # ... beyond the points this far either side along the contour to be cut at
LOOP_U = np.linspace(0.0, 1.0, 33)   # the parameters at which a curve's length is measured


def _unit(v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return v / np.maximum(n, 1e-12)


def _bezier(c: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Points (n, 2) of the cubic c (4, 2) at parameters u (n,)."""
    s = 1.0 - u
    return np.stack([s * s * s, 3 * s * s * u, 3 * s * u * u, u * u * u], axis=1) @ c


def _chord_params(p: np.ndarray) -> np.ndarray:
    """Chord-length parameters in [0, 1] of the points p (n, 2)."""
    d = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])
    return d / d[-1] if d[-1] > 0 else np.linspace(0.0, 1.0, len(p))


def _least_squares(p: np.ndarray, u: np.ndarray, t0: np.ndarray, t1: np.ndarray) -> np.ndarray:
    """The cubic from p[0] to p[-1] leaving along t0 and arriving against t1 (both unit, t1
    pointing back into the curve) whose handle lengths a0, a1 fit p at u best in least squares:
    the 2 x 2 normal equations of Schneider's fit, solved by Cramer's rule."""
    s = 1.0 - u
    b1, b2 = 3 * s * s * u, 3 * s * u * u
    rest = p - np.outer(s * s * s + b1, p[0]) - np.outer(b2 + u * u * u, p[-1])
    m00, m11 = float(b1 @ b1), float(b2 @ b2)
    m01 = float(b1 @ b2) * float(t0 @ t1)
    r0, r1 = float(b1 @ (rest @ t0)), float(b2 @ (rest @ t1))
    chord = float(np.hypot(*(p[-1] - p[0])))
    det = m00 * m11 - m01 * m01
    a0, a1 = ((r0 * m11 - r1 * m01) / det, (m00 * r1 - m01 * r0) / det) if abs(det) > 1e-12 else (0.0, 0.0)
    # a handle that is negative or vanishing bends the curve back on itself: a third of the chord instead
    if a0 < 1e-6 * chord or a1 < 1e-6 * chord:
        a0 = a1 = chord / 3.0
    return np.array([p[0], p[0] + a0 * t0, p[-1] + a1 * t1, p[-1]])


def _newton(c: np.ndarray, p: np.ndarray, u: np.ndarray) -> np.ndarray:
    """One Newton-Raphson step on each u towards the parameter of the curve point nearest p."""
    s = 1.0 - u
    d1 = np.stack([s * s, 2 * s * u, u * u], axis=1) @ (3 * np.diff(c, axis=0))
    d2 = np.stack([s, u], axis=1) @ (6 * np.diff(c, n=2, axis=0))
    e = _bezier(c, u) - p
    num = np.sum(e * d1, axis=1)
    den = np.sum(d1 * d1, axis=1) + np.sum(e * d2, axis=1)
    step = np.where(np.abs(den) > 1e-12, num / np.where(den == 0, 1, den), 0.0)
    out = np.clip(u - step, 0.0, 1.0)
    out[0], out[-1] = 0.0, 1.0
    return np.maximum.accumulate(out)


def _worst(c: np.ndarray, p: np.ndarray, u: np.ndarray, tol: float) -> tuple:
    """(error of the curve c through p at parameters u in tolerances, index of the farthest
    point): the larger of the mean distance over tol and the largest over MAX_RATIO * tol, so
    that the piece fits when the error is at most 1; infinite when the curve loops."""
    d = np.linalg.norm(_bezier(c, u) - p, axis=1)
    i = int(np.argmax(d))
    err = max(float(np.mean(d)), float(d[i]) / MAX_RATIO) / tol
    # a loop between two points' parameters escapes their distances: the curve's length shows it
    if err <= 1.0 and _length(_bezier(c, LOOP_U)) > LOOP_RATIO * _length(p) + LOOP_SLACK:
        return np.inf, i
    return err, i


def _length(p: np.ndarray) -> float:
    """Length of the open polyline p (n, 2)."""
    return float(np.sum(np.linalg.norm(np.diff(p, axis=0), axis=1)))


def fit_one(p: np.ndarray, t0: np.ndarray, t1: np.ndarray, tol: float, steps: int = NEWTON_STEPS) -> tuple:
    """(the cubic through p (n, 2) with end tangents t0, t1 (as fit_open takes them), its error in
    tolerances as _worst measures it, the index of its farthest point): Schneider's least squares
    with up to `steps` reparametrisations while they may still bring the error under 1."""
    if len(p) <= 2:
        d = float(np.linalg.norm(p[-1] - p[0])) / 3.0
        return np.array([p[0], p[0] + d * t0, p[-1] + d * t1, p[-1]]), 0.0, 0
    u = _chord_params(p)
    c = _least_squares(p, u, t0, t1)
    err, i = _worst(c, p, u, tol)
    for _ in range(steps if err <= 4.0 else 0):
        if err <= 1.0:
            break
        u = _newton(c, p, u)
        c = _least_squares(p, u, t0, t1)
        err, i = _worst(c, p, u, tol)
    return c, err, i


def _split_tangent(p: np.ndarray, i: int, reach: int) -> np.ndarray:
    """The unit tangent at p[i] pointing back along p, from the chord between the points `reach`
    either side (fewer near the ends)."""
    k = max(1, min(reach, i, len(p) - 1 - i))
    return _unit(p[i - k] - p[i + k])


def _fit_split(p: np.ndarray, t0: np.ndarray, t1: np.ndarray, tol: float, reach: int) -> list:
    """[(first index, last index, cubic)] through p: one cubic when it fits, else split at the
    farthest point and each side fitted in turn."""
    c, err, i = fit_one(p, t0, t1, tol)
    if err <= 1.0:
        return [(0, len(p) - 1, c)]
    i = min(max(i, 1), len(p) - 2)
    mid = _split_tangent(p, i, reach)
    right = _fit_split(p[i:], -mid, t1, tol, reach)
    return _fit_split(p[:i + 1], t0, mid, tol, reach) + [(a + i, b + i, c) for a, b, c in right]


def _merge(p: np.ndarray, pieces: list, tol: float) -> list:
    """The pieces [(first, last, cubic)] with neighbours joined wherever one cubic from the first's
    start tangent to the second's end tangent fits both their points: the greedy splits leave
    joints a single curve would have spanned."""
    k = 0
    while k < len(pieces) - 1:
        (a, _, c0), (_, b, c1) = pieces[k], pieces[k + 1]
        t0, t1 = _unit(c0[1] - c0[0]), _unit(c1[2] - c1[3])
        c, err, _ = fit_one(p[a:b + 1], t0, t1, tol)
        if err <= 1.0 and np.linalg.norm(c0[1] - c0[0]) > 0 and np.linalg.norm(c1[2] - c1[3]) > 0:
            pieces[k:k + 2] = [(a, b, c)]
            k = max(k - 1, 0)
        else:
            k += 1
    return pieces


def fit_open(p: np.ndarray, t0: np.ndarray, t1: np.ndarray, tol: float, reach: int = 1) -> list:
    """Cubics (each (4, 2)) joined end to end through the points p (n, 2) from p[0] to p[-1],
    each curve's points on average within tol of it at their parameters, none farther than
    MAX_RATIO * tol; t0 the unit tangent at the start, t1 at the end pointing back into the curve;
    the tangents at the joints from the chord over `reach` points either side."""
    return [c for _, _, c in _merge(p, _fit_split(p, t0, t1, tol, reach), tol)]


def _turns(p: np.ndarray, reach: int) -> np.ndarray:
    """(n,) the angle in degrees the closed polyline p turns through over `reach` points each side."""
    back = _unit(p - np.roll(p, reach, axis=0))
    ahead = _unit(np.roll(p, -reach, axis=0) - p)
    return np.degrees(np.arccos(np.clip(np.sum(back * ahead, axis=1), -1.0, 1.0)))


def corners(p: np.ndarray, spacing: float) -> np.ndarray:
    """Indices of the corners of the closed polyline p (n, 2) whose points lie about `spacing`
    apart: local maxima of the turn that exceed CORNER_DEG, at least `reach` points apart."""
    reach = max(2, int(round(CORNER_REACH / max(spacing, 1e-9))))
    if len(p) < 4 * reach:
        return np.zeros(0, dtype=int)
    turn = _turns(p, reach)
    peak = np.ones(len(p), dtype=bool)
    for k in range(1, reach + 1):
        peak &= (turn >= np.roll(turn, k)) & (turn > np.roll(turn, -k))
    return np.flatnonzero(peak & (turn > CORNER_DEG))


def _end_tangent(p: np.ndarray, reach: int) -> np.ndarray:
    """The unit tangent at p[0] leaving along p, from the chord to a point `reach` ahead."""
    return _unit(p[min(reach, len(p) - 1)] - p[0])


def extremes(p: np.ndarray, spacing: float) -> list:
    """[(index, axis)] of the closed polyline p's (points about `spacing` apart) extremes along x
    (axis 0) and y (axis 1): points beyond every other within EXTREME_REACH_PX along the contour
    either side, and by more than EXTREME_PX beyond the points that far (not a ripple)."""
    reach = max(2, int(round(CORNER_REACH / max(spacing, 1e-9))))
    far = max(reach + 1, int(round(EXTREME_REACH_PX / max(spacing, 1e-9))))
    out = []
    for axis in (0, 1):
        for w in (p[:, axis], -p[:, axis]):
            top = np.ones(len(p), dtype=bool)
            for k in range(1, far + 1):
                top &= (w >= np.roll(w, k)) & (w > np.roll(w, -k))
            top &= w - np.maximum(np.roll(w, far), np.roll(w, -far)) > EXTREME_PX
            out += [(int(i), axis) for i in np.flatnonzero(top)]
    return out


def _cuts(p: np.ndarray, spacing: float, reach: int) -> dict:
    """{index: None at a corner, the axis at an extreme}: where fit_closed cuts p, extremes
    within `reach` points of a cut already made left out."""
    cuts: dict = {int(i): None for i in corners(p, spacing)}
    for i, axis in extremes(p, spacing):
        if all(min(abs(i - c), len(p) - abs(i - c)) > reach for c in cuts):
            cuts[i] = axis
    return cuts


def _cut_tangent(piece: np.ndarray, axis, reach: int) -> np.ndarray:
    """The unit tangent leaving piece[0] along the piece: the chord to a point `reach` ahead, or at
    an extreme along `axis` the direction across that axis the chord leans to."""
    t = _end_tangent(piece, reach)
    if axis is None:
        return t
    out = np.zeros(2)
    out[1 - axis] = 1.0 if t[1 - axis] >= 0 else -1.0
    return out


def fit_closed(p: np.ndarray, tol: float, spacing: float) -> list:
    """Cubics (each (4, 2)) around the closed polyline p (n, 2) (points about `spacing` apart,
    the last not repeating the first), starting and ending at one point, cut at its corners and
    its x and y extremes (there level or plumb), each piece fitted within tol (as fit_open
    measures it); sharp at the corners, smooth elsewhere."""
    reach = max(2, int(round(CORNER_REACH / max(spacing, 1e-9))))
    cuts = _cuts(p, spacing, reach)
    if not cuts:
        # no corner nor extreme: start anywhere and make the start as smooth as the rest
        t = _unit(p[min(reach, len(p) - 1)] - p[-min(reach, len(p) - 1)])
        ring = np.concatenate([p, p[:1]])
        return fit_open(ring, t, -t, tol, reach)
    at = sorted(cuts)
    ring = np.roll(p, -at[0], axis=0)
    ring = np.concatenate([ring, ring[:1]])
    ends = [c - at[0] for c in at] + [len(p)]
    kinds = [cuts[c] for c in at] + [cuts[at[0]]]
    out = []
    for a, b, ka, kb in zip(ends[:-1], ends[1:], kinds[:-1], kinds[1:]):
        piece = ring[a:b + 1]
        out += fit_open(piece, _cut_tangent(piece, ka, reach), _cut_tangent(piece[::-1], kb, reach), tol, reach)
    return out
