"""What the driver aims a stroke at: its centreline resampled, headings, the target width along
it (the style's width profile, pressed corners, broader verticals), and what the footprint shows.
"""
from __future__ import annotations

import math

import numpy as np

from .. import _core
from .plan import lowpass, smooth_polyline
from .style import Style, family

# The heading the brush is turned by: the centreline's, smoothed over HEADING_SIGMA_MM of arc
# (Gaussian sigma), corners included, and HEADING_LAG_MM behind it. The root stands about a tuft
# length ahead of the footprint on the heading, so a heading that steps at a vertex of a coarse
# median swings the root a few mm within one frame (9 mm x 20 deg = 3 mm) and the tuft, dragged
# round, leaves a lump in the edge; turned late, the brush carries on past a corner before it
# swings round, and the shoulder of a 折 is filled rather than cut
HEADING_SIGMA_MM = 2.0
HEADING_LAG_MM = 2.0


def _resample(points: np.ndarray, step: float) -> tuple[np.ndarray, np.ndarray]:
    """(n, 2) points every `step` mm along the polyline and their arc lengths (n,) mm."""
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    n = max(2, int(math.ceil(s[-1] / step)) + 1)
    ss = np.linspace(0.0, s[-1], n)
    return np.stack([np.interp(ss, s, points[:, 0]), np.interp(ss, s, points[:, 1])], axis=1), ss


def _corners(path: np.ndarray, min_turn_deg: float = 55.0) -> np.ndarray:
    """(n,) in [0, 1]: how close each point is to a sharp turn of the centreline (1 at it)."""
    n = len(path)
    out = np.zeros(n)
    if n < 5:
        return out
    d = np.diff(path, axis=0)
    ang = np.arctan2(d[:, 1], d[:, 0])
    for i in range(2, n - 2):
        turn = abs(math.degrees(math.remainder(ang[i + 1] - ang[i - 2], 2 * math.pi)))
        if turn >= min_turn_deg:
            out[max(0, i - 2):i + 3] = np.maximum(out[max(0, i - 2):i + 3], [0.4, 0.8, 1.0, 0.8, 0.4][:min(5, n - max(0, i - 2))])
    return out


def loop_area(loop: np.ndarray) -> float:
    """Signed area (shoelace) of a closed polygon (k, 2): > 0 counter-clockwise."""
    x, y = loop[:, 0], loop[:, 1]
    return 0.5 * float(x[:-1] @ y[1:] - y[:-1] @ x[1:] + x[-1] * y[0] - y[-1] * x[0])


def footprint_area(loops) -> float:
    """mm2 of the footprint polygons (Brush.footprint: outer loops counter-clockwise, holes
    clockwise), from the loops in hand (Brush.footprint_area() would find them again)."""
    return sum(loop_area(np.asarray(lp)[:, :2]) for lp in loops if len(lp) >= 3)


def _centroid_and_width(loops, heading: float) -> tuple[np.ndarray, float, float, float] | None:
    """Area centroid (mm) of the footprint polygons, their width across `heading` (mm), and how
    far they reach behind and ahead of the centroid along `heading` (mm); None without a
    footprint. (In the core: read every frame, it took 86 us in numpy, 1-2 us there. A sliver
    whose outer loop and hole nearly cancel has its area centroid anywhere: one 200 mm from a
    100 mm em box threw the root there and swept a band across 蒙; such a centroid, outside the
    points' bounds, is replaced by their mean.)"""
    if not loops:
        return None
    return _core.footprint_span(loops, float(heading))


def _heading(path: np.ndarray, step_mm: float) -> np.ndarray:
    """(n,) rad: the heading along `path` ((n, 2) mm, points step_mm apart), smoothed over
    HEADING_SIGMA_MM and HEADING_LAG_MM behind it (the first heading held meanwhile)."""
    d = np.gradient(path, axis=0)
    heading = lowpass(np.unwrap(np.arctan2(d[:, 1], d[:, 0])), HEADING_SIGMA_MM / step_mm)
    lag = min(int(round(HEADING_LAG_MM / step_mm)), len(heading) - 1)
    return np.r_[np.full(lag, heading[0]), heading[:len(heading) - lag]]


def centreline(style: Style, points_mm: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The stroke's centreline `points_mm` ((k, 2) mm) as a curve that turns smoothly between its
    corners (smooth_polyline), resampled every `step_mm`: path (n, 2) mm, arc length s (n,) mm and
    the heading the brush is turned by (n,) rad (_heading)."""
    path, s = _resample(smooth_polyline(np.asarray(points_mm, dtype=float)), style.step_mm)
    return path, s, _heading(path, style.step_mm)


def stroke_targets(style: Style, points_mm: np.ndarray, kind: str, w_nom: float,
                   line: tuple | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """What the driver aims a stroke at: its centreline `points_mm` ((k, 2) mm) -> path (n, 2) mm,
    arc length s (n,) mm, heading (n,) rad (centreline; `line`, when given, is it already), and
    the target footprint width (n,) mm: `w_nom` (mm) times the family's profile over s / length,
    pressed at corners (折) and, for plain strokes and hooks, broader when vertical."""
    path, s, heading = centreline(style, points_mm) if line is None else line
    prof = np.asarray(style.profiles[family(kind)], dtype=float)
    width = w_nom * np.interp(s / max(s[-1], 1e-6), prof[:, 0], prof[:, 1])
    width *= 1.0 + (style.corner_press - 1.0) * _corners(path)
    if family(kind) in ("plain", "hook"):
        width *= 1.0 + style.direction_gain * (2.0 * np.abs(np.sin(heading)) - 1.0)
    return path, s, heading, width


def joins(medians: list, k: int, near_mm: float) -> tuple[bool, bool]:
    """Whether stroke k's start and end lie on another stroke: within `near_mm` of another
    centreline of `medians` (a list of (m, 2) mm polylines), as where a stroke hangs from a
    crossbar or closes a box, the font's outlines touching there."""
    others = [m for i, m in enumerate(medians) if i != k]
    return tuple(any(_distance_to_polyline(p, m) < near_mm for m in others) for p in (medians[k][0], medians[k][-1]))


def _distance_to_polyline(p: np.ndarray, line: np.ndarray) -> float:
    """mm from the point p (2,) to the polyline `line` (m, 2) mm."""
    if len(line) == 1:
        return float(np.hypot(*(p - line[0])))
    a, b = line[:-1], line[1:]
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-12), 0.0, 1.0)
    return float(np.min(np.hypot(*(a + t[:, None] * ab - p).T)))
