"""`brushwork bench texture`: dry-brush streaks where a style dries the brush, none in kai, no
visible repeat, and the same texture at any resolution.

Three measures:

- exits: the fraction of paper inside the strokes left white, over the last EXIT_FRACTION of
  every stroke's median (where the brush lifts while it moves) and over the whole character, for
  xing and for kai. "Inside" is the ink closed by a disc of CLOSE_MM: streak gaps narrower than
  that count as paper inside the stroke.
- tiling: the highest local maximum of the texture's autocorrelation at offsets beyond
  REPEAT_MIN_MM, inside a long stroke of a dry brush (a texture that repeats with period P has a
  peak near 1 at P); beside it the same stroke through a paper grain that does repeat (an image
  of GRID_CELLS lattice cells set as the grain), which the measure must catch.
- resolution: that stroke at two resolutions, the finer averaged down to the coarser: the
  white fraction inside at each, the mean ink inside the coarse one's stroke, and the
  correlation of the two after a blur of BLUR_MM.
"""
from __future__ import annotations

import argparse
import math
from typing import Callable

import numpy as np

from .. import BrushModel
from ..brush import Brush
from ..paper import Paper
from ..recorded import straight_stroke
from ..scene import Scene
from .report import markdown_table

EXIT_FRACTION = 0.3    # of a stroke's median, its end
EXIT_REACH_EM = 0.04   # em: how far from the exit's median a pixel still belongs to the exit
CLOSE_MM = 0.6         # mm: radius of the disc that closes streak gaps into the stroke
INK = 0.5              # alpha above which a pixel counts as inked
REPEAT_MIN_MM = 1.0    # mm: offsets nearer than this are the texture's own grain, not a repeat
PEAK_MM = 0.25         # mm: half-size of the neighbourhood a local maximum of the autocorrelation tops
GRID_CELLS = 6         # lattice cells a side of the repeating grain image of the control
BLUR_MM = 0.5          # mm: the blur before two resolutions are compared
# the long dry stroke: medium brush, mm, wetness and scene
STROKE = {"length_mm": 110.0, "step_mm": 1.0, "press": 0.3, "wetness": 0.2}
DRY_SCENE = {"split_map": True, "dry_map": True, "grain": True}


def _disc(radius_px: float) -> np.ndarray:
    r = max(1, int(round(radius_px)))
    y, x = np.mgrid[-r:r + 1, -r:r + 1]
    return (x * x + y * y <= r * r).astype(np.uint8)


def inside_mask(alpha: np.ndarray, px_per_mm: float) -> np.ndarray:
    """(H, W) bool: the ink (alpha > INK) closed by a disc of CLOSE_MM."""
    import cv2

    ink = (alpha > INK).astype(np.uint8)
    return cv2.morphologyEx(ink, cv2.MORPH_CLOSE, _disc(CLOSE_MM * px_per_mm)).astype(bool)


def white_fraction(alpha: np.ndarray, region: np.ndarray) -> float:
    """The fraction of `region` (bool, (H, W)) whose alpha is not above INK."""
    n = int(region.sum())
    return float(((alpha <= INK) & region).sum()) / n if n else 0.0


# --- exits ------------------------------------------------------------------------------------

def _median_px(points, style, size: int) -> np.ndarray:
    """A stroke's median (k, 2) em -> (k, 2) px (x, row) on a size x size image of the em box."""
    p = (np.asarray(points, dtype=float) + np.asarray(style.offset_em, dtype=float)) * size
    return np.stack([p[:, 0], size - p[:, 1]], axis=1)


def _exit_polyline(median: np.ndarray) -> np.ndarray:
    """The last EXIT_FRACTION of a polyline (k, 2), by arc length."""
    seg = np.linalg.norm(np.diff(median, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    if s[-1] <= 0.0:
        return median[-1:]
    t = np.linspace((1.0 - EXIT_FRACTION) * s[-1], s[-1], 12)
    return np.stack([np.interp(t, s, median[:, 0]), np.interp(t, s, median[:, 1])], axis=1)


def exit_region(glyph, style, size: int) -> np.ndarray:
    """(size, size) bool: pixels within EXIT_REACH_EM of the exits of the glyph's strokes."""
    import cv2

    img = np.zeros((size, size), np.uint8)
    width = max(1, int(round(2 * EXIT_REACH_EM * size)))
    for stroke in glyph.strokes:
        pts = np.round(_exit_polyline(_median_px(stroke.points, style, size))).astype(np.int32)
        cv2.polylines(img, [pts.reshape(-1, 1, 2)], False, 1, thickness=width)
    return img.astype(bool)


def character_texture(glyph, style, size: int, seed: int = 0) -> dict:
    """White fractions inside the strokes of one character: at the exits and over all."""
    from ..writing import render_glyph

    paper = render_glyph(glyph, size, style, seed)
    alpha = paper.ink()
    ppm = size / style.em_mm
    inside = inside_mask(alpha, ppm)
    return {"exit_white": white_fraction(alpha, inside & exit_region(glyph, style, size)),
            "white": white_fraction(alpha, inside)}


def exits(chars: str, size: int, styles=("xing", "kai"), progress: Callable[[str], None] | None = None) -> list:
    """One row per style: white fractions at the exits and over the characters, averaged."""
    from ..glyphs import load_source
    from ..writing import Style

    glyphs = load_source("default", chars)
    rows = []
    for name in styles:
        style = Style.load(name)
        per = [character_texture(glyphs[c], style, size) for c in chars]
        if progress:
            progress(f"exits: {name}")
        rows.append({"style": name, "chars": chars, "size_px": size,
                     "exit_white": float(np.mean([p["exit_white"] for p in per])),
                     "white": float(np.mean([p["white"] for p in per]))})
    return rows


# --- the long dry stroke -----------------------------------------------------------------------

def dry_stroke(px_per_mm: float, grain_image: np.ndarray | None = None, **scene) -> np.ndarray:
    """(H, W) alpha of one long straight stroke of a dry medium brush (STROKE) through DRY_SCENE
    (settings in `scene` override), optionally with `grain_image` set as the grain's lattice."""
    model = BrushModel.preset("medium")
    poses = straight_stroke(model, start=(15.0, 20.0), length_mm=STROKE["length_mm"], step_mm=STROKE["step_mm"],
                            press=STROKE["press"])
    brush = Brush(model)
    brush.wetness = np.full(model.n_segments + 1, STROKE["wetness"])
    paper = Paper(STROKE["length_mm"] + 30.0, 40.0, px_per_mm, scene=Scene(**{**DRY_SCENE, **scene}))
    if grain_image is not None:
        paper.set_map("grain", np.asarray(grain_image, dtype=np.float32))
    for pose in poses:
        brush.step(pose)
        paper.deposit(brush)
    paper.end_stroke()
    return paper.ink()


def _correlate(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Circular cross-correlation of two equal (H, W) arrays (zero-padded by the caller), origin
    at [0, 0]."""
    return np.fft.irfft2(np.fft.rfft2(a) * np.conj(np.fft.rfft2(b)), s=a.shape)


def autocorrelation(alpha: np.ndarray, region: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The normalised autocorrelation of alpha over `region` (bool) at every offset, origin at
    [0, 0] (offsets wrap), and the overlap of the region with itself at each offset (pixels)."""
    h, w = alpha.shape
    m = np.zeros((2 * h, 2 * w))
    m[:h, :w] = region
    x = np.zeros_like(m)
    vals = alpha[region]
    x[:h, :w] = np.where(region, alpha - vals.mean(), 0.0)
    overlap = np.rint(_correlate(m, m))
    ac = _correlate(x, x) / np.maximum(overlap, 1.0) / max(float(vals.var()), 1e-12)
    return ac, overlap


def repeat_score(alpha: np.ndarray, px_per_mm: float) -> dict:
    """The highest local maximum of the texture's autocorrelation beyond REPEAT_MIN_MM (with at
    least a quarter of the region overlapping), inside the stroke eroded by 1 mm; and its offset."""
    import cv2

    inside = inside_mask(alpha, px_per_mm).astype(np.uint8)
    core = cv2.erode(inside, _disc(px_per_mm)).astype(bool)
    ac, overlap = autocorrelation(alpha, core)
    hh, ww = ac.shape
    dy = np.minimum(np.arange(hh), hh - np.arange(hh))[:, None]
    dx = np.minimum(np.arange(ww), ww - np.arange(ww))[None, :]
    far = np.hypot(dx, dy) > REPEAT_MIN_MM * px_per_mm
    k = 2 * max(1, int(round(PEAK_MM * px_per_mm))) + 1
    peaks = (ac >= cv2.dilate(ac.astype(np.float32), np.ones((k, k), np.uint8))) & far
    peaks &= overlap >= 0.25 * core.sum()
    if not peaks.any():
        return {"repeat": 0.0, "offset_mm": None}
    i = np.unravel_index(np.argmax(np.where(peaks, ac, -np.inf)), ac.shape)
    return {"repeat": float(ac[i]), "offset_mm": float(math.hypot(dx[0, i[1]], dy[i[0], 0]) / px_per_mm)}


def control_grain(seed: int) -> np.ndarray:
    """(GRID_CELLS, GRID_CELLS) the control's grain image: cells of two levels, 0 or 1, at random,
    a repeat the dry streaks cannot hide (cells of uniform random levels repeat as weakly as the
    procedural fields for some seeds)."""
    return (np.random.default_rng(seed).random((GRID_CELLS, GRID_CELLS)) > 0.5).astype(np.float32)


def tiling(px_per_mm: float = 8.0, seed: int = 3) -> list:
    """The repeat score of the long dry stroke, and of the same stroke through a repeating grain."""
    grid = control_grain(seed)
    rows = []
    for name, image in (("procedural fields", None), (f"grain image of {GRID_CELLS}x{GRID_CELLS} cells", grid)):
        alpha = dry_stroke(px_per_mm, grain_image=image)
        rows.append({"texture": name, **repeat_score(alpha, px_per_mm)})
    return rows


def resolution_agreement(coarse: float = 4.0, fine: float = 16.0) -> dict:
    """The long dry stroke at `coarse` and `fine` px/mm: white fractions inside, and the
    correlation of the fine one averaged down with the coarse one, both blurred by BLUR_MM."""
    import cv2

    a_c, a_f = dry_stroke(coarse), dry_stroke(fine)
    down = cv2.resize(a_f, (a_c.shape[1], a_c.shape[0]), interpolation=cv2.INTER_AREA)
    sigma = BLUR_MM * coarse
    b_c, b_f = (cv2.GaussianBlur(a.astype(np.float32), (0, 0), sigma) for a in (a_c, down))
    inside = inside_mask(a_c, coarse)
    corr = float(np.corrcoef(b_c[inside], b_f[inside])[0, 1])
    return {"coarse_px_per_mm": coarse, "fine_px_per_mm": fine,
            "white_coarse": white_fraction(a_c, inside), "white_fine": white_fraction(a_f, inside_mask(a_f, fine)),
            "ink_coarse": float(a_c[inside].mean()), "ink_fine": float(down[inside].mean()),
            "mean_abs_diff": float(np.abs(a_c - down)[inside].mean()), "blurred_corr": corr}


def run(chars: str = "永和九年", size: int = 512, progress: Callable[[str], None] | None = None) -> dict:
    result = {"exits": exits(chars, size, progress=progress)}
    if progress:
        progress("tiling")
    result["tiling"] = tiling()
    if progress:
        progress("resolution")
    result["resolution"] = resolution_agreement()
    return result


def table(result: dict) -> str:
    parts = ["White paper inside the strokes (closed by a disc of "
             f"{CLOSE_MM} mm), at the last {EXIT_FRACTION:.0%} of every stroke and over the whole character:",
             markdown_table(result["exits"], ["style", "chars", "size_px", "exit_white", "white"]),
             "",
             f"Repeats: highest local maximum of the texture's autocorrelation beyond {REPEAT_MIN_MM} mm, "
             "inside a long dry stroke:",
             markdown_table(result["tiling"], ["texture", "repeat", "offset_mm"]),
             "",
             "The same dry stroke at two resolutions (the fine one averaged down):",
             markdown_table([result["resolution"]], ["coarse_px_per_mm", "fine_px_per_mm", "white_coarse",
                                                     "white_fine", "ink_coarse", "ink_fine", "mean_abs_diff",
                                                     "blurred_corr"])]
    return "\n".join(parts)


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")
    p.add_argument("--chars", default="永和九年", help="characters of the exits measure (default 永和九年)")
    p.add_argument("--size", type=int, default=512, help="px per character, 64..2048 (default 512)")


def handle(args: argparse.Namespace) -> int:
    from .report import progress, run_benchmark

    if not 64 <= args.size <= 2048 or not args.chars.strip():
        raise ValueError(f"--size {args.size} --chars {args.chars!r}: expected 64..2048 px and some characters")
    return run_benchmark("texture", args, lambda: run("".join(args.chars.split()), args.size, progress), table)
