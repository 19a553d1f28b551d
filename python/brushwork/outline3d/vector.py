"""Strokes as vector shapes: each stroke's ink outline as a filled path, written as SVG or PDF in
draw order (the SVG grouped by kind, in px; the PDF's page as large as the paper, in points).

Where the ink is geometry (an opaque scene) a stroke's outline is its region as the paper swept
it (OutlineDrawer.stroke_loops).  Otherwise it is the stroke's share of the paper's coverage,
traced (`stroke_outline`): the coverage is upsampled TRACE_SCALE times (bilinear) and its
iso-line at the PNG's mid-grey traced (OpenCV contours, simplified to SIMPLIFY_PX), so the
outline lies within a fraction of a pixel of where the PNG turns from light to dark.
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from ..ink.vectors import MM_TO_PT, pdf_page
from .lines import KINDS

TRACE_SCALE = 8          # the coverage is traced at this many times the image's resolution
LEVEL = 0.5              # coverage (times the stroke's opacity) of the traced edge: the PNG's mid-grey
CHANGED = 1e-4           # coverage a stroke adds to a pixel it touches
SIMPLIFY_PX = 0.1        # the traced outline is simplified to within this many px
VECTOR_SUFFIXES = (".svg", ".pdf")


@dataclass
class StrokeShape:
    """One stroke as drawn: its kind code, whether the line is seen, its opacity, and its outline
    as closed loops (k, 2) px (x right, y down; holes inside, filled even-odd)."""
    kind: int
    visible: bool
    alpha: float
    loops: list = field(default_factory=list)


def stroke_outline(prior: np.ndarray, inked: np.ndarray, alpha: float) -> list:
    """The outline (loops, px) of the ink a stroke laid: the paper's coverage (H, W) once it is
    `inked` where it added to the coverage `prior` to it, traced at LEVEL times its opacity `alpha`."""
    import cv2

    region = (inked - prior) > CHANGED
    if not region.any():
        return []
    ys, xs = np.nonzero(region)
    h, w = inked.shape
    y0, y1 = max(0, ys.min() - 2), min(h, ys.max() + 3)
    x0, x1 = max(0, xs.min() - 2), min(w, xs.max() + 3)
    near = cv2.dilate(region[y0:y1, x0:x1].astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
    field_ = np.where(near, inked[y0:y1, x0:x1], 0.0).astype(np.float32)
    big = cv2.resize(field_, None, fx=TRACE_SCALE, fy=TRACE_SCALE, interpolation=cv2.INTER_LINEAR)
    level = LEVEL * alpha
    contours, _ = cv2.findContours((big >= level).astype(np.uint8), cv2.RETR_CCOMP, cv2.CHAIN_APPROX_NONE)
    gy, gx = np.gradient(big)
    loops = []
    for c in contours:
        c = _onto_level(c[:, 0, :], big, gx, gy, level)
        c = cv2.approxPolyDP(c.astype(np.float32)[:, None, :], SIMPLIFY_PX * TRACE_SCALE, True)[:, 0, :]
        if len(c) >= 3:
            # a pixel i of the upsampled image is centred on (i + 0.5) / TRACE_SCALE of the image
            loops.append((c.astype(float) + 0.5) / TRACE_SCALE + [x0, y0])
    return loops


def _onto_level(points: np.ndarray, field_: np.ndarray, gx: np.ndarray, gy: np.ndarray, level: float) -> np.ndarray:
    """Contour points (k, 2) (x, y), the centres of the pixels just inside the region where the
    field reaches `level`, moved along its gradient onto the level itself (one Newton step, at
    most a pixel): the region's edge to a fraction of the traced pixel."""
    x, y = points[:, 0], points[:, 1]
    g = np.column_stack([gx[y, x], gy[y, x]])
    step = (level - field_[y, x])[:, None] * g / np.maximum((g * g).sum(axis=1, keepdims=True), 1e-12)
    return points + np.clip(step, -1.0, 1.0)


def _path_data(loops: list) -> str:
    return " ".join("M" + " L".join(f"{x:.2f},{y:.2f}" for x, y in loop) + " Z" for loop in loops)


def svg_text(shapes: list, size: tuple) -> str:
    """An SVG of (W, H) px: a white page, then each stroke's path filled with black at its
    opacity, in draw order, runs of one kind and visibility in a group named after them."""
    w, h = size
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">',
           f'<rect width="{w}" height="{h}" fill="#fff"/>']
    group = None
    for s in shapes:
        name = KINDS[s.kind] if s.visible else f"hidden-{KINDS[s.kind]}"
        if name != group:
            out += ["</g>"] if group is not None else []
            out.append(f'<g id={quoteattr(name)} fill="#000" fill-rule="evenodd">')
            group = name
        if s.loops:
            opacity = f' fill-opacity="{s.alpha:.3f}"' if s.alpha < 1.0 else ""
            out.append(f'<path d="{_path_data(s.loops)}"{opacity}/>')
    out += ["</g>"] if group is not None else []
    out.append("</svg>")
    return "\n".join(out) + "\n"


def _pdf_ops(shapes: list, height: int, scale: float, alphas: list) -> str:
    """The page's drawing operators: each stroke's loops (px, y down) as a path in points (y up)
    filled even-odd with black, under the graphics state of its opacity where it is below 1."""
    ops = ["0 0 0 rg"]
    for s in shapes:
        if not s.loops:
            continue
        path = []
        for loop in s.loops:
            xy = [f"{x * scale:.3f} {(height - y) * scale:.3f}" for x, y in loop]
            path.append(xy[0] + " m " + " ".join(p + " l" for p in xy[1:]) + " h")
        state = f"/A{alphas.index(round(s.alpha, 3))} gs " if s.alpha < 1.0 else ""
        ops.append(f"q {state}" + " ".join(path) + " f* Q")
    return "\n".join(ops)


def pdf_bytes(shapes: list, size: tuple, px_per_mm: float) -> bytes:
    """A one-page PDF of W / px_per_mm x H / px_per_mm mm: each stroke's path filled with black
    at its opacity, in draw order."""
    w, h = size
    scale = MM_TO_PT / px_per_mm
    alphas = sorted({round(s.alpha, 3) for s in shapes if s.alpha < 1.0})
    states = " ".join(f"/A{k} << /Type /ExtGState /ca {a:.3f} >>" for k, a in enumerate(alphas))
    return pdf_page(_pdf_ops(shapes, h, scale, alphas), w * scale, h * scale, f"/ExtGState << {states} >>")


def write_vector(path: str | os.PathLike, shapes: list, size: tuple, px_per_mm: float) -> str:
    """Write the shapes as the .svg or .pdf `path` names, atomically; returns the path."""
    from ..files import write_atomic

    pdf = os.fspath(path).lower().endswith(".pdf")
    data = pdf_bytes(shapes, size, px_per_mm) if pdf else svg_text(shapes, size).encode("utf-8")
    write_atomic(path, lambda tmp: Path(tmp).write_bytes(data))
    return os.fspath(path)
