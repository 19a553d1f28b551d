"""Glyph benchmark: how close the driver's ink comes to a source's stroke outlines (`bench glyphs`),
and a character's ink under solver settings (for `bench precision`).

`bench glyphs --source mmah:PATH` (default: the five characters bundled in glyphs/outlines)
renders every character of a Make Me a Hanzi source with the default kai style at 512 px, its em
box filling the image as the data's SVG recipe draws it, and scores the ink mask (coverage > 0.5)
against the union of the stroke outlines by IoU. It prints the mean, the 10th percentile and the
worst, lists the worst characters, and writes a contact sheet of overlays (black: ink inside the
outline; red: ink outside it; pink: outline the ink missed) beside the same characters from a
reference Kai font when one is installed.
"""
from __future__ import annotations

import argparse
import math
import os
import time

import numpy as np

from ..glyphs import load_source
from ..glyphs.model import Glyph
from ..glyphs.sources import outlines_path
from ..glyphs.score import EDGE_SIGMA_PX, PARTS, corner_count, edge_figures, error_by_part, has_outlines, iou, pieces, stroke_masks
from ..writing.fit import ink_widths
from ..writing.style import family
from ..pool import Progress, parallel_map
from ..paper import ink_path
from ..scene import Scene
from ..writing import Style, Writer, check_size, text_paper, writing_paper

OVERLAY_PX = 256      # px side of each overlay kept for the contact sheet

_JOB: dict = {}


def _init(style: str, size: int, seed: int, ink: str = "auto", sigma: float = EDGE_SIGMA_PX) -> None:
    _JOB.update(style=Style.load(style), size=size, seed=seed, ink=ink, sigma=sigma)


def overlay(ink: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """(h, w, 3) uint8 BGR: ink inside the outline black, ink outside red, missed outline pink."""
    img = np.full(ink.shape + (3,), 255, np.uint8)
    img[ref] = (200, 200, 255)
    img[ink & ref] = (0, 0, 0)
    img[ink & ~ref] = (0, 0, 230)
    return img


ROUND_PEN_EM = 45.0 / 1024.0   # width of the round-pen baseline, em (its best on the MMAH dev set)


def round_pen_mask(glyph, size: int, width_em: float = ROUND_PEN_EM) -> np.ndarray:
    """(size, size) bool: a round pen of constant width drawn along the glyph's centrelines, the
    baseline a brush must beat (OpenCV thick polylines, round joins and caps)."""
    import cv2

    mask = np.zeros((size, size), np.uint8)
    thick = max(1, int(round(width_em * size)))
    for stroke in glyph.strokes:
        px = np.stack([stroke.points[:, 0] * size, (1.0 - stroke.points[:, 1]) * size], axis=1)
        cv2.polylines(mask, [np.round(px * 16).astype(np.int32)], False, 1, thick, cv2.LINE_8, 4)
    return mask.astype(bool)


def _score(task: tuple) -> tuple:
    """(char, Glyph) -> (char, scores or None, seconds, overlay (OVERLAY_PX^2 BGR) or None, error or None);
    scores: a dict of the character's measures (iou, round_pen_iou, extra_pieces, specks,
    error_by_part, broken_strokes, frames, held_frames)."""
    import cv2

    char, glyph = task
    t0 = time.perf_counter()
    try:
        counts: dict = {}
        paper = text_paper([glyph], _JOB["size"], _JOB["style"], _JOB["seed"], counts=counts, ink=_JOB["ink"])
        ink = paper.ink() > 0.5                                     # (size, size) bool, row 0 at top
        masks = stroke_masks(glyph, _JOB["size"])                  # one (size, size) bool per stroke
        ref = np.any(masks, axis=0)
        small = cv2.resize(overlay(ink, ref), (OVERLAY_PX, OVERLAY_PX), interpolation=cv2.INTER_AREA)
        pen = round_pen_mask(glyph, _JOB["size"])
        extra, specks = pieces(ink, ref)
        em_mm = _JOB["style"].em_mm
        scores = {"iou": iou(ink, ref), "round_pen_iou": iou(pen, ref), "extra_pieces": extra, "specks": specks,
                  "error_by_part": error_by_part(glyph, ink, masks), "broken_strokes": counts["breaks"],
                  "frames": counts["frames"], "held_frames": counts["holds"], "beads": counts["beads"],
                  "solver": counts["solver"], "excess_corners": corner_count(ink) - corner_count(ref),
                  "ink_beads": ink_beads(glyph, ink, masks, em_mm), "outline_beads": ink_beads(glyph, ref, masks, em_mm),
                  **_edges(ink, ref, pen, _JOB["sigma"])}
        return char, scores, time.perf_counter() - t0, small, None
    except Exception as err:        # one character's failure is reported, the rest go on
        return char, None, time.perf_counter() - t0, None, f"{type(err).__name__}: {err}"


BEAD_END = 0.15        # the last 15% of a stroke's median


def ink_beads(glyph: Glyph, ink: np.ndarray, masks: list[np.ndarray], em_mm: float = 100.0) -> dict:
    """Beads counted on the ink (an em box em_mm wide): family -> [strokes whose last BEAD_END of
    the median is wider in the ink than the ink's median width over the middle (s 0.25..0.75),
    strokes]. Widths are taken across the median where no other stroke's outline covers it (a
    join or crossing is not a bead)."""
    out: dict = {}
    size = ink.shape[0]
    for k, stroke in enumerate(glyph.strokes):
        others = np.any([m for i, m in enumerate(masks) if i != k], axis=0) if len(masks) > 1 else np.zeros_like(ink)
        s, width, covered = ink_widths(ink, stroke.points, size, others, em_mm)
        mid = width[(s >= 0.25) & (s <= 0.75) & ~covered]
        end = width[(s >= 1.0 - BEAD_END) & ~covered]
        tally = out.setdefault(family(stroke.kind), [0, 0])
        tally[1] += 1
        if len(mid) and len(end) and np.isfinite(mid).any():
            tally[0] += int(np.nanmax(end, initial=0.0) > np.nanmedian(mid))
    return out


def _edges(ink: np.ndarray, ref: np.ndarray, pen: np.ndarray, sigma: float = EDGE_SIGMA_PX) -> dict:
    """The edge figures of the ink and of the round pen against the outlines (bool masks of one
    size): excess roughness (px: the mask's edge_figures roughness at `sigma` minus the
    outlines'), perimeter ratio (its contour length / the outlines'), extra pieces (the round
    pen's; the ink's are counted with the specks)."""
    r_ref, p_ref = edge_figures(ref, sigma)
    r_ink, p_ink = edge_figures(ink, sigma)
    r_pen, p_pen = edge_figures(pen, sigma)
    return {"roughness": r_ink - r_ref, "perimeter_ratio": p_ink / max(p_ref, 1.0),
            "round_pen_roughness": r_pen - r_ref, "round_pen_perimeter_ratio": p_pen / max(p_ref, 1.0),
            "round_pen_extra_pieces": pieces(pen, ref)[0]}


def run(source: str, size: int = 512, count: int | None = None, style: str = "kai", seed: int = 0,
        jobs: int = 1, sheet: str | None = None, progress: bool = True, resolution: int = 3,
        ink: str = "auto", sigma: float = EDGE_SIGMA_PX) -> dict:
    """Score the driver against the outlines of `source` (every character, or the first `count`),
    its ink made on the path `ink` picks for the style's scene (paper.ink_path; auto: as `brushwork
    render` makes it); the first `resolution` characters are written again at 2 and 4 times the size;
    `sigma`: px along the contour that the roughness smooths over (scale it with the size to
    compare sizes)."""
    size = check_size(size)
    if not (math.isfinite(sigma) and sigma > 0.0):
        raise ValueError(f"--sigma {sigma}: the roughness's smoothing must be a positive number of px")
    ink = ink_path(Scene(**Style.load(style).scene), ink)
    errors: list = []
    glyphs = _scorable(source, count, errors)
    rows, overlays, failed = {}, {}, [(getattr(e, "char", "?"), str(e)) for e in errors]
    t0 = time.perf_counter()
    for char, score, secs, small, err in _scored(glyphs, jobs, (style, size, seed, ink, sigma), progress):
        if err is None:
            rows[char], overlays[char] = dict(score, seconds=secs), small
        else:
            failed.append((char, err))
    wall = time.perf_counter() - t0
    order = [c for c in glyphs if c in rows]
    result = {"source": source, "size": size, "style": style, "seed": seed, "jobs": jobs, "ink": ink, "sigma": sigma,
              "characters": len(order), "failed": failed, **_summary(rows, order),
              "chars_per_s": len(order) / wall if wall > 0 else None}
    result["resolution"] = resolution_agreement([glyphs[c] for c in order[:resolution]], size, style, seed, ink)
    if sheet:
        from ..sheet import Cell, contact_sheet

        cells = [Cell(c, overlays.get(c), f"IoU {rows[c]['iou']:.3f}" if c in rows else "failed") for c in glyphs]
        result["sheet"] = contact_sheet(cells, sheet, cell_px=192)
    return result


def resolution_agreement(glyphs: list, size: int, style: str, seed: int, ink: str = "auto") -> list:
    """[[char, IoU at 2 size, IoU at 4 size], ...]: each glyph written at 2 and 4 times `size`,
    its ink downsampled (area average) to `size` and masked at 0.5, against its ink written at
    `size` (the output size should only sample the scene)."""
    import cv2

    rows = []
    for glyph in glyphs:
        masks = []
        for k in (1, 2, 4):
            cover = text_paper([glyph], size * k, style, seed, ink=ink).ink().astype(np.float32)
            masks.append(cv2.resize(cover, (size, size), interpolation=cv2.INTER_AREA) > 0.5)
        rows.append([glyph.char, iou(masks[1], masks[0]), iou(masks[2], masks[0])])
    return rows


def _scorable(source: str, count: int | None, errors: list) -> dict:
    """The glyphs of `source` (the first `count`), each with stroke outlines; ValueError otherwise."""
    glyphs = load_source(source, None, errors=errors)
    if count is not None:
        glyphs = dict(list(glyphs.items())[:count])
    if not glyphs:
        raise ValueError(f"{source}: no glyphs to score")
    lacking = [c for c, g in glyphs.items() if not has_outlines(g)]
    if lacking:
        raise ValueError(f"{source}: {len(lacking)} glyphs carry no stroke outlines to score against "
                         "(use a Make Me a Hanzi source, mmah:PATH)")
    return glyphs


def _scored(glyphs: dict, jobs: int, init: tuple, progress: bool):
    """_score over the glyphs in `jobs` workers, with a progress bar; results as they finish."""
    bar = Progress(len(glyphs)) if progress else None
    try:
        for item in parallel_map(_score, list(glyphs.items()), jobs, _init, init):
            if bar is not None:
                bar.update(item[-1] is None)
            yield item
    finally:
        if bar is not None:
            bar.close()


def _total(rows: dict, order: list, key: str) -> int:
    return int(sum(rows[c][key] for c in order))


def _summary(rows: dict, order: list) -> dict:
    """The scores of the characters in `order` pooled: IoU statistics, the worst ten, the round
    pen's baseline, gaps and stray dots, broken strokes, frames, and where the ink misses."""
    scores = np.array([rows[c]["iou"] for c in order])
    stat = (lambda f: float(f(scores)) if len(scores) else None)  # noqa: E731
    return {
        "mean_iou": stat(np.mean), "p10_iou": stat(lambda a: np.percentile(a, 10)), "worst_iou": stat(np.min),
        "worst": [[c, rows[c]["iou"]] for c in sorted(order, key=lambda c: rows[c]["iou"])[:10]],
        "round_pen_mean_iou": float(np.mean([rows[c]["round_pen_iou"] for c in order])) if order else None,
        "round_pen_width_em": ROUND_PEN_EM,
        # the edge figures (glyphs.score.edge_figures): mean excess roughness, median perimeter ratio
        **{f"{who}{k}": _pooled(rows, order, who + k) for who in ("", "round_pen_")
           for k in ("roughness", "perimeter_ratio", "extra_pieces")},
        "beads": _beads(rows, order), "solver": _solver(rows, order),
        # corners of the ink's outline beyond the outlines' own (glyphs.score.corner_count), mean a
        # character, and beads counted on the ink and on the outlines alike (glyphs.score.ink_beads)
        "excess_corners": float(np.mean([rows[c]["excess_corners"] for c in order])) if order else None,
        "ink_beads": _beads(rows, order, "ink_beads"), "outline_beads": _beads(rows, order, "outline_beads"),
        # gaps and stray dots: ink pieces beyond the outlines' count, and specks (glyphs.score.pieces)
        "extra_pieces": _total(rows, order, "extra_pieces"),
        "chars_with_extra_pieces": [c for c in order if rows[c]["extra_pieces"] > 0],
        "specks": _total(rows, order, "specks"), "broken_strokes": _total(rows, order, "broken_strokes"),
        "frames": _total(rows, order, "frames"), "held_frames": _total(rows, order, "held_frames"),
        # where the ink misses: per part of a stroke, missed and outside pixels as fractions of all
        # the outlines' pixels (glyphs.score.error_by_part)
        "error_by_part": _error_by_part([rows[c]["error_by_part"] for c in order]),
        "rows": [{"char": c, "codepoint": f"U+{ord(c):04X}",
                  **{k: rows[c][k] for k in ("iou", "round_pen_iou", "extra_pieces", "specks", "broken_strokes",
                                             "seconds")}}
                 for c in order],
    }


def _pooled(rows: dict, order: list, key: str):
    """A figure over the characters: the sum of pieces, the median of a ratio, else the mean."""
    values = [rows[c][key] for c in order]
    if not values:
        return None
    if key.endswith("pieces"):
        return int(sum(values))
    return float(np.median(values) if key.endswith("ratio") else np.mean(values))


def _beads(rows: dict, order: list, key: str = "beads") -> dict:
    """Stroke family -> [strokes ending in a bead, strokes], over the characters."""
    out: dict = {}
    for c in order:
        for fam, (n_bead, n) in rows[c][key].items():
            tally = out.setdefault(fam, [0, 0])
            tally[0] += n_bead
            tally[1] += n
    return dict(sorted(out.items()))


def _solver(rows: dict, order: list) -> dict:
    """The solver's tallies (Writer.solver) summed over the characters, the penetration's max."""
    out = {k: sum(rows[c]["solver"][k] for c in order) for k in ("steps", "steps_at_q_max", "iterations",
                                                               "substeps")}
    out["max_penetration_mm"] = max((rows[c]["solver"]["max_penetration_mm"] for c in order), default=0.0)
    return out


def _error_by_part(per_char: list) -> dict:
    """Pool error_by_part over characters: {part: {"outline", "missed", "outside"}} as fractions
    of all outline pixels."""
    total = max(sum(e["outline"] for e in per_char), 1)
    return {p: dict(zip(("outline", "missed", "outside"), (sum(e[p][k] for e in per_char) / total for k in range(3))))
            for p in PARTS}


def table(result: dict) -> str:
    lines = [f"bench glyphs: {result['characters']} characters of {result['source']} at {result['size']} px, "
             f"style {result['style']}, seed {result['seed']}, ink {result['ink']}",
             "",
             "| ink IoU against the outlines | value |",
             "|---|---|",
             f"| mean | {result['mean_iou']:.3f} |",
             f"| 10th percentile | {result['p10_iou']:.3f} |",
             f"| worst | {result['worst_iou']:.3f} |",
             f"| (baseline: round pen of width {result['round_pen_width_em'] * 1024:.0f}/1024 em, mean) "
             f"| {result['round_pen_mean_iou']:.3f} |",
             "",
             "| edge figures against the outlines | brush | round pen |",
             "|---|---|---|",
             f"| excess edge roughness (px; contour vs its Gaussian-smoothed copy, sigma {result['sigma']:g} px), mean "
             f"| {result['roughness']:.3f} | {result['round_pen_roughness']:.3f} |",
             f"| perimeter ratio (ink / outlines), median | {result['perimeter_ratio']:.3f} "
             f"| {result['round_pen_perimeter_ratio']:.3f} |",
             f"| ink pieces beyond the outlines' own | {result['extra_pieces']} | {result['round_pen_extra_pieces']} |",
             f"| excess corners (turns of > 45 deg within +-8 px of the contour, ink's minus the outlines'), "
             f"mean a character | {result['excess_corners']:.1f} | |",
             "",
             "beads on the ink (a stroke's last 15% wider than its middle, away from other strokes): "
             + "  ".join(f"{fam} {b}/{n}" for fam, (b, n) in result["ink_beads"].items())
             + " (the outlines themselves, counted alike: "
             + "  ".join(f"{fam} {b}/{n}" for fam, (b, n) in result["outline_beads"].items()) + ")",
             "beads at exits (strokes whose footprint necks and swells again at the end): "
             + "  ".join(f"{fam} {b}/{n}" for fam, (b, n) in result["beads"].items()),
             f"solver: {result['solver']['steps_at_q_max']} of {result['solver']['steps']} steps at q_max, "
             f"{result['solver']['substeps']} sub-steps, deepest penetration "
             f"{result['solver']['max_penetration_mm']:.4f} mm",
             "resolution (the ink written at 2x and 4x the size, downsampled, IoU against it at this size): "
             + "  ".join(f"{c} {a:.3f} {b:.3f}" for c, a, b in result["resolution"]),
             "",
             "worst: " + "  ".join(f"{c} U+{ord(c):04X} {s:.3f}" for c, s in result["worst"]),
             "where the ink misses (fractions of all outline pixels; head and end: first and last 15% of "
             "each stroke's median): " + "  ".join(f"{p} {e['outline']:.2f} of the outlines, missed {e['missed']:.3f}, "
                                                  f"outside {e['outside']:.3f};" for p, e in result["error_by_part"].items()),
             f"gaps and stray dots: {result['extra_pieces']} ink pieces more than the outlines have, in "
             f"{len(result['chars_with_extra_pieces'])} of {result['characters']} characters "
             f"({''.join(result['chars_with_extra_pieces'][:20])}); {result['specks']} specks; "
             f"{result['broken_strokes']} strokes broken (the brush down again after a lift within one stroke); "
             f"{result['held_frames']} of {result['frames']} frames re-stepped deeper (a pressing brush had floated off "
             "the paper or its footprint collapsed)",
             f"{result['chars_per_s']:.2f} characters/s with {result['jobs']} job(s)"]
    if result.get("sheet"):
        lines.append(f"contact sheet: {result['sheet']}")
    for char, why in result["failed"]:
        lines.append(f"failed {char}: {why}")
    return "\n".join(lines)


# --- the end of the pipeline for `bench precision`: a character's ink under solver settings ---

REFERENCE_SOLVE = {"q_max": 100000, "tolerance": 1e-10}   # "no iteration cap", a tight KKT tolerance


def written_ink(glyph, overrides: dict | None = None, size: int = 512, style: str = "kai") -> np.ndarray:
    """(size, size) bool ink mask of glyph written in `style` with a brush whose model fields are
    changed by `overrides` (e.g. {"q_max": 5}), as a batch writes it."""
    st = Style.load(style)
    paper = writing_paper(st, size)
    writer = Writer(paper, st, 0)
    if overrides:
        from ..brush import Brush

        model = writer.brush.model
        for name, value in overrides.items():
            if not hasattr(model, name):
                raise ValueError(f"unknown brush model field {name!r}")
            setattr(model, name, value)
        writer.brush = Brush(model)
    writer.write(glyph)
    return paper.ink() > 0.5


class InkMaskIoU:
    """(overrides) -> IoU of one character's ink, written with those solver settings, against the
    same character written with REFERENCE_SOLVE: how far a solver setting's error carries to the
    ink at the end of the pipeline. The character is 永 from the bundled glyphs (its eight
    basic strokes); the reference is rendered once."""

    def __init__(self, char: str = "永", size: int = 512):
        self.char, self.size = char, size
        self.glyph = load_source("default", char)[char]
        self._ref = None

    def __call__(self, overrides: dict) -> float:
        if self._ref is None:
            self._ref = written_ink(self.glyph, REFERENCE_SOLVE, self.size)
        return iou(written_ink(self.glyph, overrides, self.size), self._ref)


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--source", default=None,
                   help="a source with stroke outlines: mmah:PATH, a Make Me a Hanzi graphics.txt (over 9,000 "
                        "characters: https://github.com/skishore/makemeahanzi); default: the five bundled "
                        "characters' outlines")
    p.add_argument("--size", type=int, default=512, help="px per character (default 512)")
    p.add_argument("--style", default="kai", help="writing style (default kai)")
    p.add_argument("--seed", type=int, default=0, help="seed of the style's variation (default 0)")
    p.add_argument("--count", type=int, default=None, help="only the first N characters")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="worker processes (default: CPU count)")
    p.add_argument("--sheet", metavar="FILE", default="glyphs_sheet.png",
                   help="contact sheet of overlays (default glyphs_sheet.png; '' for none)")
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")
    p.add_argument("--ink", choices=("auto", "geometry", "gl"), default="auto",
                   help="how the ink is made, as for render: auto (the default: geometry for an opaque style), "
                        "geometry or gl")
    p.add_argument("--sigma", type=float, default=EDGE_SIGMA_PX, metavar="PX",
                   help=f"px along the contour the roughness smooths over (default {EDGE_SIGMA_PX:g}; "
                        "12 at 2048 px compares with 6 at 1024)")
    p.add_argument("--resolution", type=int, default=3, metavar="N",
                   help="characters written again at 2 and 4 times the size, their ink compared (default 3; 0: none)")


def handle(args: argparse.Namespace) -> int:
    from .report import check_writable, run_benchmark

    if args.sheet:
        check_writable(args.sheet)
    source = args.source or f"mmah:{outlines_path()}"
    return run_benchmark("glyphs", args, lambda: run(source, args.size, args.count, args.style, args.seed,
                                                     args.jobs, args.sheet or None, resolution=args.resolution,
                                                     ink=args.ink, sigma=args.sigma),
                         table)
