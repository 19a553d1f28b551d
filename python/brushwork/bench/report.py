"""Tiny report helpers for the benchmarks: Markdown tables, atomic JSON files, and the run of a
benchmark command (check, run, print, write)."""
from __future__ import annotations

import json
import math
import os
import sys
from typing import Any, Callable, Sequence

from ..files import check_writable, write_atomic  # noqa: F401  (the benchmarks' JSON goes through them)


def format_value(v: Any) -> str:
    """One table cell: floats to 3 significant digits (scientific when tiny or huge), ints as is,
    booleans as yes/no, None as an empty cell."""
    # none, booleans and integers first (bool is an int subclass)
    if v is None:
        return ""
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, int):
        return str(v)
    # numpy scalars behave like python numbers after item()
    if hasattr(v, "item") and not isinstance(v, (str, bytes)):
        try:
            return format_value(v.item())
        except (TypeError, ValueError):
            pass
    if isinstance(v, float):
        if not math.isfinite(v):
            return str(v)
        if v == 0.0:
            return "0"
        a = abs(v)
        if a < 1e-3 or a >= 1e6:
            return f"{v:.2e}"
        if a >= 100.0:
            # 3 significant digits without an exponent: 18873.2 -> 18900
            return str(int(round(v, 2 - int(math.floor(math.log10(a))))))
        return f"{v:.3g}"
    return str(v)


def _cell(v: Any) -> str:
    # keep a cell on one line and out of the table's column syntax
    return format_value(v).replace("\r", " ").replace("\n", " ").replace("|", "\\|")


def _numeric(rows: Sequence[dict], column: str) -> bool:
    """A column is numeric when every non-empty value in it is a number."""
    vals = [r.get(column) for r in rows if r.get(column) is not None]
    return bool(vals) and all(isinstance(v, (int, float)) and not isinstance(v, bool) or hasattr(v, "dtype")
                              for v in vals)


def markdown_table(rows: Sequence[dict], columns: Sequence[str],
                   headers: Sequence[str] | None = None) -> str:
    """A GitHub-flavoured Markdown table of `rows` (dicts) showing `columns` (keys) in order.

    `headers` optionally renames the columns (same length as `columns`); a missing key is an empty
    cell. Numeric columns are right-aligned.
    """
    if headers is None:
        headers = list(columns)
    if len(headers) != len(columns):
        raise ValueError(f"markdown_table: {len(headers)} headers for {len(columns)} columns")
    cells = [[_cell(r.get(c)) for c in columns] for r in rows]
    numeric = [_numeric(rows, c) for c in columns]
    widths = [max([len(str(h))] + [len(row[i]) for row in cells]) for i, h in enumerate(headers)]
    # header, separator, body
    lines = ["| " + " | ".join(str(h).ljust(w) for h, w in zip(headers, widths)) + " |"]
    lines.append("|" + "|".join((("-" * (w + 1) + ":") if num else ("-" * (w + 2)))
                                for w, num in zip(widths, numeric)) + "|")
    for row in cells:
        lines.append("| " + " | ".join(
            (s.rjust(w) if num else s.ljust(w)) for s, w, num in zip(row, widths, numeric)) + " |")
    return "\n".join(lines)


def _jsonable(obj: Any) -> Any:
    # numpy scalars and arrays to python; non-finite floats to None (strict JSON has no NaN)
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if hasattr(obj, "tolist") and not isinstance(obj, (str, bytes)):
        return _jsonable(obj.tolist())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def parameter_table(preset: str = "medium") -> str:
    """The Markdown table of every BrushModel field: unit, range, the preset's value, meaning
    (the README's "Brush parameters"; `brushwork params` prints it)."""
    from .. import BrushModel

    model = BrushModel.preset(preset)
    lines = ["| parameter | unit | range | default | meaning |", "|---|---|---|---|---|"]
    for row in BrushModel.parameters():
        value = getattr(model, row["name"])
        lo, hi = (format(v, "g") for v in (row["min"], row["max"]))
        lines.append(f"| `{row['name']}` | {row['unit']} | {lo} .. {hi} | {value} | "
                     f"{row['doc'].replace('|', '&#124;')} |")
    return "\n".join(lines)


def write_json(path: str | os.PathLike, obj: Any) -> None:
    """Write `obj` as indented JSON to `path` atomically (a temporary file in the same folder, then
    os.replace). Numpy values become plain numbers and lists; NaN and inf become null."""
    def write(tmp: str) -> None:
        with open(tmp, "w", encoding="utf-8") as f:
            json.dump(_jsonable(obj), f, indent=2, allow_nan=False)
            f.write("\n")
            f.flush()
            os.fsync(f.fileno())

    write_atomic(path, write, suffix=".json")


def run_benchmark(name: str, args, run: Callable[[], dict], table: Callable[[dict], str]) -> int:
    """Run a benchmark: fail on an unwritable --json target before the run, not after; print
    its table; write its JSON. Returns the exit code."""
    if args.json:
        check_writable(args.json)
    result = run()
    print(table(result))
    if args.json:
        write_json(args.json, {"benchmark": name, **result})
    return 0


def progress(msg: str) -> None:
    """A benchmark's progress line on stderr."""
    print(f"  {msg}", file=sys.stderr)


def check_preset(name: str) -> None:
    """ValueError unless name is a brush preset."""
    from .. import BrushModel

    if name not in BrushModel.presets():
        raise ValueError(f"unknown preset {name!r} (choose from {', '.join(BrushModel.presets())})")
