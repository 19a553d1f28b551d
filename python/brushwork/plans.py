"""`brushwork fit` and `brushwork learn`: plans fitted to a source's stroke outlines, one file a
character, and a hand learned from them (writing/fit.py, writing/hand.py).

fit: for each character (skipping those whose plan file exists and parses), the plans of its
strokes fitted in writing order; printed: seconds a character on one core and the IoU of the
fitted ink (the GL-free grid) against the outlines at 512 px.
"""
from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

SCORE_PX = 512       # px of the IoU fit reports

_JOB: dict = {}


def fit_arguments(p: argparse.ArgumentParser) -> None:
    what = p.add_mutually_exclusive_group(required=True)
    what.add_argument("--chars", metavar="TEXT", help="the characters to fit")
    what.add_argument("--charset", metavar="FILE", help="a UTF-8 file of characters (whitespace ignored)")
    p.add_argument("--source", required=True, help="a source with stroke outlines: mmah:PATH")
    p.add_argument("--out", metavar="DIR", required=True, help="folder for the U+XXXX.json plan files (made if missing)")
    p.add_argument("--style", default="kai", help="the style whose brush and em box the plans are for (default kai)")
    p.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    p.add_argument("--executor", default="local", help="local (worker processes) or ray")
    p.add_argument("--no-progress", action="store_true", help="no progress line a character")
    p.add_argument("--regions", action="store_true",
                   help="print where the fitted ink misses the outlines, by stroke family and region")


def _init(style: str, out: str) -> None:
    from .writing import Style
    from .writing.fit import GlyphFitter

    _JOB.update(fitter=GlyphFitter(Style.load(style)), out=out, style=Style.load(style))


def _fit_one(task: tuple) -> tuple:
    """(char, glyph) -> (char, iou at SCORE_PX or None, CPU seconds, error line or None, the
    fit's misses by region: {family: tally})."""
    from .glyphs.score import iou, outline_mask
    from .writing.planned import InkGrid, PlanWriter

    char, glyph = task
    t0 = time.process_time()
    _JOB["fitter"].regions = {}
    try:
        plan = _JOB["fitter"].fit(glyph)
        grid = InkGrid(SCORE_PX, _JOB["style"].em_mm)
        PlanWriter(_JOB["style"], grid).write(glyph, plan)
        plan.iou = iou(grid.ink(), outline_mask(glyph, SCORE_PX))
        plan.save(_JOB["out"])
        return char, plan.iou, time.process_time() - t0, None, _JOB["fitter"].regions
    except ValueError as err:
        return char, None, time.process_time() - t0, " ".join(str(err).split()), {}


def _done(out: str, glyphs: dict) -> dict:
    """{char: iou} of the characters whose plan file exists and parses."""
    from .writing.plan import PlanError, load_plan

    done = {}
    for c, g in glyphs.items():
        try:
            done[c] = load_plan(out, c, len(g.strokes)).iou
        except PlanError:
            pass
    return done


def _fit_glyphs(args: argparse.Namespace) -> tuple[dict, dict]:
    """({char: glyph} to fit, {char: one-line error}) for the characters the arguments name."""
    from .glyphs import load_source
    from .glyphs.charsets import parse_charset, read_charset
    from .glyphs.score import has_outlines
    from .writing import Style

    chars = parse_charset(args.chars) if args.chars is not None else read_charset(args.charset)
    if not chars:
        raise ValueError("--chars: no characters to fit")
    if args.jobs < 1:
        raise ValueError(f"--jobs {args.jobs}: expected 1 or more")
    Style.load(args.style)
    errors: list = []
    glyphs = load_source(args.source, chars, errors=errors)
    bad = {c: f"{c}: no stroke outlines to fit to (only Make Me a Hanzi's mmah: sources have them)"
           for c, g in glyphs.items() if not has_outlines(g)}
    bad.update({str(getattr(e, "char", "?")): " ".join(str(e).split()) for e in errors})
    return {c: g for c, g in glyphs.items() if c not in bad}, bad


def fit_handle(args: argparse.Namespace) -> int:
    from .pool import parallel_map
    from .writing.regions import add_tally, table

    glyphs, bad = _fit_glyphs(args)
    os.makedirs(args.out, exist_ok=True)
    done = _done(args.out, glyphs)
    tasks = [(c, g) for c, g in glyphs.items() if c not in done]
    scores, seconds, regions = dict(done), [], {}
    for n, (char, score, sec, err, tallies) in enumerate(parallel_map(_fit_one, tasks, args.jobs, _init,
                                                              (args.style, args.out), args.executor), 1):
        if err is not None:
            bad[char] = err
        else:
            scores[char] = score
            seconds.append(sec)
            for fam, tally in tallies.items():
                add_tally(regions, fam, tally)
        if not args.no_progress:
            print(f"{n}/{len(tasks)} {char} "
                  + (f"IoU {score:.3f} {sec:.1f} s" if err is None else f"failed: {err}"), file=sys.stderr)
    _fit_summary(scores, seconds, len(done), bad)
    if args.regions and regions:
        print("\n".join(table(regions)))
    return 2 if bad else 0


def _fit_summary(scores: dict, seconds: list, skipped: int, bad: dict) -> None:
    vals = np.array([v for v in scores.values() if v is not None])
    if len(vals):
        worst = min((v, c) for c, v in scores.items() if v is not None)
        print(f"fitted {len(seconds)} characters ({skipped} already fitted), "
              f"{np.mean(seconds) if seconds else 0.0:.1f} s a character on one core; IoU at {SCORE_PX} px "
              f"mean {vals.mean():.3f}, p10 {np.percentile(vals, 10):.3f}, worst {worst[0]:.3f} ({worst[1]})")
    for line in bad.values():
        print(f"brushwork: error: {line}", file=sys.stderr)


def learn_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--plans", metavar="DIR", required=True, help="folder of fitted plan files (brushwork fit)")
    p.add_argument("--source", required=True, help="the source the plans were fitted to (its medians)")
    p.add_argument("-o", "--output", metavar="FILE", required=True, help="the hand file to write (JSON)")
    p.add_argument("--style", default="kai", help="the style the plans were fitted with (default kai)")


def learn_handle(args: argparse.Namespace) -> int:
    from .glyphs import load_source
    from .writing import Style
    from .writing.hand import learn_hand
    from .writing.plan import PlanError, load_plan

    if not os.path.isdir(args.plans):
        raise ValueError(f"--plans {args.plans}: not a folder")
    names = sorted(f for f in os.listdir(args.plans) if f.startswith("U+") and f.endswith(".json"))
    chars = "".join(chr(int(f[2:-5], 16)) for f in names)
    if not chars:
        raise ValueError(f"--plans {args.plans}: no plan files (U+XXXX.json)")
    st = Style.load(args.style)
    glyphs = load_source(args.source, chars, errors=[])
    pairs = []
    for c in chars:
        if c in glyphs:
            try:
                pairs.append((glyphs[c], load_plan(args.plans, c, len(glyphs[c].strokes))))
            except PlanError as err:
                print(f"brushwork: warning: {err}", file=sys.stderr)
    if not pairs:
        raise ValueError(f"--plans {args.plans}: no plan matches a character of {args.source}")
    hand = learn_hand(pairs, st)
    hand.save(args.output)
    print(f"wrote {args.output} ({len(pairs)} characters, {hand.strokes} strokes)")
    return 0
