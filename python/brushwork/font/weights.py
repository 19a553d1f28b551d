"""A picture of a variable font's weights: the brush writing a line at the press of wght 300,
500 and 700, above the font's instances there rasterised by FreeType.

    python -m brushwork.font.weights FONT.otf TEXT OUT.png [--px 128] [--style kai]"""
from __future__ import annotations

import numpy as np

from .variable import master_style, press_factor

GAP_EM = 0.5            # white between the weights, in ems


def weights_picture(path, text: str, glyphs: dict, style, px: int = 128, weights=(300, 500, 700)) -> np.ndarray:
    """(2 px, len(weights) len(text) px + gaps) uint8 grey, black on white: the brush writing text
    at each weight's press (top row) above FreeType's raster of the variable font at path at that
    wght (bottom row), the weights left to right, GAP_EM of an em apart."""
    from ..writing import Style, text_paper
    from .browser import freetype_line
    from .trace import ink_coverage

    st = style if isinstance(style, Style) else Style.load(style)
    gap = np.zeros((px, int(GAP_EM * px)), np.float32)
    top, bottom = [], []
    for w in weights:
        top += [ink_coverage(text_paper([glyphs[c] for c in text], px, master_style(st, press_factor(w))).image()), gap]
        bottom += [freetype_line(path, text, px, wght=w), gap]
    cov = np.concatenate([np.concatenate(top[:-1], axis=1), np.concatenate(bottom[:-1], axis=1)], axis=0)
    return np.round(255 * (1 - np.clip(cov, 0, 1))).astype(np.uint8)


def main(argv: list | None = None) -> int:
    """python -m brushwork.font.weights FONT TEXT OUT.png [--px N] [--style S]: the brush writing
    TEXT at wght 300, 500 and 700, each above the variable FONT's instance there (FreeType)."""
    from ..glyphs import load_source
    from .browser import picture_main

    def draw(a) -> np.ndarray:
        grey = weights_picture(a.font, a.text, load_source("default", a.text), a.style, a.px)
        return np.repeat(grey[..., None], 3, axis=2)

    return picture_main("python -m brushwork.font.weights", main.__doc__.splitlines()[0], draw, argv,
                        lambda p: p.add_argument("--style", default="kai", help="writing style (default kai)"))


if __name__ == "__main__":
    raise SystemExit(main())
