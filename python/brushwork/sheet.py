"""Contact sheets: many glyphs on one PNG, each labelled with its character and code point, and
optionally beside each the same character from a reference font drawn through FreeType, so a
designer compares at a glance.

Image work goes through OpenCV (resizing, drawing, PNG) and FreeType (`freetype-py`, which
bundles the library). The default reference font is a Kai face: AR PL UKai (Debian/Ubuntu: apt
install fonts-arphic-ukai) or AR PL KaitiM GB (fonts-arphic-gkai00mp).
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .files import write_image

# where Debian/Ubuntu (and a few other systems) put Kai faces; BRUSHWORK_REFERENCE_FONT overrides
KAI_FONTS = (
    "/usr/share/fonts/truetype/arphic/ukai.ttc",
    "/usr/share/fonts/truetype/arphic-gkai00mp/gkai00mp.ttf",
    "/usr/share/fonts/truetype/arphic/gkai00mp.ttf",
    "/usr/share/fonts/arphic-ukai/ukai.ttc",
    "/usr/share/fonts/TTF/ukai.ttc",
)


def find_reference_font() -> str | None:
    """A Kai font file for reference glyphs and labels, or None when none is installed."""
    env = os.environ.get("BRUSHWORK_REFERENCE_FONT")
    if env:
        if not Path(env).is_file():
            raise ValueError(f"BRUSHWORK_REFERENCE_FONT={env}: no such font file")
        return env
    return next((p for p in KAI_FONTS if Path(p).is_file()), None)


class FontDrawer:
    """Characters from one font file as coverage images, through FreeType."""

    def __init__(self, path: str):
        import freetype

        try:
            self.face = freetype.Face(str(path))
        except (freetype.FT_Exception, OSError) as err:
            raise ValueError(f"{path}: cannot open the font: {err}") from None
        self.path = str(path)
        self._render = freetype.FT_LOAD_RENDER | freetype.FT_LOAD_NO_BITMAP   # outlines, antialiased

    def has(self, char: str) -> bool:
        return self.face.get_char_index(ord(char)) != 0

    def draw(self, char: str, size: int, em_fraction: float = 0.9) -> np.ndarray | None:
        """(size, size) uint8 coverage (255 = ink) of char, its em square scaled to em_fraction of
        the image and its ink box centred; None when the font lacks the character."""
        if not self.has(char):
            return None
        px = max(4, int(round(size * em_fraction)))
        self.face.set_char_size(px * 64, 0, 72, 72)     # 26.6 points at 72 dpi: the em is px pixels
        self.face.load_char(char, self._render)
        bitmap = self.face.glyph.bitmap
        bmp = np.array(bitmap.buffer, dtype=np.uint8).reshape(bitmap.rows, bitmap.pitch)[:, :bitmap.width]
        out = np.zeros((size, size), np.uint8)              # bmp: (h, w) tight ink box
        h, w = min(bmp.shape[0], size), min(bmp.shape[1], size)
        y0, x0 = (size - h) // 2, (size - w) // 2
        out[y0:y0 + h, x0:x0 + w] = bmp[:h, :w]
        return out


@dataclass
class Cell:
    """One entry of a sheet: the character, its rendering ((h, w) uint8 grey, 0 = ink on 255 =
    paper, or (h, w, 3) uint8 BGR; None when it failed) and a note under the label (e.g. its score, or the error)."""
    char: str
    image: np.ndarray | None
    note: str = ""


def _label(width: int, height: int, text: str, note: str, char: str, font: FontDrawer | None) -> np.ndarray:
    """(height, width) uint8 label strip: the character (through FreeType when a font has it),
    its code point and the note (OpenCV's Hershey font, ASCII only)."""
    import cv2

    strip = np.full((height, width), 255, np.uint8)
    x = 4
    if font is not None and font.has(char):
        g = font.draw(char, height - 4, em_fraction=1.0)
        strip[2:2 + g.shape[0], x:x + g.shape[1]] = 255 - g
        x += g.shape[1] + 4
    scale = height / 60.0
    cv2.putText(strip, text, (x, int(height * 0.45)), cv2.FONT_HERSHEY_SIMPLEX, scale, 0, 1, cv2.LINE_AA)
    if note:
        cv2.putText(strip, note[:40], (x, int(height * 0.9)), cv2.FONT_HERSHEY_SIMPLEX, scale * 0.9, 90, 1,
                    cv2.LINE_AA)
    return strip


def contact_sheet(cells: list[Cell], path: str | os.PathLike, cell_px: int = 192, columns: int | None = None,
                  reference_font: str | None | bool = None) -> str:
    """Write a PNG grid of `cells`; each is the rendering (resized to cell_px) beside, when a
    reference font is given or found (reference_font None: look for a Kai font; False: none), the
    same character from that font; a label strip under each. Returns the path (written atomically)."""
    import cv2

    if not cells:
        raise ValueError("contact sheet: no glyphs to show")
    font = None
    if reference_font is not False:
        found = reference_font if isinstance(reference_font, str) else find_reference_font()
        font = FontDrawer(found) if found else None
    pair = 2 if font is not None else 1
    label_h = max(24, cell_px // 5)
    cols = columns or max(1, int(round(np.sqrt(len(cells) * 1.6 / pair))))
    rows = -(-len(cells) // cols)
    pad = 6
    cw, ch = pair * cell_px + pad, cell_px + label_h + pad
    sheet = np.full((rows * ch + pad, cols * cw + pad, 3), 255, np.uint8)       # BGR
    for k, cell in enumerate(cells):
        y, x = pad + (k // cols) * ch, pad + (k % cols) * cw
        if cell.image is not None:
            img = cv2.resize(cell.image, (cell_px, cell_px), interpolation=cv2.INTER_AREA)
            img = img if img.ndim == 3 else cv2.cvtColor(img, cv2.COLOR_GRAY2BGR)
        else:                                     # failed: a crossed box
            img = np.full((cell_px, cell_px, 3), 235, np.uint8)
            cv2.line(img, (0, 0), (cell_px - 1, cell_px - 1), (150, 150, 150), 2)
            cv2.line(img, (0, cell_px - 1), (cell_px - 1, 0), (150, 150, 150), 2)
        sheet[y:y + cell_px, x:x + cell_px] = img
        cv2.rectangle(sheet, (x, y), (x + cell_px - 1, y + cell_px - 1), (200, 200, 200), 1)
        if font is not None:
            ref = font.draw(cell.char, cell_px)
            ref_img = np.full((cell_px, cell_px), 255, np.uint8) if ref is None else 255 - ref
            sheet[y:y + cell_px, x + cell_px:x + 2 * cell_px] = ref_img[:, :, None]
            cv2.rectangle(sheet, (x + cell_px, y), (x + 2 * cell_px - 1, y + cell_px - 1), (200, 200, 200), 1)
        sheet[y + cell_px:y + cell_px + label_h, x:x + pair * cell_px] = _label(
            pair * cell_px, label_h, f"U+{ord(cell.char):04X}", cell.note, cell.char, font)[:, :, None]
    return write_image(path, sheet)
