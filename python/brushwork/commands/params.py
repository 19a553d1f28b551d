"""`brushwork params`: every brush parameter (or, with --style, style field) with its unit, range
and value."""
from __future__ import annotations

import argparse


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--preset", default="medium", help="brush preset whose values to show (default medium)")
    p.add_argument("--style", action="store_true", help="the fields of a style file instead of the brush's")


def handle(args: argparse.Namespace) -> int:
    from ..bench.report import check_preset, parameter_table
    from ..writing import style_table

    check_preset(args.preset)
    print(style_table() if args.style else parameter_table(args.preset))
    return 0
