"""`brushwork bench batch`: characters per second of `brushwork batch` as a user runs it, on a
sample of GB2312 characters spread evenly across the set (those the source has), at 1024 px with
two jobs; then one process's frames timed to say where the time goes.  With both ink paths
(`--ink geometry,gl`) it also compares what they draw of the same writing: their IoU, and the ink
only one of them has.

The batch runs through the command line's entry point, which the caller hands in (`args.entry`):
the benchmark measures the command, not a copy of it."""
from __future__ import annotations

import argparse
import contextlib
import io
import os
import tempfile
import time
from pathlib import Path
from typing import Callable

import numpy as np

from ..glyphs import load_source
from ..glyphs.charsets import gb2312
from ..writing import Style, Writer, check_samples, check_size, writing_paper

Entry = Callable[[list], int]
AGREEMENT_CHARS = 12     # characters of the sample, spread over it, the two ink paths' rasters are compared on


class _Timed:
    """Wraps a bound method and adds its wall time to a counter."""

    def __init__(self, fn, name: str, counters: dict):
        self.fn, self.name, self.counters = fn, name, counters

    def __call__(self, *a, **k):
        t0 = time.perf_counter()
        try:
            return self.fn(*a, **k)
        finally:
            self.counters[self.name] = self.counters.get(self.name, 0.0) + time.perf_counter() - t0


def breakdown(glyphs: list, size: int, style: str = "kai", samples: int | None = None, ink: str = "auto") -> dict:
    """Where one process's time goes while writing `glyphs` at `size` px: seconds in the brush's
    step (the solver), in the paper's deposit (GL, or the geometry's sweep), in the driver's own
    Python, in the geometry's union and raster (on readback), and in PNG saving."""
    st = Style.load(style)
    counters: dict = {}
    frames = 0
    t0 = time.perf_counter()
    paper = writing_paper(st, size, samples=samples, ink=ink)   # one paper, cleared for each, as in a batch
    paper.deposit = _Timed(paper.deposit, "deposit", counters)
    with tempfile.TemporaryDirectory() as tmp:
        for k, glyph in enumerate(glyphs):
            paper.clear()
            writer = Writer(paper, st, k)
            writer.brush.step = _Timed(writer.brush.step, "step", counters)
            writer.write(glyph)
            frames += writer.frames
            ts = time.perf_counter()
            paper.save(os.path.join(tmp, "g.png"))
            saved = time.perf_counter() - ts
            for part, secs in _readback(paper).items():
                counters[part] = counters.get(part, 0.0) + secs
                saved -= secs
            counters["save"] = counters.get("save", 0.0) + saved
    total = time.perf_counter() - t0
    counters["driver and the rest"] = total - sum(counters.values())
    return {"characters": len(glyphs), "frames": frames, "seconds": total, "parts": counters,
            "ink": paper.inked_by}


def _readback(paper) -> dict:
    """The geometry's last readback: seconds of union and of raster (none for a GL paper)."""
    t = getattr(paper, "timings", None)
    return {} if t is None else {"union": t["union_s"], "raster": t["raster_s"]}


def _failures(folder: Path) -> list:
    """(char, why) for each line of the batch's failed.txt: `failed C (U+XXXX): why`."""
    path = folder / "failed.txt"
    lines = path.read_text(encoding="utf-8").splitlines() if path.is_file() else []
    return [(ln[len("failed "):].partition(" ")[0], ln.partition("): ")[2]) for ln in lines]


def time_batch(entry: Entry, text: str, options: list) -> dict:
    """Run `brushwork batch --chars text` with `options` into a new folder through `entry`: the
    characters written, the failures, the seconds of the whole command."""
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        with contextlib.redirect_stdout(io.StringIO()):
            rc = entry(["batch", "--chars", text, "--out", tmp] + options)
        seconds = time.perf_counter() - t0
        written = len(list(Path(tmp).glob("U+*.png")))
        failed = _failures(Path(tmp))
    if rc not in (0, 2) or (rc == 2 and not failed):
        raise ValueError(f"`brushwork batch` exited {rc} before rendering")
    return {"characters": written, "failed": failed, "seconds": seconds,
            "chars_per_s": written / seconds if seconds > 0 else 0.0}


def _sample(chars: list, count: int) -> list:
    """`count` of `chars` at even steps through them, each once."""
    return list(dict.fromkeys(chars[int(i)] for i in np.linspace(0, len(chars) - 1, min(count, len(chars)))))


def run(entry: Entry, source: str = "default", count: int = 200, size: int = 1024, jobs: int = 2,
        style: str = "kai", progress: bool = True, samples: int | None = None, ink: str = "auto") -> dict:
    """Characters per second of `brushwork batch` over `count` GB2312 characters spread evenly
    across the set (those the source has), then one process's time breakdown on a few of them."""
    size, samples = check_size(size), check_samples(samples)
    Style.load(style)
    pool = gb2312()
    errors: list = []
    have = load_source(source, pool, errors=errors)
    if not have:
        raise ValueError(f"{source}: none of GB2312's characters are in this source")
    text = "".join(_sample(list(have), count))
    options = ["--source", source, "--jobs", str(jobs), "--size", str(size), "--style", style]
    options += (["--samples", str(samples)] if samples else []) + ([] if progress else ["--no-progress"])
    res = time_batch(entry, text, options + ["--ink", ink])
    parts = breakdown([have[c] for c in text[:4]], size, style, samples, ink)
    return {"source": source, "size": size, "jobs": jobs, "style": style, "samples": samples or "style's",
            "ink": parts["ink"], "text": text, **res,
            "gb2312_hours": len(pool) / res["chars_per_s"] / 3600.0 if res["chars_per_s"] else None,
            "breakdown": parts}


def table(result: dict) -> str:
    b = result["breakdown"]
    lines = [f"bench batch: {result['characters']} characters of {result['source']} at {result['size']} px, "
             f"{result['jobs']} jobs, samples {result['samples']}, ink {result['ink']}: "
             f"{result['chars_per_s']:.2f} characters/s "
             f"(GB2312's 6,763 in {result['gb2312_hours'] * 60:.0f} min)",
             "",
             f"one process, {b['characters']} characters, {b['frames']} frames, {b['seconds']:.2f} s:",
             "| part | s/char | share |", "|---|---|---|"]
    for name, secs in sorted(b["parts"].items(), key=lambda kv: -kv[1]):
        lines.append(f"| {name} | {secs / b['characters']:.3f} | {100 * secs / b['seconds']:.0f}% |")
    for char, why in result["failed"]:
        lines.append(f"failed {char}: {why}")
    return "\n".join(lines)


def add_arguments(p: argparse.ArgumentParser) -> None:
    from ..commands.options import SOURCE_HELP

    p.add_argument("--source", default="default", help=SOURCE_HELP)
    p.add_argument("--count", type=int, default=200,
                   help="characters, spread over GB2312 (default 200: a sample of the set's mix of simple and "
                        "busy characters, long enough that the workers' start-up weighs as little as in a real batch)")
    p.add_argument("--size", type=int, default=1024, help="px per character (default 1024)")
    p.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    p.add_argument("--style", default="kai", help="writing style (default kai)")
    p.add_argument("--samples", type=int, default=None, help="multisampling: 1, 2, 4 or 8 (default: the style's)")
    p.add_argument("--ink", default="auto", help="auto (default, as batch), geometry or gl, or several with commas "
                                                 "(geometry,gl): each measured in turn, in this one run")
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")


def handle(args: argparse.Namespace) -> int:
    from .report import run_benchmark

    from ..paper import ink_path
    from ..scene import Scene

    check_samples(args.samples)
    inks = args.ink.split(",")
    for ink in inks:
        ink_path(Scene(**Style.load(args.style).scene), ink)
    return run_benchmark("batch", args, lambda: runs(args.entry, args.source, args.count, args.size, args.jobs,
                                                     args.style, samples=args.samples, inks=inks), tables)


def ink_agreement(glyphs: list, size: int, style: str = "kai", samples: int | None = None) -> dict:
    """The same writing of each of `glyphs` at `size` px inked by geometry and by the GL footprint
    pass: the IoU of the two inks (at half coverage), mean and worst, and where they differ: the ink
    only GL's raster has and the ink only the geometry's has, each in px per px of the geometry's
    contour (a rim of that depth all round), mean over the characters."""
    from ..glyphs.score import contours, iou
    from ..writing import text_paper

    rows = []
    for glyph in glyphs:
        geo, gl = (text_paper([glyph], size, style, samples=samples, ink=ink).ink() > 0.5 for ink in ("geometry", "gl"))
        rim = max(float(sum(len(c) for c in contours(geo))), 1.0)
        rows.append((iou(geo, gl), np.count_nonzero(gl & ~geo) / rim, np.count_nonzero(geo & ~gl) / rim))
    r = np.array(rows, dtype=float).reshape(-1, 3)
    return {"characters": len(rows), "iou_mean": float(r[:, 0].mean()), "iou_worst": float(r[:, 0].min()),
            "gl_only_px": float(r[:, 1].mean()), "geometry_only_px": float(r[:, 2].mean())}


def runs(entry: Entry, source: str = "default", count: int = 200, size: int = 1024, jobs: int = 2,
         style: str = "kai", progress: bool = True, samples: int | None = None, inks: tuple = ("gl",)) -> dict:
    """run() once for each ink path of `inks`, in turn, in this one run; with both geometry and gl,
    then the two inks of the same writing compared (ink_agreement) on AGREEMENT_CHARS of the sample."""
    out = [run(entry, source, count, size, jobs, style, progress, samples, ink) for ink in inks]
    if len(out) == 1:
        return out[0]
    result = {"runs": out}
    if {"geometry", "gl"} <= {r["ink"] for r in out}:
        chars = _sample(list(out[0]["text"]), AGREEMENT_CHARS)
        have = load_source(source, "".join(chars))
        result["agreement"] = ink_agreement([have[c] for c in chars], size, style, samples)
    return result


def tables(result: dict) -> str:
    """table() of each run, then the speed of each against the last."""
    each = result.get("runs")
    if each is None:
        return table(result)
    last = each[-1]
    ratios = [f"{r['ink']}: {r['chars_per_s'] / last['chars_per_s']:.2f}x {last['ink']}" for r in each[:-1]
              if last["chars_per_s"]]
    out = "\n\n".join(table(r) for r in each) + "\n\n" + "; ".join(ratios)
    a = result.get("agreement")
    if a:
        out += (f"\n\nthe same writing of {a['characters']} characters inked both ways: IoU {a['iou_mean']:.4f} "
                f"(worst {a['iou_worst']:.4f}); ink only the gl raster has {a['gl_only_px']:.2f} px, only the "
                f"geometry's {a['geometry_only_px']:.2f} px (per px of contour)")
    return out
