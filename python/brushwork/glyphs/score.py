"""Scoring a rendered glyph against its source's filled stroke outlines (Make Me a Hanzi keeps them).

The reference mask is drawn the way the source's SVG recipe draws the outlines: the em box fills
the image, so ink and outlines compare pixel for pixel. Filling goes through OpenCV.
"""
from __future__ import annotations

import cv2
import numpy as np

from .model import Glyph, GlyphError
from .svgpath import parse_svg_path

_SHIFT = 4  # cv2.fillPoly fixed-point bits: vertices placed to 1/16 px


def has_outlines(glyph: Glyph) -> bool:
    """True when every stroke carries its filled outline (needed by `outline_mask`)."""
    return bool(glyph.strokes) and all(s.outline is not None for s in glyph.strokes)


def outline_mask(glyph: Glyph, size: int) -> np.ndarray:
    """(size, size) bool, row 0 at the top: the union of the strokes' filled outlines, the em box
    mapped onto the whole image."""
    if not has_outlines(glyph):
        raise GlyphError(glyph.source or glyph.char, "no stroke outlines to score against "
                         "(only Make Me a Hanzi keeps them)")
    mask = np.zeros((size, size), np.uint8)
    for stroke in glyph.strokes:
        polys = []
        for poly in parse_svg_path(stroke.outline):
            uv = glyph.to_em(poly)                                    # (k, 2) em, y up
            px = np.stack([uv[:, 0] * size, (1.0 - uv[:, 1]) * size], axis=1)
            polys.append(np.round(px * (1 << _SHIFT)).astype(np.int32))
        # each stroke on its own: an even-odd fill of the union would punch holes at overlaps
        cv2.fillPoly(mask, polys, 1, lineType=cv2.LINE_8, shift=_SHIFT)
    return mask.astype(bool)


def iou(a: np.ndarray, b: np.ndarray) -> float:
    """Intersection over union of two bool masks of one shape (1.0 when both are empty)."""
    if a.shape != b.shape:
        raise ValueError(f"mask shapes differ: {a.shape} vs {b.shape}")
    union = np.logical_or(a, b).sum()
    return 1.0 if union == 0 else float(np.logical_and(a, b).sum() / union)
