"""`brushwork font`: the command line of build_font."""
from __future__ import annotations

import argparse
import os
import sys

from .build import FORMATS, FontInfo
from .fit import MAX_RATIO
from .outline import FIT_TOL_PX, TRACE_SIZE
from .web import SLICE_CHARS


def add_arguments(p: argparse.ArgumentParser) -> None:
    what = p.add_mutually_exclusive_group(required=True)
    what.add_argument("--chars", metavar="TEXT", help="the characters of the font")
    what.add_argument("--charset", metavar="FILE", help="a UTF-8 file of characters (whitespace ignored), "
                                                        "or a built-in set: gb2312, gb2312-1, gb2312-2")
    p.add_argument("-o", "--output", metavar="OUT",
                   help=f"the font to write, in the format its suffix names: {' '.join(FORMATS)}")
    p.add_argument("--web", metavar="DIR", help=f"also (or only) the font for the web in DIR: WOFF2 slices of "
                                                f"--slice-chars characters each, their @font-face CSS, index.html")
    p.add_argument("--variable", action="store_true",
                   help="a variable font (-o .otf: CFF2, .ttf: gvar, .woff2) with a wght axis, 300..700: the "
                        "writing at a lighter and heavier press, every stroke its own contour")
    p.add_argument("--slice-chars", type=int, default=SLICE_CHARS,
                   help=f"characters in each --web slice, in the charset's order (default {SLICE_CHARS})")
    p.add_argument("--style", default="kai", help="writing style (default kai)")
    p.add_argument("--source", default="default", help="where the strokes come from, as for `brushwork render`")
    p.add_argument("--seed", type=int, default=0, help="seed of the style's variation (default 0)")
    p.add_argument("--family", default=FontInfo.family, help=f"family name (default {FontInfo.family})")
    p.add_argument("--version", dest="font_version", default=FontInfo.version, metavar="X.Y",
                   help=f"font version (default {FontInfo.version})")
    p.add_argument("--licence", default=FontInfo.licence, metavar="TEXT",
                   help="the licence's text or summary (name ID 13; default: the stroke data's licence applies)")
    p.add_argument("--licence-url", default="", metavar="URL", help="where the licence is (name ID 14)")
    p.add_argument("--copyright", default="", metavar="TEXT", help="the copyright notice (name ID 0)")
    p.add_argument("--vendor-url", default="", metavar="URL", help="the font's maker's web site (name ID 11)")
    p.add_argument("--ink", default="auto", choices=("auto", "geometry", "gl"),
                   help="how each glyph's ink is made: geometry (its exact contours, fitted with cubics), gl (the "
                        "EGL render, its edge traced), auto (default: geometry where the style's scene is opaque)")
    p.add_argument("--size", type=int, default=TRACE_SIZE,
                   help=f"px of the render the tolerance is measured in (and, with --ink gl, traced from; "
                        f"default {TRACE_SIZE})")
    p.add_argument("--tolerance", type=float, default=FIT_TOL_PX,
                   help=f"px of that render: the curves' mean distance from the ink's edge, none straying more "
                        f"than {MAX_RATIO:g} times it (default {FIT_TOL_PX}); larger: fewer points, a smaller font")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                   help=f"worker processes (default: the CPU count, {os.cpu_count()})")
    p.add_argument("--executor", default="local", help="local (worker processes) or ray (a Ray cluster: "
                                                       "RAY_ADDRESS, else a local one; the ray extra)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")


def handle(args: argparse.Namespace) -> int:
    from ..glyphs.charsets import parse_charset, read_charset
    from .make import build_font, summary

    if args.output is None and args.web is None:
        raise ValueError("-o OUT or --web DIR: name a font or a folder to write")
    chars = parse_charset(args.chars) if args.chars is not None else read_charset(args.charset)
    if not chars:
        raise ValueError("no characters to build a font of")
    info = FontInfo(family=args.family, version=args.font_version, licence=args.licence,
                    licence_url=args.licence_url, copyright=args.copyright, vendor_url=args.vendor_url)
    res = build_font(chars, args.output, source=args.source, style=args.style, seed=args.seed, size=args.size,
                     tolerance=args.tolerance, info=info, jobs=args.jobs, executor=args.executor,
                     progress=not args.no_progress, web=args.web, slice_chars=args.slice_chars,
                     variable=args.variable, ink=args.ink)
    print(summary(res))
    if res.interrupted:
        return 130
    if not res.points:
        print("brushwork: error: no glyph could be made: no font written", file=sys.stderr)
        return 2
    if res.failed:
        print(f"brushwork: error: {len(res.failed)} character(s) left out of the font (listed above)", file=sys.stderr)
        return 2
    return 0
