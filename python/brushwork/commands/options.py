"""Options the rendering commands share: size, style, source, seed, and the image's samples,
bits and background; loading the glyphs a command names."""
from __future__ import annotations

import argparse

SOURCE_HELP = ("where the strokes come from: default (the bundled glyph files, then the bundled medians: all "
               "of GB2312; then KanjiVG when installed), medians or medians:PATH, kanjivg, kanjivg:DIR, "
               "mmah:PATH or glyphs:DIR; several joined by + take each character from the first that has it "
               "(glyphs:DIR+default)")


def look_arguments(p: argparse.ArgumentParser, size: int = 1024) -> None:
    """The options every rendering command shares: size, style, source, seed."""
    from ..writing import Style

    p.add_argument("--size", type=int, default=size, help=f"px per character, 16..8192 (default {size})")
    p.add_argument("--style", default="kai", help=f"writing style: {', '.join(Style.names())} or a JSON file "
                                                  "(default kai)")
    p.add_argument("--source", default="default", help=SOURCE_HELP)
    p.add_argument("--seed", type=int, default=0, help="seed of the style's variation (default 0)")


def image_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--samples", type=int, default=None,
                   help="multisampling of the strokes: 1, 2, 4 or 8 (default: the style's, 4); "
                        "1 is ~2.5x faster on a software renderer, its edges stepped at the pixel")
    p.add_argument("--bits", type=int, default=8, help="bits per channel, 8 or 16 (16: .png and .tif only; default 8)")
    p.add_argument("--transparent", action="store_true", help="ink on transparency instead of white")
    p.add_argument("--ink", default=None, choices=("auto", "geometry", "gl"),
                   help="how the ink is made: auto (the default: geometry unless the style's scene has split, dry "
                        "or grain maps, a soaked tip or a colour ramp, then gl), geometry (exact outlines in mm swept "
                        "continuously between frames, rasterised without GL; always for .svg and .pdf) or gl (the EGL "
                        "footprint pass)")


def plans_argument(p: argparse.ArgumentParser) -> None:
    p.add_argument("--plans", metavar="DIR", help="write each character from its plan file in DIR (brushwork fit), "
                                                  "drawn in the source's em box")


def plural(n: int, noun: str) -> str:
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"


def load_glyphs(source: str, chars: str) -> dict:
    """The glyphs of chars from the source; an unknown character says how to add one."""
    from ..glyphs import GlyphError, load_source
    from ..glyphs.sources import add_source_hint

    try:
        return load_source(source, chars)
    except GlyphError as err:
        if getattr(err, "unknown", False):        # say how to add one (batch says it in its summary)
            raise ValueError(f"{err}; {add_source_hint(source)}") from err
        raise
