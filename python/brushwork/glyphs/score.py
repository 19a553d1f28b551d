"""Scoring a rendered glyph against its source's filled stroke outlines (Make Me a Hanzi keeps them).

The reference mask is drawn the way the source's SVG recipe draws the outlines: the em box fills
the image, so ink and outlines compare pixel for pixel. Filling goes through OpenCV. A bead at a
stroke's end is measured here too, from the footprint's widths (the driver tallies it per family).
"""
from __future__ import annotations

import math

import cv2
import numpy as np

from .model import Glyph, GlyphError
from .svgpath import parse_svg_path

_SHIFT = 4  # cv2.fillPoly fixed-point bits: vertices placed to 1/16 px


def has_outlines(glyph: Glyph) -> bool:
    """True when every stroke carries its filled outline (needed by `outline_mask`)."""
    return bool(glyph.strokes) and all(s.outline is not None for s in glyph.strokes)


def stroke_masks(glyph: Glyph, size: int) -> list[np.ndarray]:
    """One (size, size) bool mask per stroke, row 0 at the top: its filled outline, the em box
    mapped onto the whole image."""
    if not has_outlines(glyph):
        raise GlyphError(glyph.source or glyph.char, "no stroke outlines to score against "
                         "(only Make Me a Hanzi keeps them)")
    masks = []
    for stroke in glyph.strokes:
        mask = np.zeros((size, size), np.uint8)
        polys = []
        for poly in parse_svg_path(stroke.outline):
            uv = glyph.to_em(poly)                                    # (k, 2) em, y up
            px = np.stack([uv[:, 0] * size, (1.0 - uv[:, 1]) * size], axis=1)
            polys.append(np.round(px * (1 << _SHIFT)).astype(np.int32))
        cv2.fillPoly(mask, polys, 1, lineType=cv2.LINE_8, shift=_SHIFT)
        masks.append(mask.astype(bool))
    return masks


def outline_mask(glyph: Glyph, size: int) -> np.ndarray:
    """(size, size) bool, row 0 at the top: the union of the strokes' filled outlines, the em box
    mapped onto the whole image (each stroke filled on its own: an even-odd fill of the union
    would punch holes where strokes overlap)."""
    return np.any(stroke_masks(glyph, size), axis=0)


def beaded(widths_mm) -> bool:
    """A bead at a stroke's end: the footprint's widths (mm, one a frame from the first touch to
    the lift) dip over their last 30% and then grow to 1.6 times the dip and 0.4 mm over it (a
    bulb after a neck, as a soft tip that folded is pressed down again)."""
    low = np.inf
    widths = np.asarray(widths_mm, dtype=float)
    for w in widths[int(0.7 * len(widths)):]:
        low = min(low, w)
        if w >= 1.6 * low and w >= low + 0.4:
            return True
    return False


def tally_bead(beads: dict, fam: str, widths_mm) -> None:
    """Add one stroke of family `fam` to `beads` (family -> [strokes ending in a bead, strokes]),
    beaded or not by its footprint's widths a frame (beaded)."""
    tally = beads.setdefault(fam, [0, 0])
    tally[0] += int(beaded(widths_mm))
    tally[1] += 1


# the parts of a stroke, by arc length along its median: head, body, end
PARTS = ("head", "body", "end")
HEAD_END_FRACTION = 0.15


def error_by_part(glyph: Glyph, ink: np.ndarray, masks: list[np.ndarray] | None = None) -> dict:
    """Where a written glyph misses its outlines: pixel counts per part of a stroke.

    ink: (size, size) bool, the written ink (row 0 at the top). Every pixel of the ink or the
    outlines goes to the stroke whose outline is nearest, and to the part of that stroke whose
    median it projects on: the first HEAD_END_FRACTION of the arc length (head), the last (end),
    or between (body); pixels beyond a median's ends go to its head or end. Returns {part:
    (outline px, missed px, outside px)} and "outline" (all outline px). masks: the glyph's
    stroke_masks at this size, when the caller has them already.
    """
    size = ink.shape[0]
    masks = stroke_masks(glyph, size) if masks is None else masks
    ref = np.any(masks, axis=0)
    # nearest stroke outline for every pixel: (size, size) index
    dist = np.stack([cv2.distanceTransform((~m).astype(np.uint8), cv2.DIST_L2, 3) for m in masks])
    nearest = dist.argmin(axis=0)
    out = {p: np.zeros(3, np.int64) for p in PARTS}
    for k, stroke in enumerate(glyph.strokes):
        ys, xs = np.nonzero((nearest == k) & (ref | ink))
        uv = np.asarray(stroke.points, dtype=float)                   # (n, 2) em, y up
        med = np.stack([uv[:, 0] * size, (1.0 - uv[:, 1]) * size], axis=1)
        seg = np.diff(med, axis=0)                                    # (n-1, 2) px
        arc = np.r_[0.0, np.cumsum(np.hypot(seg[:, 0], seg[:, 1]))]   # (n,) px
        if len(xs) == 0 or arc[-1] <= 0.0:
            continue
        q = np.stack([xs, ys], axis=1).astype(float)                  # (k, 2) px
        best, t_arc = np.full(len(q), np.inf), np.zeros(len(q))
        for i in range(len(seg)):
            ll = float(seg[i] @ seg[i])
            if ll <= 0.0:
                continue
            t = np.clip((q - med[i]) @ seg[i] / ll, 0.0, 1.0)
            d = np.hypot(*(q - med[i] - t[:, None] * seg[i]).T)
            closer = d < best
            best[closer], t_arc[closer] = d[closer], (arc[i] + t * np.sqrt(ll))[closer]
        frac = t_arc / arc[-1]
        part = np.where(frac < HEAD_END_FRACTION, 0, np.where(frac > 1.0 - HEAD_END_FRACTION, 2, 1))
        r, i_ = ref[ys, xs], ink[ys, xs]
        for j, name in enumerate(PARTS):
            sel = part == j
            out[name] += [int((r & sel).sum()), int((r & ~i_ & sel).sum()), int((i_ & ~r & sel).sum())]
    return {**{p: tuple(int(v) for v in out[p]) for p in PARTS}, "outline": int(ref.sum())}


def iou(a: np.ndarray, b: np.ndarray) -> float:
    """Intersection over union of two bool masks of one shape (1.0 when both are empty)."""
    if a.shape != b.shape:
        raise ValueError(f"mask shapes differ: {a.shape} vs {b.shape}")
    union = np.logical_or(a, b).sum()
    return 1.0 if union == 0 else float(np.logical_and(a, b).sum() / union)


# pieces of ink, as fractions of the em square (at 512 px: 4 and 40 px).  Under DUST_EM2 a piece
# is the anti-aliased fringe of an edge crossing the mask threshold, invisible at any size, and
# is not counted; under SPECK_EM2 (a dot of ~7 px at 512) it is a speck: no stroke of a Kai
# character is that small, so it is ink the brush left where it should not (a tip that touched
# down again, a neck that broke)
DUST_EM2 = 4.0 / 512 ** 2
SPECK_EM2 = 40.0 / 512 ** 2


def pieces(ink: np.ndarray, ref: np.ndarray) -> tuple[int, int]:
    """Gaps and stray dots of a written glyph: (extra, specks).

    ink, ref: (size, size) bool masks of one shape (the written ink, the reference outlines).
    extra: how many more connected pieces (8-connected, dust left out) the ink has than the
    outlines, 0 when it has as many or fewer: a broken stroke or a stray dot adds one, and so
    does a stroke the font joins to another that the brush left apart. specks: ink pieces of
    DUST_EM2 to SPECK_EM2 of the em square.
    """
    if ink.shape != ref.shape:
        raise ValueError(f"mask shapes differ: {ink.shape} vs {ref.shape}")
    n_ink, _, stats, _ = cv2.connectedComponentsWithStats(ink.astype(np.uint8), connectivity=8)
    n_ref = cv2.connectedComponents(ref.astype(np.uint8), connectivity=8)[0]
    area = stats[1:, cv2.CC_STAT_AREA] / ink.size                 # (n_ink - 1,) em^2
    kept = area >= DUST_EM2
    specks = int((kept & (area < SPECK_EM2)).sum())
    return max(0, int(kept.sum()) - (n_ref - 1)), specks


# the edge figures: how smooth and how long the ink's outline is (a brush's edge against a felt
# marker's waver), measured on the contours of a mask, in px of that mask
EDGE_SIGMA_PX = 6.0      # px: the Gaussian along the contour that keeps the shape and drops the waver
MIN_CONTOUR_PX = 8.0     # px: shorter contours are dust at the mask threshold, left out


def contours(mask: np.ndarray) -> list[np.ndarray]:
    """The closed outlines (outer and holes) of a bool mask, each (n, 2) px resampled every 1 px
    of arc length; dust shorter than MIN_CONTOUR_PX is left out."""
    found, _ = cv2.findContours(mask.astype(np.uint8), cv2.RETR_LIST, cv2.CHAIN_APPROX_NONE)
    out = []
    for c in found:
        pts = c[:, 0, :].astype(float)                                  # (k, 2) px
        closed = np.vstack([pts, pts[:1]])
        arc = np.r_[0.0, np.cumsum(np.hypot(*np.diff(closed, axis=0).T))]   # (k + 1,) px
        if arc[-1] < MIN_CONTOUR_PX:
            continue
        s = np.arange(0.0, arc[-1], 1.0)
        out.append(np.stack([np.interp(s, arc, closed[:, 0]), np.interp(s, arc, closed[:, 1])], axis=1))
    return out


def _smooth_closed(pts: np.ndarray, sigma: float) -> np.ndarray:
    """(n, 2) points of a closed curve (1 px apart) convolved along it with a Gaussian of sigma px."""
    r = int(math.ceil(3.0 * sigma))
    kernel = np.exp(-0.5 * (np.arange(-r, r + 1) / sigma) ** 2)
    kernel /= kernel.sum()
    wrapped = pts[np.arange(-r, len(pts) + r) % len(pts)]                # (n + 2r, 2), around the loop
    return np.stack([np.convolve(wrapped[:, k], kernel, mode="valid") for k in range(2)], axis=1)


def edge_figures(mask: np.ndarray, sigma: float = EDGE_SIGMA_PX) -> tuple[float, float]:
    """(roughness px, perimeter px) of a bool mask's outlines: roughness is the mean distance of
    the contour points from the contour's own Gaussian-smoothed copy (sigma px along it, point to
    its smoothed point), over all contours by length; perimeter is their total length."""
    loops = contours(mask)
    length = float(sum(len(c) for c in loops))
    if not loops:
        return 0.0, 0.0
    dist = sum(float(np.hypot(*(c - _smooth_closed(c, sigma)).T).sum()) for c in loops)
    return dist / length, length


# corners: a turn of more than CORNER_TURN_DEG within +-CORNER_CHORD_PX along a contour
CORNER_CHORD_PX = 8
CORNER_TURN_DEG = 45.0


def corner_count(mask: np.ndarray) -> int:
    """Corners of a bool mask's outlines: on each contour (resampled every px), the runs of points
    where the chords CORNER_CHORD_PX back and ahead meet at less than 180 - CORNER_TURN_DEG deg.
    A hexagonal head, a notch, a frame step or a bead's neck each count; a smooth curve does not."""
    k = CORNER_CHORD_PX
    cos_max = math.cos(math.radians(180.0 - CORNER_TURN_DEG))
    n = 0
    for c in contours(mask):
        if len(c) <= 2 * k:
            continue
        back, ahead = np.roll(c, k, axis=0) - c, np.roll(c, -k, axis=0) - c
        cos = (back * ahead).sum(axis=1) / np.maximum(np.hypot(*back.T) * np.hypot(*ahead.T), 1e-9)
        sharp = cos > cos_max                       # the chords meet at less than 135 deg
        if sharp.all():
            n += 1
            continue
        n += int((sharp & ~np.roll(sharp, 1)).sum())     # runs around the closed contour
    return n

