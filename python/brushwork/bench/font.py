"""`brushwork bench font`: a font of characters spread over GB2312 built as `brushwork font`
builds it, then measured: points per glyph, the OTF's size and the build time extrapolated to
GB2312's 6,763 glyphs, and FreeType's 512 px raster of each glyph against the brush's 512 px
render (IoU, and the outline's 90th-percentile distance from the ink's edge); then the same
renders fitted at other tolerances, the trade between points and fidelity, and the ceiling of
that trade: the traced edge before any fitting, filled by area coverage as FreeType fills an
outline, against the render's pixels thresholded at half coverage."""
from __future__ import annotations

import argparse
import os
import tempfile
import time

import numpy as np

from ..font.outline import FIT_TOL_PX, TRACE_SIZE, Em, outline_from_image, point_count
from ..font.trace import SMOOTH_PX
from ..glyphs.charsets import gb2312
from ..writing import text_paper
from .report import markdown_table

TOLERANCES = (0.1, 0.25, 0.5, 1.0, 2.0, 2.5)     # px of the 512 px render: the trade-off table's rows
FILL_SUPERSAMPLE = 8     # sub-pixels per pixel along each axis the ceiling's edge is filled at
TARGETS = {"points": 150, "otf_mb": 4.0, "gb2312_min": 20.0, "iou": 0.99, "stray": 2.0}


def add_arguments(p) -> None:
    p.add_argument("--count", type=int, default=60, help="characters, spread evenly over GB2312 (default 60)")
    p.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    p.add_argument("--executor", default="local", help="local or ray (default local)")
    p.add_argument("--style", default="kai", help="writing style (default kai)")
    p.add_argument("--tolerances", default=",".join(map(str, TOLERANCES)),
                   help="the trade-off table's fitting tolerances in px, comma-separated ('' for none)")
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")


def sample(count: int) -> str:
    """count characters of GB2312 at even steps through the set."""
    pool = gb2312()
    if count < 1:
        raise ValueError(f"--count {count}: expected >= 1")
    return "".join(dict.fromkeys(pool[int(i)] for i in np.linspace(0, len(pool) - 1, min(count, len(pool)))))


def _fidelity(path: str, renders: dict, em: Em) -> dict:
    from ..font.check import glyph_fidelity

    rows = [glyph_fidelity(path, c, rgb, em) for c, rgb in renders.items()]
    ious, strays = [r["iou"] for r in rows], [r["stray"] for r in rows]
    return {"iou_median": float(np.median(ious)), "iou_min": float(np.min(ious)),
            "iou_share_099": float(np.mean(np.array(ious) >= TARGETS["iou"])),
            "stray_p90_max": float(np.max(strays))}


def _ttf_points(path: str) -> float:
    from fontTools.ttLib import TTFont

    with TTFont(path) as font:
        glyf = font["glyf"]
        counts = [len(glyf[n].getCoordinates(glyf)[0]) for n in font.getGlyphOrder()[1:]]
    return float(np.median(counts))


def _trade_row(tol: float, renders: dict, em: Em, folder: str) -> dict:
    """The renders fitted within tol px on average: points, extrapolated OTF size and fidelity."""
    from ..font.build import write_font

    t0 = time.perf_counter()
    outlines = {c: outline_from_image(rgb, em, tol) for c, rgb in renders.items()}
    fit_s = (time.perf_counter() - t0) / len(renders)
    path = write_font(outlines, os.path.join(folder, f"tol{tol}.otf"))
    return {"tolerance_px": tol, "points_median": float(np.median([point_count(o) for o in outlines.values()])),
            "otf_mb_gb2312": os.path.getsize(path) / len(renders) * len(gb2312()) / 1e6,
            "trace_fit_s": fit_s, **_fidelity(path, renders, em)}


def _area_fill(polys: list, size: int) -> np.ndarray:
    """(size, size) coverage in [0, 1] of the closed polylines polys (each (n, 2) px, disjoint,
    holes inside their outer edges): each pixel's share of its FILL_SUPERSAMPLE^2 sub-pixels whose
    centres lie inside, by even-odd scanlines."""
    k = FILL_SUPERSAMPLE
    n = size * k
    flips = np.zeros((n, n + 1), np.int32)
    for p in polys:
        a, b = p * k, np.roll(p, -1, axis=0) * k
        # sub-pixel rows whose centre y + 0.5 lies in [min(ya, yb), max(ya, yb)) of each edge
        lo = np.ceil(np.minimum(a[:, 1], b[:, 1]) - 0.5).astype(int)
        hi = np.ceil(np.maximum(a[:, 1], b[:, 1]) - 0.5).astype(int)
        edge = np.repeat(np.arange(len(p)), hi - lo)
        row = np.concatenate([np.arange(l, h) for l, h in zip(lo, hi)]) if len(edge) else edge
        t = (row + 0.5 - a[edge, 1]) / (b[edge, 1] - a[edge, 1])
        x = a[edge, 0] + t * (b[edge, 0] - a[edge, 0])
        # the crossing flips inside/outside for every sub-pixel centre right of it
        col = np.clip(np.ceil(x - 0.5).astype(int), 0, n)
        keep = (row >= 0) & (row < n)
        np.add.at(flips, (row[keep], col[keep]), 1)
    inside = (np.cumsum(flips, axis=1)[:, :n] % 2).astype(np.float32)
    return inside.reshape(size, k, size, k).mean(axis=(1, 3))


def _ceiling(renders: dict, em: Em) -> dict:
    """The traced edge, unfitted and unsmoothed (every vertex a point), then smoothed over
    SMOOTH_PX: its IoU against each render, filled by area coverage, and its vertices a glyph."""
    from ..font.check import iou
    from ..font.trace import ink_coverage, ink_mask, trace

    out = {}
    for name, smooth in (("raw", 0.0), ("smoothed", SMOOTH_PX)):
        ious, verts = [], []
        for rgb in renders.values():
            cov = ink_coverage(rgb)
            polys = trace(cov, smooth)
            ious.append(iou(ink_mask(cov), _area_fill(polys, em.size) >= 0.5))
            verts.append(sum(len(p) for p in polys))
        out[name] = {"points_median": float(np.median(verts)), "iou_median": float(np.median(ious)),
                     "iou_min": float(np.min(ious))}
    return out


def run(count: int = 60, jobs: int = 2, executor: str = "local", style: str = "kai",
        tolerances=TOLERANCES, progress: bool = True) -> dict:
    from ..font import build_font
    from ..glyphs import load_source

    chars = sample(count)
    em = Em(TRACE_SIZE)
    with tempfile.TemporaryDirectory() as tmp:
        otf = os.path.join(tmp, "bench.otf")
        res = build_font(chars, otf, style=style, jobs=jobs, executor=executor, progress=progress)
        ttf = os.path.join(tmp, "bench.ttf")
        build_font(chars, ttf, style=style, jobs=1)                # from the cache: glyf assembly only
        glyphs = load_source("default", chars)
        renders = {c: text_paper([glyphs[c]], em.size, style).image() for c in res.made}
        n = len(res.made)
        result = {"characters": n, "failed": res.failed, "jobs": jobs, "executor": executor,
                  "tolerance_px": FIT_TOL_PX, "size_px": em.size,
                  "points_median": float(np.median(res.points)), "ttf_points_median": _ttf_points(ttf),
                  "otf_bytes": os.path.getsize(otf),
                  "otf_mb_gb2312": os.path.getsize(otf) / n * len(gb2312()) / 1e6,
                  "seconds": res.seconds, "s_per_glyph": res.seconds / n,
                  "gb2312_min": res.seconds / n * len(gb2312()) / 60.0,
                  "cpu_s_per_glyph": res.cpu_seconds / n,
                  "gb2312_min_cpu": (res.cpu_seconds / jobs + res.write_seconds) / n * len(gb2312()) / 60.0,
                  "load": os.getloadavg()[0],
                  **_fidelity(otf, renders, em), "ttf": _fidelity(ttf, renders, em)}
        result["tradeoff"] = [_trade_row(t, renders, em, tmp) for t in tolerances]
        result["ceiling"] = _ceiling(renders, em)
    return result


def iou_vs_points(r: dict) -> str:
    """One line: median IoU at each median point count of the trade-off rows, fewest points
    first, then the unfitted edge; and the best IoU of a row within the points target."""
    rows = sorted(r["tradeoff"], key=lambda x: x["points_median"])
    pairs = [f"{x['points_median']:.0f}: {x['iou_median']:.3f}" for x in rows]
    raw = r["ceiling"]["raw"]
    pairs.append(f"{raw['points_median']:.0f} (the traced edge, unfitted): {raw['iou_median']:.3f}")
    within = [x["iou_median"] for x in rows if x["points_median"] <= TARGETS["points"]]
    best = f"; best within {TARGETS['points']} points: {max(within):.3f}" if within else ""
    return "  IoU vs points a glyph (medians): " + ", ".join(pairs) + best


def table(r: dict) -> str:
    t = TARGETS
    lines = [f"bench font: {r['characters']} GB2312 characters, {r['jobs']} jobs ({r['executor']}), traced at "
             f"{r['size_px']} px, fitted within {r['tolerance_px']} px on average",
             f"  median points a glyph: {r['points_median']:.0f} cubic (OTF), {r['ttf_points_median']:.0f} "
             f"quadratic (TTF)   (target <= {t['points']})",
             f"  OTF size for 6,763 glyphs: {r['otf_mb_gb2312']:.1f} MB   (target <= {t['otf_mb']} MB)",
             f"  build time: {r['s_per_glyph']:.3f} s a glyph, render included; GB2312 in {r['gb2312_min']:.1f} min"
             f"   (target <= {t['gb2312_min']:.0f} min)",
             f"  worker CPU time: {r['cpu_s_per_glyph']:.3f} s a glyph; on {r['jobs']} unshared cores (the "
             f"workers' CPU time shared out, the font's assembly added) GB2312 in "
             f"{r['gb2312_min_cpu']:.1f} min (load average during the run: {r['load']:.1f})",
             f"  FreeType 512 px vs the brush's 512 px render, OTF: IoU median {r['iou_median']:.4f}, min "
             f"{r['iou_min']:.4f}, {100 * r['iou_share_099']:.0f}% of glyphs >= {t['iou']}; outline's p90 distance "
             f"from the ink edge <= {r['stray_p90_max']:.2f} units (target <= {t['stray']})",
             f"  TTF: IoU median {r['ttf']['iou_median']:.4f}, min {r['ttf']['iou_min']:.4f}; p90 distance "
             f"<= {r['ttf']['stray_p90_max']:.2f} units"]
    if r["tradeoff"]:
        cols = ["tolerance_px", "points_median", "otf_mb_gb2312", "iou_median", "iou_min", "iou_share_099",
                "stray_p90_max", "trace_fit_s"]
        heads = ["tolerance px", "points (median)", "OTF MB (6,763)", "IoU median", "IoU min", "share IoU >= 0.99",
                 "p90 stray units (max)", "trace+fit s/glyph"]
        lines += ["", "the same renders fitted at other tolerances:", markdown_table(r["tradeoff"], cols, heads),
                  iou_vs_points(r)]
    c = r["ceiling"]
    lines.append(f"  ceiling, the traced edge filled by area coverage: unfitted {c['raw']['points_median']:.0f} points, "
                 f"IoU {c['raw']['iou_median']:.4f} / {c['raw']['iou_min']:.4f}; smoothed over {SMOOTH_PX:g} px, "
                 f"IoU {c['smoothed']['iou_median']:.4f} / {c['smoothed']['iou_min']:.4f} (median / min)")
    lines += [f"failed {c}: {why}" for c, why in r["failed"]]
    return "\n".join(lines)


def handle(args: argparse.Namespace) -> int:
    from .report import run_benchmark

    tols = [float(t) for t in args.tolerances.split(",") if t.strip()]
    return run_benchmark("font", args, lambda: run(args.count, args.jobs, args.executor, args.style, tols), table)
