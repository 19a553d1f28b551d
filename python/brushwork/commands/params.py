"""`brushwork params`: every brush parameter (or, with --style, style field) with its unit, range
and value, as a table for the terminal or, with --markdown, for a Markdown page."""
from __future__ import annotations

import argparse

MARKDOWN_BAR = "&#124;"     # a '|' inside a Markdown table's cell (|x| in a formula)


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--preset", default="medium", help="brush preset whose values to show (default medium)")
    p.add_argument("--style", action="store_true", help="the fields of a style file instead of the brush's")
    p.add_argument("--markdown", action="store_true",
                   help=f"'|' inside a cell written {MARKDOWN_BAR}, for a Markdown page (docs/parameters.md, "
                        "the README's style table)")


def handle(args: argparse.Namespace) -> int:
    from ..bench.report import check_preset, parameter_table
    from ..writing import style_table

    check_preset(args.preset)
    table = style_table() if args.style else parameter_table(args.preset)
    print(table if args.markdown else table.replace(MARKDOWN_BAR, "|"))
    return 0
