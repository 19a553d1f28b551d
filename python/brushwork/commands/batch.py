"""`brushwork batch`: many characters, one PNG each, in parallel; resumable (brushwork.batch)."""
from __future__ import annotations

import argparse
import os
import sys

from .options import image_arguments, look_arguments, plans_argument, plural


def add_arguments(p: argparse.ArgumentParser) -> None:
    what = p.add_mutually_exclusive_group(required=True)
    what.add_argument("--chars", metavar="TEXT", help="the characters to render")
    what.add_argument("--charset", metavar="FILE", help="a UTF-8 file of characters (whitespace ignored), "
                                                        "or a built-in set: gb2312, gb2312-1, gb2312-2")
    p.add_argument("--out", metavar="DIR", required=True, help="folder for the U+XXXX.png files (made if missing)")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                   help=f"worker processes (default: the CPU count, {os.cpu_count()})")
    p.add_argument("--sheet", metavar="FILE", help="also write a contact sheet of the characters to FILE, "
                                                   "beside a reference Kai font when one is installed")
    p.add_argument("--sheet-px", type=int, default=192, metavar="N",
                   help="the contact sheet's cell size in px, 32 to 1024 (default 192)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    plans_argument(p)
    p.add_argument("--executor", default="local", help="local (worker processes) or ray (a Ray cluster: "
                                                       "RAY_ADDRESS, else a local one; the ray extra)")
    look_arguments(p)
    image_arguments(p)


def handle(args: argparse.Namespace) -> int:
    from .. import batch
    from ..glyphs.charsets import parse_charset, read_charset

    chars = parse_charset(args.chars) if args.chars is not None else read_charset(args.charset)
    if not chars:
        raise ValueError("no characters to render")
    if not 32 <= args.sheet_px <= 1024:
        raise ValueError(f"--sheet-px {args.sheet_px}: the cell size must be 32 to 1024 px")
    if args.sheet:
        from ..bench.report import check_writable

        # the batch makes its --out folder anyway; made first, a sheet inside it checks as writable
        os.makedirs(args.out, exist_ok=True)
        check_writable(args.sheet)
    # stopped by SIGTERM or Ctrl-C (cli.main), finished files are whole (atomic writes) and a rerun resumes
    res = batch.run_batch(chars, args.out, source=args.source, jobs=args.jobs, size=args.size, style=args.style,
                          seed=args.seed, bits=args.bits, background="transparent" if args.transparent else "white",
                          progress=not args.no_progress, samples=args.samples, executor=args.executor,
                          ink=args.ink or "auto", plans=args.plans)
    failures = batch.write_failures(res, args.out)
    print(batch.summary(res, failures))
    if args.sheet and not res.interrupted:
        from ..sheet import contact_sheet

        failed = dict(res.failed)
        print(f"wrote {contact_sheet(batch.sheet_cells(chars, args.out, failed), args.sheet, args.sheet_px)}")
    if res.interrupted:
        return 130
    if res.failed:
        print(f"brushwork: error: {plural(len(res.failed), 'character')} failed (listed in {failures})",
              file=sys.stderr)
        return 2
    return 0
