"""`brushwork render`: characters written left to right on one image by one brush."""
from __future__ import annotations

import argparse
import os
import time

from ..files import check_bits
from ..writing import MAX_SIDE, check_samples, check_seed, check_size
from .options import image_arguments, load_glyphs, look_arguments, plans_argument, plural

MAX_TEXT_CHARS = 256     # characters `brushwork render` writes on one image (a batch takes any number)


def text_chars(text: str) -> str:
    """The characters `render` writes: every non-space character of text, in order, a repeated
    one written again; ValueError when there are none or more than MAX_TEXT_CHARS."""
    chars = "".join(c for c in text if not c.isspace())
    if not chars:
        raise ValueError("no characters to render")
    if len(chars) > MAX_TEXT_CHARS:
        raise ValueError(f"{len(chars)} characters: `render` writes at most {MAX_TEXT_CHARS} on one image; "
                         "use `brushwork batch` for more")
    return chars


def check_request(chars: str, size: int, bits: int, samples: int | None, seed: int) -> None:
    """The numbers of a render request, checked before any work: size, bits, samples, seed and
    the image's width (chars x size px, at most writing.MAX_SIDE)."""
    check_size(size)
    check_bits(bits)
    check_samples(samples)
    check_seed(seed)
    if len(chars) * size > MAX_SIDE:
        raise ValueError(f"{len(chars)} characters x {size} px = {len(chars) * size} px wide: more than "
                         f"{MAX_SIDE}; use a smaller size or `brushwork batch`")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("text", help="the characters to write, left to right on one image (spaces ignored)")
    p.add_argument("-o", "--output", metavar="FILE", required=True,
                   help="the image to write, in the format its suffix names: .png .jpg .jpeg .tif .tiff .bmp .webp, "
                        "or the ink's outlines as .svg or .pdf")
    look_arguments(p)
    image_arguments(p)
    plans_argument(p)
    p.add_argument("--stats", metavar="FILE", help="also write the writing's figures as JSON to FILE: frames, "
                                                   "solver steps at the iteration cap q_max, sub-steps, deepest "
                                                   "penetration (mm), beads at exits by stroke family")


def handle(args: argparse.Namespace) -> int:
    from ..files import check_image_path, check_writable, save_paper
    from ..ink import VECTOR_FORMATS, write_vectors
    from ..paper import ink_path
    from ..scene import Scene
    from ..writing import Style, text_paper, writing_stats

    chars = text_chars(args.text)
    check_request(chars, args.size, args.bits, args.samples, args.seed)
    style = Style.load(args.style)
    vectors = os.path.splitext(args.output)[1].lower() in VECTOR_FORMATS
    ink = args.ink or ("geometry" if vectors else "auto")
    if vectors and ink_path(Scene(**style.scene), ink) != "geometry":
        raise ValueError(f"{args.output}: vector outlines come from the ink's geometry; --ink {ink} takes the "
                         f"GL pass for style {style.name}")
    ink_path(Scene(**style.scene), ink)
    if vectors:
        check_writable(args.output)
    else:
        check_image_path(args.output, args.bits, args.transparent)     # before the work, not after
    if args.stats:
        from ..bench.report import check_writable, write_json

        check_writable(args.stats)
    glyphs = load_glyphs(args.source, "".join(dict.fromkeys(chars)))
    t0 = time.perf_counter()
    counts: dict = {}
    paper = text_paper([glyphs[c] for c in chars], args.size, style, args.seed, args.samples, counts, ink=ink,
                       plans=args.plans)
    if vectors:
        path = write_vectors(paper, args.output)
    else:
        path = save_paper(paper, args.output, bits=args.bits, background="transparent" if args.transparent else "white")
    print(f"wrote {path} ({plural(len(chars), 'character')}, {paper.width_px} x {paper.height_px} px, "
          f"{time.perf_counter() - t0:.1f} s)")
    if args.stats:
        write_json(args.stats, {"text": "".join(chars), "size": args.size, "style": style.name, "ink": paper.inked_by,
                                **writing_stats(counts)})
    return 0
