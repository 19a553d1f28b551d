"""The `brushwork` command line: benchmarks and the demo.

    brushwork bench stability [--json FILE] [--quick] [--seed N]
    brushwork bench solver [--json FILE] [--preset P] [--frames N] [--repeats N]
    brushwork bench precision [--json FILE] [--out DIR] [--quick] [--repeats N] [--no-peers]
    brushwork demo [-o FILE]

New commands plug in through COMMANDS (top level) and BENCHMARKS (under `bench`): each maps a
name to (help, add_arguments, handler); a handler takes the parsed arguments and returns the exit
code. ValueError and OSError from a handler print one `brushwork: error: ...` line and exit 2.
"""
from __future__ import annotations

import argparse
import sys
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
                                                      repeats=args.repeats), solver.table)


def _render_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")
    p.add_argument("--px", type=int, default=2048, help="canvas size in pixels (default 2048)")
    p.add_argument("--frames", type=int, default=320, help="frames of the stroke (default 320)")
    p.add_argument("--repeats", type=int, default=3, help="runs per scene, best kept (default 3)")


def _render(args: argparse.Namespace) -> int:
    from .bench import render

    return _report("render", args, lambda: render.run(px=args.px, frames=args.frames, repeats=args.repeats,
                                                      progress=_progress), render.table)


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


# benchmarks not written yet: accept anything, say so, exit 2
def _pending_args(p: argparse.ArgumentParser) -> None:
    p.set_defaults(accepts_extra=True)


def _pending(what: str) -> Handler:
    def handler(args: argparse.Namespace) -> int:
        print(f"brushwork: not implemented yet: {what}", file=sys.stderr)
        return 2
    return handler


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


def _params(args: argparse.Namespace) -> int:
    from .bench.report import parameter_table

    _check_preset(args.preset)
    print(parameter_table(args.preset))
    return 0


# the benchmarks under `brushwork bench`: name -> (help, add_arguments, handler)
BENCHMARKS: dict[str, tuple[str, AddArgs, Handler]] = {
    "stability": ("solver robustness on hard and odd motions", _stability_args, _stability),
    "solver": ("solver speed, carried vs fresh Hessian", _solver_args, _solver),
    "footprint": ("footprint area and width against press depth and tilt", _footprint_args, _footprint),
    "render": ("deposit cost per frame, minimal vs full scene", _render_args, _render),
    "glyphs": ("(not implemented yet)", _pending_args, _pending("bench glyphs")),
    "precision": ("error against run time per frame, ours and peer solvers", _precision_args, _precision),
}


def _bench_args(p: argparse.ArgumentParser) -> None:
    sub = p.add_subparsers(dest="benchmark", metavar="BENCHMARK")
    sub.required = True
    for name, (help_text, add_args, handler) in BENCHMARKS.items():
        q = sub.add_parser(name, help=help_text, description=help_text)
        add_args(q)
        q.set_defaults(handler=handler)


# the top-level commands: name -> (help, add_arguments, handler or None when subcommands set it)
COMMANDS: dict[str, tuple[str, AddArgs, Optional[Handler]]] = {
    "bench": ("run a benchmark", _bench_args, None),
    "demo": ("draw the demo", _demo_args, _demo),
    "params": ("print every brush parameter with its unit, range and value", _params_args, _params),
    "gallery": ("render the seed's Figure 11 sample strokes to one PNG", _gallery_args, _gallery),
}


def build_parser() -> argparse.ArgumentParser:
    """The argparse parser of the whole CLI."""
    from . import __version__

    parser = argparse.ArgumentParser(prog="brushwork", description=__doc__.splitlines()[0])
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
        # placeholders take any arguments; everything else must parse exactly
        args, extra = parser.parse_known_args(argv)
        if extra and not getattr(args, "accepts_extra", False):
            parser.error(f"unrecognized arguments: {' '.join(extra)}")
        return int(args.handler(args))
    # user-facing failures: one line, exit 2
    except (ValueError, OSError) as exc:
        print(f"brushwork: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("brushwork: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
