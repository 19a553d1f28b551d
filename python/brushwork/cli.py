"""The `brushwork` command line: rendering characters, benchmarks and the demo.

    brushwork render TEXT -o FILE [--size N] [--style S] [--source SPEC] [--seed N] [--bits 8|16] [--transparent] [--stats FILE] [--plans DIR]
    brushwork batch --chars TEXT | --charset FILE --out DIR [--jobs N] [--size N] [--source SPEC] [--sheet FILE] [--plans DIR]
    brushwork fit --chars TEXT | --charset FILE --source mmah:PATH --out DIR [--style S] [--jobs N] [--executor local|ray]
    brushwork learn --plans DIR --source mmah:PATH -o HAND.json [--style S]
    brushwork font --chars TEXT | --charset FILE -o OUT.{otf,ttf,woff2,ufo} [--style S] [--jobs N] [--executor local|ray]
    brushwork bench glyphs --source mmah:PATH [--size 512] [--count N] [--jobs N] [--sheet FILE] [--json FILE]
    brushwork bench batch [--source SPEC] [--count 200] [--size 1024] [--jobs 2] [--json FILE]
    brushwork bench stability [--json FILE] [--quick] [--seed N]
    brushwork bench solver [--json FILE] [--preset P] [--frames N] [--repeats N] [--tufts K ...]
    brushwork bench precision [--json FILE] [--out DIR] [--quick] [--repeats N] [--no-peers]
    brushwork bench font [--count 60] [--jobs 2] [--executor local|ray] [--json FILE]
    brushwork bench fuzz [--n N] [--seed N] [--render-every N] [--json FILE]
    brushwork bench texture [--chars TEXT] [--size 512] [--json FILE]
    brushwork outline MESH -o FILE [--size N] [--azimuth DEG] [--elevation DEG] [--style S] [--camera-json FILE] ...
    brushwork bench outline [--meshes DIR] [--json FILE]
    brushwork demo [-o FILE]
    brushwork paint [--port P] [--host H --token T] [--size W H] [--preset P] [--log-dir DIR]
    brushwork replay LOG -o FILE [--size N]
    brushwork bench paint [--samples N] [--json FILE]

New commands plug in through COMMANDS (top level) and BENCHMARKS (under `bench`): each maps a
name to (help, add_arguments, handler); a handler takes the parsed arguments and returns the exit
code. ValueError and OSError from a handler print one `brushwork: error: ...` line and exit 2.
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from typing import Callable, Optional

Handler = Callable[[argparse.Namespace], int]
AddArgs = Callable[[argparse.ArgumentParser], None]


# bench stability
def _stability_args(p: argparse.ArgumentParser) -> None:
    from .bench import stability

    stability.add_arguments(p)


def _stability(args: argparse.Namespace) -> int:
    from .bench import stability

    return stability.handle(args)


# bench solver
def _solver_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")
    p.add_argument("--preset", default="medium", help="brush preset (default medium)")
    p.add_argument("--frames", type=int, default=320, help="frames of the stroke (default 320)")
    p.add_argument("--repeats", type=int, default=5, help="runs per mode, best kept (default 5)")
    p.add_argument("--tufts", type=int, nargs="+", metavar="K",
                   help="also time the brush split into K tufts (the seed's Table 1: 1 3 5)")


def _check_preset(name: str) -> None:
    from . import BrushModel

    if name not in BrushModel.presets():
        raise ValueError(f"unknown preset {name!r} (choose from {', '.join(BrushModel.presets())})")


def _report(name: str, args: argparse.Namespace, run, table) -> int:
    """Run a benchmark: fail on an unwritable --json target before the run, not after; print
    its table; write its JSON."""
    from .bench import report

    if args.json:
        report.check_writable(args.json)
    result = run()
    print(table(result))
    if args.json:
        report.write_json(args.json, {"benchmark": name, **result})
    return 0


def _progress(msg: str) -> None:
    print(f"  {msg}", file=sys.stderr)


def _solver(args: argparse.Namespace) -> int:
    from .bench import solver

    _check_preset(args.preset)
    return _report("solver", args, lambda: solver.run(preset=args.preset, frames=args.frames,
                                                      repeats=args.repeats, tufts=args.tufts), solver.table)


def _render_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")
    p.add_argument("--px", type=int, default=2048, help="canvas size in pixels (default 2048)")
    p.add_argument("--frames", type=int, default=320, help="frames of the stroke (default 320)")
    p.add_argument("--repeats", type=int, default=3, help="runs per scene, best kept (default 3)")


def _render(args: argparse.Namespace) -> int:
    from .bench import render

    def run() -> dict:
        result = render.run(px=args.px, frames=args.frames, repeats=args.repeats, progress=_progress)
        result["mesh"] = render.mesh_sweep(frames=args.frames, repeats=args.repeats, progress=_progress)
        return result

    return _report("render", args, run, render.table)


def _footprint_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")
    p.add_argument("--preset", default="medium", help="brush preset (default medium)")
    p.add_argument("--set", metavar="NAME=VALUE", action="append", default=[],
                   help="override a model field, e.g. --set internal_friction=0.3 (repeatable)")


def _parse_settings(items: list[str]) -> dict:
    """--set NAME=VALUE items -> {name: bool | int | float}."""
    settings = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep:
            raise ValueError(f"--set {item!r}: expected NAME=VALUE")
        text = value.strip().lower()
        if text in ("true", "false"):
            settings[name.strip()] = text == "true"
        else:
            settings[name.strip()] = int(text) if text.lstrip("-").isdigit() else float(text)
    return settings


def _footprint(args: argparse.Namespace) -> int:
    from .bench import footprint

    _check_preset(args.preset)
    settings = _parse_settings(args.set)
    return _report("footprint", args, lambda: footprint.run(args.preset, progress=_progress, settings=settings),
                   footprint.table)


# bench precision
def _precision_args(p: argparse.ArgumentParser) -> None:
    from .bench import precision

    precision.add_arguments(p)


def _precision(args: argparse.Namespace) -> int:
    from .bench import precision

    return precision.handle(args)


# rendering characters: render, batch, bench glyphs, bench batch
SOURCE_HELP = ("where the strokes come from: default (the bundled glyphs, then KanjiVG when installed), "
               "kanjivg, kanjivg:DIR, mmah:PATH or glyphs:DIR; several joined by + take each character "
               "from the first that has it (default+mmah:PATH)")


def _look_args(p: argparse.ArgumentParser, size: int = 1024) -> None:
    """The options every rendering command shares: size, style, source, seed."""
    from .writing import Style

    p.add_argument("--size", type=int, default=size, help=f"px per character, 16..8192 (default {size})")
    p.add_argument("--style", default="kai", help=f"writing style: {', '.join(Style.names())} or a JSON file "
                                                  "(default kai)")
    p.add_argument("--source", default="default", help=SOURCE_HELP)
    p.add_argument("--seed", type=int, default=0, help="seed of the style's variation (default 0)")


def _image_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--samples", type=int, default=None,
                   help="multisampling of the strokes: 1, 2, 4 or 8 (default: the style's, 4); "
                        "1 is ~2.5x faster on a software renderer, its edges stepped at the pixel")
    p.add_argument("--bits", type=int, default=8, help="PNG bits per channel, 8 or 16 (default 8)")
    p.add_argument("--transparent", action="store_true", help="ink on transparency instead of white")


def _plans_arg(p: argparse.ArgumentParser) -> None:
    p.add_argument("--plans", metavar="DIR", help="write each character from its plan file in DIR (brushwork fit), "
                                                  "drawn in the source's em box")


def _render_text_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("text", help="the characters to write, left to right on one image (spaces ignored)")
    p.add_argument("-o", "--output", metavar="FILE", required=True,
                   help="the image to write, in the format its suffix names: .png .jpg .jpeg .tif .tiff .bmp .webp")
    _look_args(p)
    _image_args(p)
    _plans_arg(p)
    p.add_argument("--stats", metavar="FILE", help="also write the writing's figures as JSON to FILE: frames, "
                                                   "solver steps at the iteration cap q_max, sub-steps, deepest "
                                                   "penetration (mm), beads at exits by stroke family")


def _render_text(args: argparse.Namespace) -> int:
    from .batch import check_request, text_chars, text_paper, writing_stats
    from .files import check_image_path, save_paper
    from .writing import Style

    chars = text_chars(args.text)
    check_request(chars, args.size, args.bits, args.samples, args.seed)
    style = Style.load(args.style)
    check_image_path(args.output, args.bits, args.transparent)     # before the work, not after
    if args.stats:
        from .bench.report import check_writable, write_json

        check_writable(args.stats)
    glyphs = _load_glyphs(args.source, "".join(dict.fromkeys(chars)))
    t0 = time.perf_counter()
    counts: dict = {}
    paper = text_paper([glyphs[c] for c in chars], args.size, style, args.seed, args.samples, counts,
                       plans=args.plans)
    path = save_paper(paper, args.output, bits=args.bits,
                      background="transparent" if args.transparent else "white")
    print(f"wrote {path} ({_plural(len(chars), 'character')}, {paper.width_px} x {paper.height_px} px, "
          f"{time.perf_counter() - t0:.1f} s)")
    if args.stats:
        write_json(args.stats, {"text": "".join(chars), "size": args.size, "style": style.name, **writing_stats(counts)})
    return 0


def _plural(n: int, noun: str) -> str:
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"


def _load_glyphs(source: str, chars: str) -> dict:
    """The glyphs of chars from the source; an unknown character says how to add one."""
    from .glyphs import GlyphError, load_source
    from .glyphs.sources import add_source_hint

    try:
        return load_source(source, chars)
    except GlyphError as err:
        if getattr(err, "unknown", False):        # say how to add one (batch says it in its summary)
            raise ValueError(f"{err}; {add_source_hint(source)}") from err
        raise


def _batch_args(p: argparse.ArgumentParser) -> None:
    what = p.add_mutually_exclusive_group(required=True)
    what.add_argument("--chars", metavar="TEXT", help="the characters to render")
    what.add_argument("--charset", metavar="FILE", help="a UTF-8 file of characters (whitespace ignored), "
                                                        "or a built-in set: gb2312, gb2312-1, gb2312-2")
    p.add_argument("--out", metavar="DIR", required=True, help="folder for the U+XXXX.png files (made if missing)")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                   help=f"worker processes (default: the CPU count, {os.cpu_count()})")
    p.add_argument("--sheet", metavar="FILE", help="also write a contact sheet of the characters to FILE, "
                                                   "beside a reference Kai font when one is installed")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    _plans_arg(p)
    p.add_argument("--executor", default="local", help="local (worker processes) or ray (a Ray cluster: "
                                                       "RAY_ADDRESS, else a local one; pip install brushwork[ray])")
    _look_args(p)
    _image_args(p)


def _batch(args: argparse.Namespace) -> int:
    from . import batch

    chars = batch.parse_charset(args.chars) if args.chars is not None else batch.read_charset(args.charset)
    if not chars:
        raise ValueError("no characters to render")
    if args.sheet:
        from .bench.report import check_writable

        # the batch makes its --out folder anyway; made first, a sheet inside it checks as writable
        os.makedirs(args.out, exist_ok=True)
        check_writable(args.sheet)
    # a batch stopped by SIGTERM (a scheduler's kill, `timeout`) ends like Ctrl-C: workers stopped,
    # the summary printed; finished files are whole (atomic writes) and a rerun resumes
    import signal

    def _stop(signum, frame):
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, _stop)
    res = batch.run_batch(chars, args.out, source=args.source, jobs=args.jobs, size=args.size, style=args.style,
                          seed=args.seed, bits=args.bits, background="transparent" if args.transparent else "white",
                          progress=not args.no_progress, samples=args.samples, executor=args.executor,
                          plans=args.plans)
    failures = batch.write_failures(res, args.out)
    print(batch.summary(res, failures))
    if args.sheet and not res.interrupted:
        from .sheet import contact_sheet

        failed = dict(res.failed)
        print(f"wrote {contact_sheet(batch.sheet_cells(chars, args.out, failed), args.sheet)}")
    if res.interrupted:
        return 130
    if res.failed:
        print(f"brushwork: error: {_plural(len(res.failed), 'character')} failed (listed in {failures})",
              file=sys.stderr)
        return 2
    return 0


def _bench_glyphs_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--source", required=True, help="a source with stroke outlines: mmah:PATH")
    p.add_argument("--size", type=int, default=512, help="px per character (default 512)")
    p.add_argument("--style", default="kai", help="writing style (default kai)")
    p.add_argument("--seed", type=int, default=0, help="seed of the style's variation (default 0)")
    p.add_argument("--count", type=int, default=None, help="only the first N characters")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="worker processes (default: CPU count)")
    p.add_argument("--sheet", metavar="FILE", default="glyphs_sheet.png",
                   help="contact sheet of overlays (default glyphs_sheet.png; '' for none)")
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")


def _bench_glyphs(args: argparse.Namespace) -> int:
    from .bench import glyphs

    if args.sheet:
        from .bench.report import check_writable

        check_writable(args.sheet)
    return _report("glyphs", args, lambda: glyphs.run(args.source, args.size, args.count, args.style, args.seed,
                                                      args.jobs, args.sheet or None), glyphs.table)


def _bench_batch_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--source", default="default", help=SOURCE_HELP)
    p.add_argument("--count", type=int, default=200,
                   help="characters, spread over GB2312 (default 200: a sample of the set's mix of simple and "
                        "busy characters, long enough that the workers' start-up weighs as little as in a real batch)")
    p.add_argument("--size", type=int, default=1024, help="px per character (default 1024)")
    p.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    p.add_argument("--style", default="kai", help="writing style (default kai)")
    p.add_argument("--samples", type=int, default=None, help="multisampling: 1, 2, 4 or 8 (default: the style's)")
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")


def _bench_batch(args: argparse.Namespace) -> int:
    from .batch import check_samples
    from .bench import glyphs

    check_samples(args.samples)
    return _report("batch", args, lambda: glyphs.run_batch_bench(args.source, args.count, args.size, args.jobs,
                                                                 args.style, samples=args.samples),
                   glyphs.batch_table)


# font (brushwork.font: its options and handler live there)
def _font_args(p: argparse.ArgumentParser) -> None:
    from .font import cli

    cli.add_arguments(p)


def _font(args: argparse.Namespace) -> int:
    from .font import cli

    return cli.handle(args)


def _bench_font_args(p: argparse.ArgumentParser) -> None:
    from .bench import font

    font.add_arguments(p)


def _bench_font(args: argparse.Namespace) -> int:
    from .bench import font

    tols = [float(t) for t in args.tolerances.split(",") if t.strip()]
    return _report("font", args, lambda: font.run(args.count, args.jobs, args.executor, args.style, tols), font.table)


# demo (brushwork.demo is someone else's module: imported only when asked for)
def _demo_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("-o", "--output", metavar="FILE", default=None,
                   help="the image the demo writes (default: the demo's own, brush_demo.png)")


def _demo(args: argparse.Namespace) -> int:
    try:
        from . import demo
    except ModuleNotFoundError as exc:
        if exc.name not in ("brushwork.demo",):
            raise
        print("brushwork: error: the demo is not available in this build (no brushwork.demo)",
              file=sys.stderr)
        return 2
    # without -o the demo picks its own file name
    rc = demo.main(args.output) if args.output else demo.main()
    return rc if isinstance(rc, int) else 0


def _gallery_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("-o", "--output", metavar="FILE", default="gallery.png",
                   help="the PNG to write (default gallery.png)")
    p.add_argument("--px-per-mm", type=float, default=10.0,
                   help="resolution of the paper (default 10 px/mm: 2100 x 1500 px)")
    p.add_argument("--views", metavar="FILE", default=None,
                   help="also write the brush view (shaded, outlined, transparent) to FILE")


def _gallery(args: argparse.Namespace) -> int:
    from .gallery import render_gallery

    if not 1.0 <= args.px_per_mm <= 40.0:
        raise ValueError(f"--px-per-mm {args.px_per_mm}: expected 1..40")
    path = render_gallery(args.output, args.px_per_mm, progress=_progress)
    print(f"wrote {path}")
    if args.views:
        from .gallery import render_views

        print(f"wrote {render_views(args.views)}")
    return 0


def _params_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--preset", default="medium", help="brush preset whose values to show (default medium)")
    p.add_argument("--style", action="store_true", help="the fields of a style file instead of the brush's")


def _params(args: argparse.Namespace) -> int:
    from .bench.report import parameter_table
    from .writing import style_table

    _check_preset(args.preset)
    print(style_table() if args.style else parameter_table(args.preset))
    return 0


# bench fuzz
def _fuzz_args(p: argparse.ArgumentParser) -> None:
    from .bench import fuzz

    fuzz.add_arguments(p)


def _fuzz(args: argparse.Namespace) -> int:
    from .bench import fuzz

    if args.n < 1 or args.render_every < 1:
        raise ValueError(f"--n {args.n} --render-every {args.render_every}: expected >= 1")
    run = lambda: fuzz.run(args.n, args.seed, args.render_every, progress=_progress)  # noqa: E731
    rc = _report("fuzz", args, run, fuzz.table)
    return rc


# bench texture
def _texture_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")
    p.add_argument("--chars", default="永和九年", help="characters of the exits measure (default 永和九年)")
    p.add_argument("--size", type=int, default=512, help="px per character, 64..2048 (default 512)")


def _texture(args: argparse.Namespace) -> int:
    from .bench import texture

    if not 64 <= args.size <= 2048 or not args.chars.strip():
        raise ValueError(f"--size {args.size} --chars {args.chars!r}: expected 64..2048 px and some characters")
    return _report("texture", args, lambda: texture.run("".join(args.chars.split()), args.size, _progress),
                   texture.table)
# outline (3-D meshes) and bench outline: brushwork.outline3d
def _outline_args(p: argparse.ArgumentParser) -> None:
    from .outline3d import command

    command.add_arguments(p)


def _outline(args: argparse.Namespace) -> int:
    from .outline3d import command

    return command.run(args)


def _bench_outline_args(p: argparse.ArgumentParser) -> None:
    from .bench import outline

    outline.add_arguments(p)


def _bench_outline(args: argparse.Namespace) -> int:
    from .bench import outline

    return _report("outline", args, lambda: outline.run(args, progress=_progress), outline.table)


# paint, replay, bench paint: brushwork.paint.commands, imported when run (aiohttp is an extra)
def _paint(name: str) -> Callable:
    def call(arg):
        from .paint import commands

        return getattr(commands, name)(arg)

    return call


# the benchmarks under `brushwork bench`: name -> (help, add_arguments, handler)
BENCHMARKS: dict[str, tuple[str, AddArgs, Handler]] = {
    "stability": ("solver robustness on hard and odd motions", _stability_args, _stability),
    "solver": ("solver speed, carried vs fresh Hessian", _solver_args, _solver),
    "footprint": ("footprint area and width against press depth and tilt", _footprint_args, _footprint),
    "render": ("deposit cost per frame, minimal vs full scene", _render_args, _render),
    "glyphs": ("the driver's ink against a source's stroke outlines (IoU), with a contact sheet",
               _bench_glyphs_args, _bench_glyphs),
    "batch": ("characters per second of `brushwork batch`, and where the time goes", _bench_batch_args,
              _bench_batch),
    "precision": ("error against run time per frame, ours and peer solvers", _precision_args, _precision),
    "font": ("points, size, build time and FreeType-vs-render fidelity of `brushwork font`", _bench_font_args,
             _bench_font),
    "fuzz": ("glyph files, style files, SVG paths and command lines, valid and broken: failures per kind",
             _fuzz_args, _fuzz),
    "texture": ("dry-brush streaks at exits (xing vs kai), repeats of the texture, agreement across resolutions",
                _texture_args, _texture),
    "outline": ("3-D outlines of meshes: silhouette recall and precision, chains, time per phase, orbit coherence",
                _bench_outline_args, _bench_outline),
    "paint": ("pen sample to ink through `brushwork paint`'s WebSocket: p50, p95 ms; simulated fps",
              _paint("bench_args"), _paint("bench")),
}


def _bench_args(p: argparse.ArgumentParser) -> None:
    sub = p.add_subparsers(dest="benchmark", metavar="BENCHMARK")
    sub.required = True
    for name, (help_text, add_args, handler) in BENCHMARKS.items():
        q = sub.add_parser(name, help=help_text, description=help_text)
        add_args(q)
        q.set_defaults(handler=handler)


def _plans(name: str) -> Callable:
    def call(arg):
        from . import plans

        return getattr(plans, name)(arg)
    return call


# the top-level commands: name -> (help, add_arguments, handler or None when subcommands set it)
COMMANDS: dict[str, tuple[str, AddArgs, Optional[Handler]]] = {
    "render": ("write characters with the brush to one PNG", _render_text_args, _render_text),
    "batch": ("render many characters, one PNG each, in parallel; resumable", _batch_args, _batch),
    "fit": ("fit each character's stroke plans to its outlines (mmah: sources); resumable",
            _plans("fit_arguments"), _plans("fit_handle")),
    "learn": ("learn a hand (a style's plans from medians alone) from fitted plans", _plans("learn_arguments"),
              _plans("learn_handle")),
    "font": ("build an OTF, TTF, WOFF2 or UFO font of characters written by the brush; resumable", _font_args, _font),
    "bench": ("run a benchmark", _bench_args, None),
    "demo": ("draw the demo", _demo_args, _demo),
    "params": ("print every brush parameter (or, with --style, style field) with its unit, range and value",
               _params_args, _params),
    "gallery": ("render the seed's Figure 11 sample strokes to one PNG", _gallery_args, _gallery),
    "outline": ("draw a 3-D mesh's visible feature lines with the brush", _outline_args, _outline),
    "paint": ("paint with a pen (or mouse) in the browser: a local web app", _paint("paint_args"), _paint("paint")),
    "replay": ("render the motion log of a painting to an image", _paint("replay_args"), _paint("replay")),
}


class _Parser(argparse.ArgumentParser):
    """argparse with a usage error in one line: `brushwork: error: ...` and exit 2."""

    def error(self, message: str):
        self.exit(2, f"brushwork: error: {self.prog}: {' '.join(message.split())}\n")


def build_parser() -> argparse.ArgumentParser:
    """The argparse parser of the whole CLI (its subcommands' parsers of the same one-line kind)."""
    from . import __version__

    parser = _Parser(prog="brushwork", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"brushwork {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for name, (help_text, add_args, handler) in COMMANDS.items():
        p = sub.add_parser(name, help=help_text, description=help_text)
        add_args(p)
        if handler is not None:
            p.set_defaults(handler=handler)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Parse `argv` (default sys.argv[1:]), run the command, return its exit code."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        return int(args.handler(args))
    except BrokenPipeError:
        # the reader closed our output (`brushwork params | head`): stop quietly, as a filter does
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    # user-facing failures: one line, exit 2
    except (ValueError, OSError) as exc:
        print(f"brushwork: error: {_one_line(exc)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("brushwork: interrupted", file=sys.stderr)
        return 130


def _one_line(exc: Exception) -> str:
    """The error as one plain line: an OSError that carries its file names it, without errno."""
    if isinstance(exc, OSError) and exc.filename is not None:
        from .files import os_error_why

        return f"{exc.filename}: {os_error_why(exc)}"
    if isinstance(exc, OSError) and exc.strerror:
        return " ".join(exc.strerror.split())
    return " ".join(str(exc).split())


if __name__ == "__main__":
    sys.exit(main())
