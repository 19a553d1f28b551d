"""A character's outline from the brush: the glyph written as `brushwork render CHAR --size N`
writes it, its ink traced (trace.py) and fitted with cubics (fit.py), in font units.

The em square of the font is the rendered image: x in [0, upm] across its N columns, y from
the typo ascender (row 0's top edge) down to the typo descender (the last row's bottom edge)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .fit import fit_closed
from .trace import SMOOTH_PX, SPACING_PX, ink_coverage, trace

UPM = 1000
ASCENDER = 880          # font units: typo ascender, 0.88 em (Google Fonts' CJK vertical metrics)
DESCENDER = -120        # font units: typo descender, -0.12 em; ASCENDER - DESCENDER == UPM
TRACE_SIZE = 512        # px: the render the outline is traced from, N x N
FIT_TOL_PX = 0.5        # px of the traced image: a fitted curve's mean distance from the ink's edge (~1 unit)
SMOOTH_PER_TOL = 2.0    # the traced edge is smoothed over this many tolerances (SMOOTH_PX at most)


@dataclass(frozen=True)
class Em:
    """The mapping between an N x N render and the em square in font units."""
    size: int = TRACE_SIZE
    upm: int = UPM
    ascender: int = ASCENDER

    def to_font(self, px: np.ndarray) -> np.ndarray:
        """(..., 2) image px (x right, y down, the image's top-left corner at 0) -> font units (y up)."""
        k = self.upm / self.size
        return np.stack([px[..., 0] * k, self.ascender - px[..., 1] * k], axis=-1)

    def to_px(self, units: np.ndarray) -> np.ndarray:
        """The inverse of to_font."""
        k = self.size / self.upm
        return np.stack([units[..., 0] * k, (self.ascender - units[..., 1]) * k], axis=-1)


def outline_from_image(rgb: np.ndarray, em: Em, tol_px: float = FIT_TOL_PX) -> list:
    """The outline of the ink in an ink-on-white image (N, N, 3): a list of closed contours, each a
    (m, 4, 2) float array of cubics in font units, outer contours clockwise (y up), holes
    counter-clockwise. The traced edge is smoothed over SMOOTH_PER_TOL * tol_px (SMOOTH_PX at most)."""
    contours = []
    for poly in trace(ink_coverage(rgb), min(SMOOTH_PER_TOL * tol_px, SMOOTH_PX)):
        curves = fit_closed(poly, tol_px, SPACING_PX)
        contours.append(em.to_font(np.array(curves)))
    return contours


def render_outline(glyph, em: Em, style="kai", seed: int = 0, samples: int | None = None) -> list:
    """The outline of `glyph` (a loaded Glyph) as the brush writes it in an em.size px render."""
    from ..writing import text_paper

    paper = text_paper([glyph], em.size, style, seed, samples)
    return outline_from_image(paper.image(), em)


def point_count(contours: list) -> int:
    """Points of the contours as a CFF charstring holds them: three per cubic."""
    return 3 * sum(len(c) for c in contours)
