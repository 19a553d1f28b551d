"""Outlines (lists of (k, 2) arrays in mm, x right, y up from the paper's bottom-left corner, outer
loops counter-clockwise, holes clockwise) written as vector files: SVG (one path, millimetre
units, y flipped to SVG's downward axis) and a one-page PDF (points, y up as PDF's is). Both fill
by the non-zero rule, so holes stay open."""
from __future__ import annotations

import os
import zlib

import numpy as np

from ..files import write_atomic

VECTOR_FORMATS = (".svg", ".pdf")
MM_TO_PT = 72.0 / 25.4


def _path_data(loops: list, fmt: str, flip_to: float | None) -> str:
    """Each loop as move-to, line-to..., close, coordinates with 4 decimals (0.1 um in mm)."""
    out = []
    for loop in loops:
        pts = np.asarray(loop, dtype=float)
        if flip_to is not None:
            pts = np.c_[pts[:, 0], flip_to - pts[:, 1]]
        xy = [fmt.format(x, y) for x, y in pts]
        out.append(xy)
    return out


def svg_text(loops: list, width_mm: float, height_mm: float, rgb=(0.0, 0.0, 0.0), alpha: float = 1.0) -> str:
    """An SVG document of `width_mm` x `height_mm` mm whose one path fills the loops."""
    colour = "#" + "".join(f"{int(round(255 * min(max(c, 0.0), 1.0))):02x}" for c in rgb)
    parts = []
    for xy in _path_data(loops, "{:.4f} {:.4f}", height_mm):
        parts.append("M" + " L".join(xy) + " Z")
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{width_mm:g}mm" height="{height_mm:g}mm" '
            f'viewBox="0 0 {width_mm:g} {height_mm:g}">\n'
            f'<path fill="{colour}" fill-opacity="{alpha:g}" fill-rule="nonzero" d="{" ".join(parts)}"/>\n</svg>\n')


def pdf_bytes(loops: list, width_mm: float, height_mm: float, rgb=(0.0, 0.0, 0.0)) -> bytes:
    """A one-page PDF of `width_mm` x `height_mm` mm whose page fills the loops."""
    ops = [f"{rgb[0]:.4f} {rgb[1]:.4f} {rgb[2]:.4f} rg"]
    scaled = [np.asarray(l, dtype=float) * MM_TO_PT for l in loops]
    for xy in _path_data(scaled, "{:.3f} {:.3f}", None):
        ops.append(xy[0] + " m " + " ".join(p + " l" for p in xy[1:]) + " h")
    ops.append("f")
    return pdf_page("\n".join(ops), width_mm * MM_TO_PT, height_mm * MM_TO_PT)


def pdf_page(ops: str, width_pt: float, height_pt: float, resources: str = "") -> bytes:
    """A one-page PDF of `width_pt` x `height_pt` points drawn by the content operators `ops`
    (compressed), with the page's `resources` dictionary entries (e.g. graphics states)."""
    stream = zlib.compress(ops.encode("ascii"))
    objects = [b"<< /Type /Catalog /Pages 2 0 R >>",
               b"<< /Type /Pages /Kids [3 0 R] /Count 1 >>",
               (f"<< /Type /Page /Parent 2 0 R /MediaBox [0 0 {width_pt:.3f} {height_pt:.3f}] /Contents 4 0 R "
                f"/Resources << {resources} >> >>").encode(),
               f"<< /Length {len(stream)} /Filter /FlateDecode >>\nstream\n".encode() + stream + b"\nendstream"]
    out = bytearray(b"%PDF-1.4\n")
    offsets = []
    for k, body in enumerate(objects, 1):
        offsets.append(len(out))
        out += f"{k} 0 obj\n".encode() + body + b"\nendobj\n"
    xref = len(out)
    out += f"xref\n0 {len(objects) + 1}\n0000000000 65535 f \n".encode()
    out += b"".join(f"{o:010d} 00000 n \n".encode() for o in offsets)
    out += f"trailer\n<< /Size {len(objects) + 1} /Root 1 0 R >>\nstartxref\n{xref}\n%%EOF\n".encode()
    return bytes(out)


def write_vectors(paper, path: str | os.PathLike) -> str:
    """The paper's outlines (a VectorPaper's `outlines()`) as the .svg or .pdf `path` names,
    atomically. Returns the path."""
    path = os.fspath(path)
    suffix = os.path.splitext(path)[1].lower()
    if suffix not in VECTOR_FORMATS:
        raise ValueError(f"{path}: vectors are written as {' or '.join(VECTOR_FORMATS)}, not {suffix or 'no suffix'}")
    loops = paper.outlines()
    if suffix == ".svg":
        data = svg_text(loops, paper.width_mm, paper.height_mm).encode("utf-8")
    else:
        data = pdf_bytes(loops, paper.width_mm, paper.height_mm)

    def write(tmp: str) -> None:
        with open(tmp, "wb") as f:
            f.write(data)

    write_atomic(path, write, suffix=suffix)
    return path
