"""`brushwork gallery`: the seed's Figure 11 sample strokes on one PNG (brushwork.gallery)."""
from __future__ import annotations

import argparse


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("-o", "--output", metavar="FILE", default="gallery.png",
                   help="the PNG to write (default gallery.png)")
    p.add_argument("--px-per-mm", type=float, default=10.0,
                   help="resolution of the paper (default 10 px/mm: 2100 x 1500 px)")
    p.add_argument("--views", metavar="FILE", default=None,
                   help="also write the brush view (shaded, outlined, transparent) to FILE")


def handle(args: argparse.Namespace) -> int:
    from ..bench.report import progress
    from ..gallery import render_gallery

    if not 1.0 <= args.px_per_mm <= 40.0:
        raise ValueError(f"--px-per-mm {args.px_per_mm}: expected 1..40")
    path = render_gallery(args.output, args.px_per_mm, progress=progress)
    print(f"wrote {path}")
    if args.views:
        from ..gallery import render_views

        print(f"wrote {render_views(args.views)}")
    return 0
