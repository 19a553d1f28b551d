"""The `brushwork` command line: rendering characters, benchmarks and the demo.

    brushwork render TEXT -o FILE [--size N] [--style S] [--source SPEC] [--seed N] [--bits 8|16] [--transparent] [--stats FILE] [--plans DIR]
    brushwork batch --chars TEXT | --charset FILE --out DIR [--jobs N] [--size N] [--source SPEC] [--sheet FILE] [--plans DIR]
    brushwork fit --chars TEXT | --charset FILE --source mmah:PATH --out DIR [--style S] [--jobs N] [--executor local|ray]
    brushwork learn --plans DIR --source mmah:PATH -o HAND.json [--style S]
    brushwork font --chars TEXT | --charset FILE -o OUT.{otf,ttf,woff2,ufo} [--style S] [--jobs N] [--executor local|ray]
    brushwork bench glyphs [--source mmah:PATH] [--size 512] [--count N] [--jobs N] [--sheet FILE] [--json FILE]
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
name to its help and the module that owns it, which exports add_arguments(parser) and
handle(args) (a module with several commands names its pair). A handler takes the parsed arguments
and returns the exit code; ValueError and OSError from a handler print one `brushwork: error: ...`
line and exit 2. `args.entry` is this module's `main`, for the benchmarks that drive the command line.
"""
from __future__ import annotations

import argparse
import importlib
import os
import signal
import sys
import threading
from typing import NamedTuple


class Command(NamedTuple):
    """A command's help and where it lives: module (relative to brushwork), its argument and
    handler functions (no handler: its subcommands set theirs)."""
    help: str
    module: str
    add_arguments: str = "add_arguments"
    handle: str = "handle"

    def attach(self, sub, name: str) -> argparse.ArgumentParser:
        """The command's parser under `sub`, its options added and its handler set."""
        module = importlib.import_module(f"brushwork.{self.module}")
        p = sub.add_parser(name, help=self.help, description=self.help)
        getattr(module, self.add_arguments)(p)
        if self.handle:
            p.set_defaults(handler=getattr(module, self.handle))
        return p


# the benchmarks under `brushwork bench`
BENCHMARKS: dict[str, Command] = {
    "stability": Command("solver robustness on hard and odd motions", "bench.stability"),
    "solver": Command("solver speed, carried vs fresh Hessian", "bench.solver"),
    "footprint": Command("footprint area and width against press depth and tilt", "bench.footprint"),
    "render": Command("deposit cost per frame, minimal vs full scene", "bench.render"),
    "glyphs": Command("the driver's ink against a source's stroke outlines (IoU), with a contact sheet",
                      "bench.glyphs"),
    "batch": Command("characters per second of `brushwork batch`, and where the time goes", "bench.batch"),
    "precision": Command("error against run time per frame, ours and peer solvers", "bench.precision"),
    "font": Command("points, size, build time and FreeType-vs-render fidelity of `brushwork font`", "bench.font"),
    "fuzz": Command("glyph files, style files, SVG paths and command lines, valid and broken: failures per kind",
                    "bench.fuzz"),
    "texture": Command("dry-brush streaks at exits (xing vs kai), repeats of the texture, agreement across "
                       "resolutions", "bench.texture"),
    "outline": Command("3-D outlines of meshes: silhouette recall and precision, chains, time per phase, orbit "
                       "coherence", "bench.outline"),
    "paint": Command("pen sample to ink through `brushwork paint`'s WebSocket: p50, p95 ms; simulated fps",
                     "paint.commands", "bench_args", "bench"),
}


def _bench_args(p: argparse.ArgumentParser) -> None:
    sub = p.add_subparsers(dest="benchmark", metavar="BENCHMARK")
    sub.required = True
    for name, command in BENCHMARKS.items():
        command.attach(sub, name)


# the top-level commands
COMMANDS: dict[str, Command] = {
    "render": Command("write characters with the brush on one image (PNG, JPEG, TIFF, BMP or WebP)",
                      "commands.render"),
    "batch": Command("render many characters, one PNG each, in parallel; resumable", "commands.batch"),
    "fit": Command("fit each character's stroke plans to its outlines (mmah: sources); resumable", "plans",
                   "fit_arguments", "fit_handle"),
    "learn": Command("learn a hand (a style's plans from medians alone) from fitted plans", "plans",
                     "learn_arguments", "learn_handle"),
    "font": Command("build an OTF, TTF, WOFF2 or UFO font of characters written by the brush; resumable", "font.cli"),
    "bench": Command("run a benchmark", "cli", "_bench_args", handle=""),     # each benchmark sets its own
    "demo": Command("draw the demo", "commands.demo"),
    "params": Command("print every brush parameter (or, with --style, style field) with its unit, range and value",
                      "commands.params"),
    "gallery": Command("render the seed's Figure 11 sample strokes to one PNG", "commands.gallery"),
    "outline": Command("draw a 3-D mesh's visible feature lines with the brush", "outline3d.command",
                       handle="run"),
    "paint": Command("paint with a pen (or mouse) in the browser: a local web app", "paint.commands", "paint_args",
                     "paint"),
    "replay": Command("render the motion log of a painting to an image", "paint.commands", "replay_args", "replay"),
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
    parser.set_defaults(entry=main)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for name, command in COMMANDS.items():
        command.attach(sub, name)
    return parser


def _interrupt(signum, frame):
    raise KeyboardInterrupt


def main(argv: list[str] | None = None) -> int:
    """Parse `argv` (default sys.argv[1:]), run the command, return its exit code. SIGTERM (a
    scheduler's kill, `timeout`) ends a command as Ctrl-C does: worker pools stopped with their
    workers, the summary printed, exit 130; a batch's, a fit's or a font's rerun resumes."""
    parser = build_parser()
    main_thread = threading.current_thread() is threading.main_thread()
    term = signal.signal(signal.SIGTERM, _interrupt) if main_thread else None
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
    finally:
        if term is not None:
            signal.signal(signal.SIGTERM, term)


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
