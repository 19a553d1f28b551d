"""How a font written by brushwork reads in real clients: the OpenType Sanitizer's verdict,
HarfBuzz's shaping, and FreeType's rasterisation of each glyph against the brush's own render of
the character (IoU of the ink, and how far the outline strays from the ink's edge)."""
from __future__ import annotations

import os

import numpy as np

from .outline import Em
from .trace import UPSAMPLE, ink_mask

EDGE_PCT = 90           # the percentile of the outline's distance from the ink edge reported


def sanitize(path: str | os.PathLike) -> str | None:
    """None when the OpenType Sanitizer accepts the font at path, else its complaint."""
    import ots

    res = ots.sanitize(os.fspath(path), os.devnull, capture_output=True)
    return None if res.returncode == 0 else (res.stderr or res.stdout).decode(errors="replace").strip()


def shaped_glyphs(path: str | os.PathLike, text: str, wght: float | None = None) -> list:
    """The glyph names HarfBuzz shapes text into with the font at path (of a variable font, at
    the instance wght), one per cluster."""
    import uharfbuzz as hb
    from fontTools.ttLib import TTFont

    with open(path, "rb") as f:
        face = hb.Face(f.read())
    font = hb.Font(face)
    if wght is not None:
        font.set_variations({"wght": wght})
    buf = hb.Buffer()
    buf.add_str(text)
    buf.guess_segment_properties()
    hb.shape(font, buf)
    with TTFont(os.fspath(path), lazy=True) as ttf:
        order = ttf.getGlyphOrder()
    return [order[i.codepoint] for i in buf.glyph_infos]


def _freetype_face(path: str | os.PathLike):
    """A FreeType face of the font at path; a WOFF2 is unpacked by fontTools first (FreeType
    builds without Brotli read no WOFF2)."""
    import io

    import freetype

    if os.fspath(path).lower().endswith(".woff2"):
        from fontTools.ttLib import TTFont

        buf = io.BytesIO()
        with TTFont(os.fspath(path)) as font:
            font.flavor = None
            font.save(buf)
        buf.seek(0)
        return freetype.Face(buf)
    return freetype.Face(os.fspath(path))


def freetype_coverage(path: str | os.PathLike, char: str, em: Em, baseline: float | None = None,
                      wght: float | None = None) -> np.ndarray:
    """(N, N) float coverage in [0, 1] of char's glyph rasterised by FreeType unhinted at
    N = em.size px per em, placed in the em square as the brush's N x N render is (or with the
    baseline `baseline` px below the top edge); of a variable font, at the instance wght."""
    import freetype

    face = _freetype_face(path)
    if wght is not None:
        face.set_var_design_coords((wght,))
    face.set_pixel_sizes(em.size, em.size)
    base = em.ascender * em.size / em.upm if baseline is None else baseline   # px below the top edge
    row, frac = int(np.floor(base)), base - np.floor(base)
    # shift the outline down by the baseline's fraction of a pixel (26.6 fixed point)
    face.set_transform(freetype.Matrix(0x10000, 0, 0, 0x10000), freetype.Vector(0, -int(round(frac * 64))))
    face.load_char(char, freetype.FT_LOAD_RENDER | freetype.FT_LOAD_NO_HINTING | freetype.FT_LOAD_NO_BITMAP)
    slot = face.glyph
    bmp = slot.bitmap
    out = np.zeros((em.size, em.size), np.float32)
    if bmp.rows == 0 or bmp.width == 0:
        return out
    img = np.array(bmp.buffer, np.uint8).reshape(bmp.rows, bmp.pitch)[:, :bmp.width].astype(np.float32) / 255.0
    _paste(out, img, row - slot.bitmap_top, slot.bitmap_left)
    return out


def _paste(out: np.ndarray, img: np.ndarray, top: int, left: int) -> None:
    """img added into out with its top-left pixel at (top, left), clipped to out."""
    h, w = out.shape
    t0, l0 = max(top, 0), max(left, 0)
    t1, l1 = min(top + img.shape[0], h), min(left + img.shape[1], w)
    if t1 > t0 and l1 > l0:
        out[t0:t1, l0:l1] += img[t0 - top:t1 - top, l0 - left:l1 - left]


def iou(a: np.ndarray, b: np.ndarray) -> float:
    """Intersection over union of two boolean masks (1 when both are empty)."""
    union = np.count_nonzero(a | b)
    return np.count_nonzero(a & b) / union if union else 1.0


def glyph_points(path: str | os.PathLike) -> dict:
    """{char: points of its glyph as the font at path stores them}: every on- and off-curve point
    of its contours (a CFF curve three, a line one; a glyf contour's stored points), the point
    that closes a contour onto its start not counted again."""
    from fontTools.pens.recordingPen import DecomposingRecordingPen
    from fontTools.ttLib import TTFont

    out = {}
    with TTFont(os.fspath(path)) as font:
        glyphs = font.getGlyphSet()
        for cp, name in font.getBestCmap().items():
            pen = DecomposingRecordingPen(glyphs)
            glyphs[name].draw(pen)
            out[chr(cp)] = sum(len(args) for op, args in pen.value if op in ("lineTo", "curveTo", "qCurveTo"))
    return out


def outline_points(path: str | os.PathLike, char: str, steps: int = 16) -> np.ndarray:
    """(n, 2) points along char's glyph outline in font units, each curve cut in `steps`."""
    from fontTools.pens.basePen import BasePen
    from fontTools.ttLib import TTFont

    pts: list = []

    class _Flatten(BasePen):
        def _moveTo(self, p):
            pts.append(p)

        def _lineTo(self, p):
            pts.append(p)

        def _curveToOne(self, p1, p2, p3):
            p0 = np.array(self._getCurrentPoint())
            u = np.linspace(0, 1, steps + 1)[1:, None]
            c = [p0, np.array(p1), np.array(p2), np.array(p3)]
            pts.extend(((1 - u) ** 3 * c[0] + 3 * (1 - u) ** 2 * u * c[1] + 3 * (1 - u) * u * u * c[2]
                        + u ** 3 * c[3]).tolist())

    with TTFont(os.fspath(path)) as font:
        glyphs = font.getGlyphSet()
        glyphs[font.getBestCmap()[ord(char)]].draw(_Flatten(glyphs))
    return np.array(pts, dtype=float).reshape(-1, 2)


def edge_strays(cov: np.ndarray, points_units: np.ndarray, em: Em) -> np.ndarray:
    """(n,) font units: how far each outline point lies from the ink's edge (the coverage's 0.5
    iso-line, found on a bilinear upsampling by UPSAMPLE)."""
    import cv2

    h, w = cov.shape
    big = cv2.resize(cov.astype(np.float32), (w * UPSAMPLE, h * UPSAMPLE), interpolation=cv2.INTER_LINEAR)
    inside = (big >= 0.5).astype(np.uint8)
    edge = inside ^ cv2.erode(inside, np.ones((3, 3), np.uint8))
    dist = cv2.distanceTransform((1 - edge).astype(np.uint8), cv2.DIST_L2, 5)
    px = em.to_px(points_units) * UPSAMPLE - 0.5
    ij = np.clip(np.round(px).astype(int), 0, [w * UPSAMPLE - 1, h * UPSAMPLE - 1])
    return dist[ij[:, 1], ij[:, 0]] / UPSAMPLE * em.upm / em.size


def shifted(cov: np.ndarray, shift_px) -> np.ndarray:
    """cov (H, W) moved by shift_px (dx, dy) whole px, right and down, what leaves the image dropped
    and what enters it empty."""
    dx, dy = (int(round(v)) for v in shift_px)
    out = np.zeros_like(cov)
    h, w = cov.shape
    out[max(dy, 0):h + min(dy, 0), max(dx, 0):w + min(dx, 0)] = cov[max(-dy, 0):h - max(dy, 0), max(-dx, 0):w - max(dx, 0)]
    return out


def glyph_fidelity(path: str | os.PathLike, char: str, rgb: np.ndarray, em: Em, shift_px=(0, 0)) -> dict:
    """FreeType's raster of char in the font at path against the brush's render rgb (N, N, 3) moved
    by shift_px as the font placed the glyph in its em box (outline.placement):
    {"iou": ink IoU, "stray": the EDGE_PCT percentile of the outline's distance from the ink edge
    in font units}."""
    from .trace import ink_coverage

    cov = shifted(ink_coverage(rgb), shift_px)
    ft = freetype_coverage(path, char, em)
    strays = edge_strays(cov, outline_points(path, char), em)
    return {"iou": iou(ink_mask(cov), ft >= 0.5),
            "stray": float(np.percentile(strays, EDGE_PCT)) if len(strays) else 0.0}
