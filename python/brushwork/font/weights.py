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
    from ..batch import text_paper
    from ..writing import Style
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
    """python -m brushwork.font.weights FONT TEXT OUT.png [--px N]: the brush writing TEXT at
    wght 300, 500 and 700, each above the variable FONT's instance there (FreeType)."""
    import argparse
    import sys

    from ..files import write_image
    from ..glyphs import load_source

    p = argparse.ArgumentParser(prog="python -m brushwork.font.weights", description=main.__doc__.splitlines()[0])
    p.add_argument("font")
    p.add_argument("text")
    p.add_argument("output")
    p.add_argument("--px", type=int, default=128)
    p.add_argument("--style", default="kai")
    args = p.parse_args(argv)
    try:
        img = weights_picture(args.font, args.text, load_source("default", args.text), args.style, args.px)
        print(f"wrote {write_image(args.output, np.repeat(img[..., None], 3, axis=2))}")
    except (OSError, ValueError, RuntimeError) as err:
        print(f"brushwork: error: {' '.join(str(err).split())}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
