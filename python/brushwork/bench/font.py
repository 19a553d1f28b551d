"""`brushwork bench font`: a font of characters spread over GB2312 built as `brushwork font`
builds it, by both routes in one run: from the ink's geometry (its exact contours fitted with
cubics) and from the GL render (its edge traced, then fitted). Each route is measured: points
per glyph as the fonts store them, the OTF's, TTF's and WOFF2's sizes and the build time
extrapolated to GB2312's 6,763 glyphs, what CFF subroutines save and cost, and FreeType's 512 px
raster of each glyph against the route's own 512 px render (IoU, and the outline's
90th-percentile distance from the ink's edge); then the same edges fitted at other tolerances,
the trade between points and fidelity, and its ceiling: the edge before any fitting, filled by
area coverage as FreeType fills an outline, against the render's pixels thresholded at half
coverage."""
from __future__ import annotations

import argparse
import os
import tempfile
import time

import numpy as np

from ..font.outline import FIT_TOL_PX, TRACE_SIZE, Em, fit_edges, image_edges, loop_edges, placement
from ..font.trace import SMOOTH_PX
from ..glyphs.charsets import gb2312
from ..writing import text_paper
from .report import markdown_table

TOLERANCES = (0.1, 0.25, 0.5, 1.0, 2.0, 2.5)     # px of the 512 px render: the trade-off table's rows
FILL_SUPERSAMPLE = 8     # sub-pixels per pixel along each axis the ceiling's edge is filled at
ROUTES = ("geometry", "gl")   # the ink's paths a font is built from: exact contours; the render, traced
TARGETS = {"points": 200, "otf_mb": 4.5, "woff2_mb": 2.5, "gb2312_min": 15.0, "iou": 0.98, "stray": 2.0}


def add_arguments(p) -> None:
    p.add_argument("--count", type=int, default=60, help="characters, spread evenly over GB2312 (default 60)")
    p.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    p.add_argument("--executor", default="local", help="local or ray (default local)")
    p.add_argument("--style", default="kai", help="writing style (default kai)")
    p.add_argument("--tolerances", default=",".join(map(str, TOLERANCES)),
                   help="the trade-off table's fitting tolerances in px, comma-separated ('' for none)")
    p.add_argument("--ink", default=",".join(ROUTES),
                   help="the routes measured, comma-separated (default geometry,gl): geometry (the ink's "
                        "exact contours fitted), gl (the render's edge traced and fitted)")
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")


def sample(count: int) -> str:
    """count characters of GB2312 at even steps through the set."""
    pool = gb2312()
    if count < 1:
        raise ValueError(f"--count {count}: expected >= 1")
    return "".join(dict.fromkeys(pool[int(i)] for i in np.linspace(0, len(pool) - 1, min(count, len(pool)))))




class Written:
    """One character as a route's brush wrote it at the bench's size: its render (rgb), its exact
    loops in mm (geometry; None when its ink is GL's), the em box's side in mm, and its placement
    in the em (outline.placement, whole px), as the font's worker finds them."""

    def __init__(self, paper, size: int):
        self.rgb = paper.image()
        self.loops = paper.outlines() if paper.inked_by == "geometry" else None
        self.em_mm, self.size = paper.height_mm, size
        self.shift = placement(self.edges(FIT_TOL_PX), size)

    def edges(self, tol: float, smooth: float | None = None) -> list:
        """The ink's edge in px: the exact loops, or the render's edge traced (smoothed over
        `smooth` px when given, else as the font's tracer smooths it at tol)."""
        if self.loops is not None:
            return loop_edges(self.loops, self.em_mm, self.size)
        if smooth is not None:
            from ..font.trace import ink_coverage, trace

            return trace(ink_coverage(self.rgb), smooth)
        return image_edges(self.rgb, tol)


def _fidelity(path: str, glyphs: dict, em: Em) -> dict:
    from ..font.check import glyph_fidelity

    rows = [glyph_fidelity(path, c, g.rgb, em, g.shift) for c, g in glyphs.items()]
    ious, strays = [r["iou"] for r in rows], [r["stray"] for r in rows]
    return {"iou_median": float(np.median(ious)), "iou_min": float(np.min(ious)),
            "iou_share": float(np.mean(np.array(ious) >= TARGETS["iou"])),
            "stray_p90_max": float(np.max(strays))}


def _trade_row(tol: float, glyphs: dict, em: Em, folder: str) -> dict:
    """The edges fitted within tol px on average: points, extrapolated OTF size and fidelity."""
    from ..font.build import write_font
    from ..font.check import glyph_points

    t0 = time.perf_counter()
    outlines = {c: fit_edges(g.edges(tol), em, tol, g.shift) for c, g in glyphs.items()}
    fit_s = (time.perf_counter() - t0) / len(glyphs)
    path = write_font(outlines, os.path.join(folder, f"tol{tol}.otf"))
    points = glyph_points(path)
    return {"tolerance_px": tol, "points_median": float(np.median([points[c] for c in glyphs])),
            "otf_mb_gb2312": os.path.getsize(path) / len(glyphs) * len(gb2312()) / 1e6,
            "fit_s": fit_s, **_fidelity(path, glyphs, em)}


def _ttf_points(path: str) -> float:
    from fontTools.ttLib import TTFont

    with TTFont(path) as font:
        glyf = font["glyf"]
        counts = [len(glyf[n].getCoordinates(glyf)[0]) for n in font.getGlyphOrder()[1:]]
    return float(np.median(counts))



def _subroutines(otf: str, glyphs: int) -> dict:
    """cffsubr on the OTF at otf, its subroutines taken out first: seconds taken, and the share of
    the OTF it saves."""
    import io

    from fontTools.ttLib import TTFont

    from ..font.build import subroutinize

    font = TTFont(otf)
    font["CFF "].cff.desubroutinize()
    plain = io.BytesIO()
    font.save(plain)
    t0 = time.perf_counter()
    subroutinize(font)
    seconds = time.perf_counter() - t0
    packed = io.BytesIO()
    font.save(packed)
    return {"subr_s": seconds, "subr_s_gb2312": seconds / glyphs * len(gb2312()),
            "subr_saves": 1.0 - len(packed.getvalue()) / len(plain.getvalue())}


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


def _ceiling(glyphs: dict, em: Em) -> dict:
    """The edge unfitted, every vertex a point (the exact loops; a traced edge unsmoothed, then
    smoothed over SMOOTH_PX): its IoU against each render, filled by area coverage, and its
    vertices a glyph."""
    from ..font.check import iou
    from ..font.trace import ink_coverage, ink_mask

    exact = next(iter(glyphs.values())).loops is not None
    out = {}
    for name, smooth in ((("exact", None),) if exact else (("raw", 0.0), ("smoothed", SMOOTH_PX))):
        ious, verts = [], []
        for g in glyphs.values():
            polys = g.edges(FIT_TOL_PX, smooth)
            ious.append(iou(ink_mask(ink_coverage(g.rgb)), _area_fill(polys, em.size) >= 0.5))
            verts.append(sum(len(p) for p in polys))
        out[name] = {"points_median": float(np.median(verts)), "iou_median": float(np.median(ious)),
                     "iou_min": float(np.min(ious))}
    return out


def _route(chars: str, ink: str, jobs: int, executor: str, style: str, tolerances, progress: bool) -> dict:
    """The font of chars built on one route (the OTF, then the TTF and WOFF2 from its cache), measured."""
    from ..font import build_font
    from ..glyphs import load_source

    em = Em(TRACE_SIZE)
    with tempfile.TemporaryDirectory() as tmp:
        otf, ttf, woff2 = (os.path.join(tmp, f"bench.{x}") for x in ("otf", "ttf", "woff2"))
        res = build_font(chars, otf, style=style, jobs=jobs, executor=executor, progress=progress, ink=ink)
        for path in (ttf, woff2):
            build_font(chars, path, style=style, jobs=1, ink=ink)      # from the cache: assembly only
        loaded = load_source("default", chars)
        glyphs = {c: Written(text_paper([loaded[c]], em.size, style, ink=ink), em.size) for c in res.made}
        n = len(res.made)
        result = {"ink": res.ink, "characters": n, "failed": res.failed,
                  "points_median": float(np.median(res.points)), "ttf_points_median": _ttf_points(ttf),
                  **{f"{x}_mb_gb2312": os.path.getsize(p) / n * len(gb2312()) / 1e6
                     for x, p in (("otf", otf), ("ttf", ttf), ("woff2", woff2))},
                  "seconds": res.seconds, "s_per_glyph": res.seconds / n,
                  "gb2312_min": res.seconds / n * len(gb2312()) / 60.0, "cpu_s_per_glyph": res.cpu_seconds / n,
                  "gb2312_min_cpu": (res.cpu_seconds / jobs + res.write_seconds) / n * len(gb2312()) / 60.0,
                  **_fidelity(otf, glyphs, em), "ttf": _fidelity(ttf, glyphs, em)}
        result.update(_subroutines(otf, n))
        result["tradeoff"] = [_trade_row(t, glyphs, em, tmp) for t in tolerances]
        result["ceiling"] = _ceiling(glyphs, em)
    return result


def run(count: int = 60, jobs: int = 2, executor: str = "local", style: str = "kai",
        tolerances=TOLERANCES, progress: bool = True, inks=ROUTES) -> dict:
    bad = [ink for ink in inks if ink not in ROUTES]
    if bad or not inks:
        raise ValueError(f"--ink {','.join(inks)}: expected a comma-separated list of {', '.join(ROUTES)}")
    chars = sample(count)
    routes = {ink: _route(chars, ink, jobs, executor, style, tolerances, progress) for ink in inks}
    return {"count": len(chars), "jobs": jobs, "executor": executor, "style": style, "tolerance_px": FIT_TOL_PX,
            "size_px": TRACE_SIZE, "load": os.getloadavg()[0], "routes": routes}


def iou_vs_points(r: dict) -> str:
    """One line: median IoU at each median point count of the trade-off rows, fewest points
    first, then the unfitted edge; and the best IoU of a row within the points target."""
    rows = sorted(r["tradeoff"], key=lambda x: x["points_median"])
    pairs = [f"{x['points_median']:.0f}: {x['iou_median']:.3f}" for x in rows]
    edge = next(iter(r["ceiling"].values()))
    pairs.append(f"{edge['points_median']:.0f} (the edge, unfitted): {edge['iou_median']:.3f}")
    within = [x["iou_median"] for x in rows if x["points_median"] <= TARGETS["points"]]
    best = f"; best within {TARGETS['points']} points: {max(within):.3f}" if within else ""
    return "  IoU vs points a glyph (medians): " + ", ".join(pairs) + best


def _route_lines(r: dict, jobs: int) -> list:
    t = TARGETS
    how = "exact contours fitted" if r["ink"] == "geometry" else "GL render traced and fitted"
    return [f"route {r['ink']} ({how}), {r['characters']} characters:",
            f"  median points a glyph, as the fonts store them: {r['points_median']:.0f} cubic (OTF), "
            f"{r['ttf_points_median']:.0f} quadratic (TTF)   (target <= {t['points']})",
            f"  size for 6,763 glyphs: OTF {r['otf_mb_gb2312']:.2f} MB (target <= {t['otf_mb']} MB), WOFF2 "
            f"{r['woff2_mb_gb2312']:.2f} MB (target <= {t['woff2_mb']} MB), TTF {r['ttf_mb_gb2312']:.2f} MB; the "
            f"OTF's subroutines (cffsubr) save {100 * r['subr_saves']:.1f}% in {r['subr_s']:.1f} s "
            f"({r['subr_s_gb2312']:.0f} s scaled to 6,763 glyphs)",
            f"  build time: {r['s_per_glyph']:.3f} s a glyph, render included; GB2312 in {r['gb2312_min']:.1f} min"
            f"   (target <= {t['gb2312_min']:.0f} min)",
            f"  worker CPU time: {r['cpu_s_per_glyph']:.3f} s a glyph; on {jobs} unshared cores (the workers' CPU "
            f"time shared out, the font's assembly added) GB2312 in {r['gb2312_min_cpu']:.1f} min",
            f"  FreeType 512 px vs the route's own 512 px render, OTF: IoU median {r['iou_median']:.4f}, min "
            f"{r['iou_min']:.4f}, {100 * r['iou_share']:.0f}% of glyphs >= {t['iou']}; outline's p90 distance "
            f"from the ink edge <= {r['stray_p90_max']:.2f} units (target <= {t['stray']})",
            f"  TTF: IoU median {r['ttf']['iou_median']:.4f}, min {r['ttf']['iou_min']:.4f}; p90 distance "
            f"<= {r['ttf']['stray_p90_max']:.2f} units"]


def _trade_lines(r: dict) -> list:
    cols = ["tolerance_px", "points_median", "otf_mb_gb2312", "iou_median", "iou_min", "iou_share",
            "stray_p90_max", "fit_s"]
    heads = ["tolerance px", "points (median)", "OTF MB (6,763)", "IoU median", "IoU min",
             f"share IoU >= {TARGETS['iou']}", "p90 stray units (max)", "edge+fit s/glyph"]
    lines = ["", f"  route {r['ink']}, the same edges fitted at other tolerances:",
             markdown_table(r["tradeoff"], cols, heads), iou_vs_points(r)] if r["tradeoff"] else []
    c = r["ceiling"]
    lines += ["  ceiling, the edge filled by area coverage, unfitted: " + "; ".join(
        f"{name} {v['points_median']:.0f} points, IoU {v['iou_median']:.4f} / {v['iou_min']:.4f}"
        for name, v in c.items()) + " (median / min)"]
    return lines + [f"failed {ch}: {why}" for ch, why in r["failed"]]


def table(r: dict) -> str:
    lines = [f"bench font: {r['count']} GB2312 characters, {r['jobs']} jobs ({r['executor']}), style {r['style']}, "
             f"edges at {r['size_px']} px fitted within {r['tolerance_px']} px on average; load average {r['load']:.1f}"]
    for route in r["routes"].values():
        lines += _route_lines(route, r["jobs"]) + _trade_lines(route) + [""]
    return "\n".join(lines).rstrip()


def handle(args: argparse.Namespace) -> int:
    from .report import run_benchmark

    tols = [float(t) for t in args.tolerances.split(",") if t.strip()]
    inks = tuple(i.strip() for i in args.ink.split(",") if i.strip())
    return run_benchmark("font", args, lambda: run(args.count, args.jobs, args.executor, args.style, tols,
                                                   inks=inks), table)
