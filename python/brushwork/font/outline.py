"""A character's outline from the brush: the glyph written as `brushwork render CHAR --size N`
writes it, its ink's exact contours (a VectorPaper's `outlines()`, in mm) or, where the ink is made
by GL, its traced edge (trace.py), fitted with cubics (fit.py) in font units.

The em square of the font is the rendered image: x in [0, upm] across its N columns, y from
the typo ascender (row 0's top edge) down to the typo descender (the last row's bottom edge)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .fit import CORNER_DEG, fit_closed
from .trace import MIN_AREA_PX, SMOOTH_PX, SPACING_PX, _signed_area, arc, ink_coverage, resample_closed, trace

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


def image_edges(rgb: np.ndarray, tol_px: float = FIT_TOL_PX) -> list:
    """The edge of the ink in an ink-on-white image (N, N, 3) as closed polylines in px, points
    SPACING_PX apart (trace.py), smoothed over SMOOTH_PER_TOL * tol_px (SMOOTH_PX at most)."""
    return trace(ink_coverage(rgb), min(SMOOTH_PER_TOL * tol_px, SMOOTH_PX))


def loops_to_px(loops: list, em_mm: float, size: int) -> list:
    """Closed loops (each (k, 2) mm, x right, y up from the em box's bottom-left corner, outer loops
    counter-clockwise, as a VectorPaper's `outlines()` gives them) as polylines in the px of a
    size x size render of the em box (x right, y down), wound as trace() winds its edges: outer
    edges with a positive shoelace area, holes negative."""
    k = size / em_mm
    # flipping y turns every loop's sense; reversing it turns it back
    return [np.stack([l[:, 0] * k, (em_mm - l[:, 1]) * k], axis=1)[::-1] for l in loops if len(l) >= 3]


def _turns(p: np.ndarray) -> np.ndarray:
    """(n,) degrees the closed polyline p turns through at each vertex."""
    ahead = np.roll(p, -1, axis=0) - p
    back = p - np.roll(p, 1, axis=0)
    cos = np.sum(ahead * back, axis=1) / np.maximum(np.linalg.norm(ahead, axis=1) * np.linalg.norm(back, axis=1), 1e-12)
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def resample_keeping_corners(p: np.ndarray, spacing: float) -> np.ndarray:
    """The closed polyline p (n, 2) resampled about `spacing` apart along its length, each vertex
    where it turns by more than CORNER_DEG at once kept as a point (a corner of the exact contour
    stays sharp), the runs between evenly."""
    keep = np.flatnonzero(_turns(p) > CORNER_DEG)
    if len(keep) == 0:
        return resample_closed(p, spacing)
    ring = np.roll(p, -int(keep[0]), axis=0)
    ring = np.concatenate([ring, ring[:1]])
    ends = list(keep - keep[0]) + [len(p)]
    out = []
    for a, b in zip(ends[:-1], ends[1:]):
        run = ring[a:b + 1]
        length = float(np.sum(np.linalg.norm(np.diff(run, axis=0), axis=1)))
        out.append(arc(run, max(int(round(length / spacing)), 1) + 1)[:-1])
    return np.concatenate(out)


def loop_edges(loops: list, em_mm: float, size: int) -> list:
    """The ink's exact loops in mm (loops_to_px) as closed polylines in px resampled SPACING_PX apart
    along their length with their corners kept (resample_keeping_corners), unsmoothed (the contour
    is the ink's own edge), those enclosing under MIN_AREA_PX dropped."""
    return [resample_keeping_corners(p, SPACING_PX) for p in loops_to_px(loops, em_mm, size)
            if abs(_signed_area(p)) >= MIN_AREA_PX]


def paper_edges(paper, size: int, tol_px: float = FIT_TOL_PX) -> list:
    """The edge of the ink on a paper one em box square, in the px of a size px render: its exact
    loops when its ink is geometry (loop_edges), else its image traced (image_edges)."""
    if getattr(paper, "inked_by", "gl") == "geometry":
        return loop_edges(paper.outlines(), paper.height_mm, size)
    return image_edges(paper.image(), tol_px)


def placement(edges: list, size: int) -> np.ndarray:
    """(2,) whole px of a size px render: the shift that puts the centre of the ink's box (edges,
    closed polylines in px, unclipped where they are geometry) on the centre of the em box, as a
    CJK face sets a character: its side bearings equal, its ink as far above the em box's
    middle as below. Zero when there is no ink."""
    if not edges:
        return np.zeros(2)
    pts = np.concatenate(edges)
    return np.round(size / 2.0 - (pts.min(axis=0) + pts.max(axis=0)) / 2.0)


def fit_edges(edges: list, em: Em, tol_px: float = FIT_TOL_PX, shift_px=(0.0, 0.0)) -> list:
    """Closed polylines in px (points SPACING_PX apart) fitted with cubics within tol_px (fit.py)
    and moved by shift_px: a list of contours, each a (m, 4, 2) float array of cubics in font
    units, outer contours clockwise (y up), holes counter-clockwise."""
    return [em.to_font(np.array(fit_closed(poly, tol_px, SPACING_PX)) + np.asarray(shift_px)) for poly in edges]


def outline_from_image(rgb: np.ndarray, em: Em, tol_px: float = FIT_TOL_PX) -> list:
    """The outline of the ink in an ink-on-white image (N, N, 3), where it lies in the image:
    its traced edge (image_edges) fitted (fit_edges)."""
    return fit_edges(image_edges(rgb, tol_px), em, tol_px)


def outline_of_paper(paper, em: Em, tol_px: float = FIT_TOL_PX) -> list:
    """The outline of the ink on a paper one em box square (paper_edges) fitted within tol_px of
    an em.size px render, centred in the em box (placement)."""
    edges = paper_edges(paper, em.size, tol_px)
    return fit_edges(edges, em, tol_px, placement(edges, em.size))


def render_outline(glyph, em: Em, style="kai", seed: int = 0, samples: int | None = None, ink: str = "auto") -> list:
    """The outline of `glyph` (a loaded Glyph) as the brush writes it in an em.size px render, its
    ink made on the path `ink` picks (paper.ink_path)."""
    from ..writing import text_paper

    paper = text_paper([glyph], em.size, style, seed, samples, ink=ink)
    return outline_of_paper(paper, em)


def point_count(contours: list) -> int:
    """Points of the contours as a CFF charstring holds them: three per cubic."""
    return 3 * sum(len(c) for c in contours)
