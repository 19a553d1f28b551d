"""Where a fitted stroke's ink misses its outline, by region of the stroke (`brushwork fit --regions`).

Every pixel of a stroke's ink or outline goes to the point of its median (extended straight past
its ends) it lies nearest, and so to a region: the hook (from a hook family's last corner on), a
corner (within CORNER_MM of arc of a turn of more than CORNER_DEG within +-CORNER_MM), the head
(the first HEAD_FRACTION of the arc and before it), the end (the last HEAD_FRACTION and past it)
or the body. A region's tally: outline px, missed px (outline without ink), outside px (ink
without outline); missed + outside over the regions is the stroke's union less its intersection,
what its IoU loses.
"""
from __future__ import annotations

import numpy as np

from .plan import CORNER_MM, Median, corners_mm
from .style import family

REGIONS = ("head", "body", "corner", "hook", "end")
HEAD_FRACTION = 0.15
STEP_MM = 0.25          # spacing of the median's points pixels are projected on


def region_of(median: Median, kind: str, u: np.ndarray) -> np.ndarray:
    """(len(u),) index into REGIONS of the arc lengths u (mm) of `median`, a stroke of `kind`."""
    length = max(median.length, 1e-9)
    out = np.where(u < HEAD_FRACTION * length, 0, np.where(u > (1.0 - HEAD_FRACTION) * length, 4, 1))
    corners = corners_mm(median)
    if len(corners):
        near = np.min(np.abs(u[:, None] - corners[None, :]), axis=1) <= CORNER_MM
        out = np.where(near, 2, out)
        if family(kind) == "hook":
            out = np.where(u >= corners[-1] - CORNER_MM, 3, out)
    return out


def stroke_tally(ink: np.ndarray, mask: np.ndarray, median: Median, kind: str, ppm: float,
                 em_mm: float) -> np.ndarray:
    """(len(REGIONS), 3) int: outline, missed and outside px of a stroke's ink against its
    outline ((size, size) bool masks, row 0 at the top; the median in mm, y up; ppm px a mm)."""
    ys, xs = np.nonzero(ink | mask)
    out = np.zeros((len(REGIONS), 3), np.int64)
    if len(xs) == 0:
        return out
    reach = 0.5 * ink.shape[0] / ppm
    u = np.arange(-reach, median.length + reach, STEP_MM)
    pts = median.at(u)
    q = np.stack([(xs + 0.5) / ppm, em_mm - (ys + 0.5) / ppm], axis=1)
    near = np.empty(len(q), np.int64)
    for lo in range(0, len(q), 2048):
        d = ((q[lo:lo + 2048, None, :] - pts[None, :, :]) ** 2).sum(axis=2)
        near[lo:lo + 2048] = d.argmin(axis=1)
    reg = region_of(median, kind, u[near])
    r, i = mask[ys, xs], ink[ys, xs]
    for k in range(len(REGIONS)):
        sel = reg == k
        out[k] = ((r & sel).sum(), (r & ~i & sel).sum(), (i & ~r & sel).sum())
    return out


def add_tally(total: dict, fam: str, tally: np.ndarray) -> None:
    """Adds a tally to total[fam] (made when missing)."""
    total[fam] = total.get(fam, np.zeros((len(REGIONS), 3), np.int64)) + tally


def table(total: dict) -> list[str]:
    """Lines: for each family and region with outline or ink, its share of all the error (missed
    + outside px), and its missed and outside px as percentages of its outline px."""
    err = sum(int(t[:, 1:].sum()) for t in total.values())
    lines = [f"{'family':8} {'region':7} {'outline px':>10} {'error share':>11} {'missed %':>8} {'outside %':>9}"]
    for fam in sorted(total):
        for k, name in enumerate(REGIONS):
            ref, miss, extra = (int(v) for v in total[fam][k])
            if ref + miss + extra == 0:
                continue
            lines.append(f"{fam:8} {name:7} {ref:10d} {100.0 * (miss + extra) / max(err, 1):10.1f}% "
                         f"{100.0 * miss / max(ref, 1):8.1f} {100.0 * extra / max(ref, 1):9.1f}")
    by_region = np.sum([t for t in total.values()], axis=0) if total else np.zeros((len(REGIONS), 3))
    lines.append("all      " + "  ".join(f"{name} {100.0 * by_region[k, 1:].sum() / max(err, 1):.1f}%"
                                         for k, name in enumerate(REGIONS)))
    return lines
