"""Fuzzing the inputs a user hands brushwork: glyph files, style files, SVG path data and command
lines, valid and broken. Every input must end in success or a one-line error with exit code 2:
never a traceback, another exit code, a hang past a time limit or a partial output file.

The generators take a `random.Random` and return one input; the test suite drives them through
Hypothesis (tests/test_fuzz.py), `brushwork bench fuzz --n N` through a seeded loop; command lines
go through the entry point the caller hands in (the CLI's `main`). Valid glyphs
and styles are rendered at 16 px only every `render_every` inputs, so most inputs exercise parsing
and validation.
"""
from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import random
import signal
import tempfile
import time
from pathlib import Path
from typing import Callable

TIMEOUT_S = 20.0      # an input running longer than this is a hang
CHAR = "一"           # the character the glyph inputs draw

Entry = Callable[[list], int]   # the command line's entry point: argv -> exit code (brushwork.cli.main)

# numbers a broken input puts where a value belongs: edge values, wrong types, huge, tiny, non-finite
ODD_VALUES = [0, -1, 1, 2.5, 1e300, -1e300, 1e-300, 1e6, -1e6, float("nan"), float("inf"), "abc", "", None, True,
              [], {}, [1], [[0, 0]], 10 ** 30]


def _odd(rng: random.Random):
    return rng.choice(ODD_VALUES)


def _number(rng: random.Random, lo: float, hi: float) -> float:
    return round(rng.uniform(lo, hi), 4)


# --- glyph files ---
def _points(rng: random.Random) -> list:
    n = rng.choice([2, 2, 3, 5, 8])
    return [[_number(rng, 0.05, 0.95), _number(rng, 0.05, 0.95)] for _ in range(n)]


def _stroke(rng: random.Random) -> dict:
    stroke = {"points": _points(rng)} if rng.random() < 0.8 else {"d": svg_path(rng, valid=True)}
    if rng.random() < 0.5:
        stroke["kind"] = chr(rng.randrange(0x31C0, 0x31E4))
    return stroke


def _break_glyph(rng: random.Random, doc: dict) -> None:
    """Break one thing in a valid glyph document, in place."""
    stroke = rng.choice(doc["strokes"])
    where = rng.randrange(6)
    if where == 0:
        doc[rng.choice(list(doc))] = _odd(rng)
    elif where == 1:
        doc.pop(rng.choice(list(doc)))
    elif where == 2:
        stroke[rng.choice(["points", "kind", "pressure", "speed", "tilt_deg", "outline", "d", "extra"])] = _odd(rng)
    elif where == 3 and "points" in stroke:
        stroke["points"][rng.randrange(len(stroke["points"]))][rng.randrange(2)] = _odd(rng)
    elif where == 4:
        doc["strokes"] = rng.choice([[], [stroke] * rng.choice([101, 1000]), "x"])
    else:
        doc["em_box"] = [rng.choice([0, 1, 1e300, -1e300, float("nan")]) for _ in range(rng.choice([3, 4]))]


def glyph_json(rng: random.Random, valid: bool | None = None) -> str:
    """The text of a glyph file for CHAR: valid, one thing broken, or not JSON at all."""
    valid = rng.random() < 0.3 if valid is None else valid
    doc = {"format": "brushwork-glyph", "version": 1, "char": CHAR, "codepoint": ord(CHAR),
           "em_box": [0, 0, 1, 1], "y_down": rng.random() < 0.5,
           "strokes": [_stroke(rng) for _ in range(rng.choice([1, 1, 2, 3]))]}
    if not valid:
        _break_glyph(rng, doc)
    text = json.dumps(doc)
    if not valid and rng.random() < 0.1:
        text = text[:rng.randrange(len(text) + 1)]        # truncated
    return text


# --- style files ---
def style_json(rng: random.Random, valid: bool | None = None) -> str:
    """The text of a style file: kai with fields changed within their ranges, or one broken."""
    from ..writing.style import FIELDS, STYLE_DIR

    doc = json.loads((STYLE_DIR / "kai.json").read_text(encoding="utf-8"))
    valid = rng.random() < 0.3 if valid is None else valid
    numeric = [f for f in FIELDS if f.kind in ("float", "int")]
    for f in rng.sample(numeric, 3):
        value = rng.uniform(f.lo, f.hi) if f.kind == "float" else rng.randint(int(f.lo), int(min(f.hi, 8)))
        doc[f.name] = max(value, f.lo + 1e-3) if f.lo_open else value
    if not valid:
        name = rng.choice([f.name for f in FIELDS] + ["colour"])
        doc[name] = _odd(rng) if rng.random() < 0.8 else rng.choice([-5, 1e9, 0])
    text = json.dumps(doc)
    return text[:rng.randrange(len(text) + 1)] if not valid and rng.random() < 0.05 else text


# --- SVG path data ---
_SVG_LETTERS = "MmLlHhVvCcSsQqTtZzAa"


def svg_path(rng: random.Random, valid: bool | None = None) -> str:
    """SVG path data: M then commands with the right count of numbers, or a jumble of tokens."""
    valid = rng.random() < 0.5 if valid is None else valid
    if not valid:
        tokens = [rng.choice([rng.choice(_SVG_LETTERS), str(_number(rng, -2, 2)), ",", " ", "1e999", "-.5e-3",
                              "nan", "1e300", "#"]) for _ in range(rng.randrange(12))]
        return " ".join(tokens)
    arity = {"L": 2, "H": 1, "V": 1, "C": 6, "S": 4, "Q": 4, "T": 2}
    parts = [f"M {_number(rng, 0.1, 0.9)} {_number(rng, 0.1, 0.9)}"]
    for _ in range(rng.randrange(1, 4)):
        cmd = rng.choice(list(arity))
        parts.append(cmd + " " + " ".join(str(_number(rng, 0.1, 0.9)) for _ in range(arity[cmd])))
    return " ".join(parts)


# --- command lines ---
_OPTION_VALUES = {"--size": ["16", "16", "17", "0", "-5", "abc", "99999", "1e3"],
                  "--bits": ["8", "16", "12", "x"], "--samples": ["1", "2", "3", "x"],
                  "--seed": ["0", "7", "-1", "x", str(2 ** 70)], "--style": ["kai", "xing", "caoshu", "absent.json"],
                  "--source": ["default", "nope", "glyphs:absent", "mmah:absent", "kanjivg:absent", "a+b"],
                  "--jobs": ["1", "0", "-3", "x"], "--preset": ["medium", "small", "huge"]}
_TEXTS = ["一", "一二", "一一", "", " ", "x", "\u0000", "一" * 300, "𠀀"]
_OUTPUTS = ["o.png", "o.jpg", "o.tif", "o.webp", "o.gif", "o", "absent/o.png", ".", "o.PNG"]


def argv(rng: random.Random) -> list[str]:
    """A command line: render, batch or params with options drawn from valid and broken values
    (a rendering command always names a --size, mostly 16 px)."""
    command = rng.choice(["render", "render", "batch", "params", "nonsense", "--version"])
    args = [command]
    if command == "render":
        args += [rng.choice(_TEXTS), "-o", rng.choice(_OUTPUTS), "--size", rng.choice(_OPTION_VALUES["--size"])]
    elif command == "batch":
        args += [rng.choice(["--chars", "--charset"]), rng.choice(_TEXTS[:-2] + ["absent.txt"]), "--out", "out",
                 "--no-progress", "--size", rng.choice(_OPTION_VALUES["--size"])]
    for _ in range(rng.randrange(3)):
        option = rng.choice(list(_OPTION_VALUES) + ["--transparent", "--bogus", "--style"])
        args += [option] + ([rng.choice(_OPTION_VALUES[option])] if option in _OPTION_VALUES else [])
    return args


# --- running one input ---
class Hang(Exception):
    """An input ran past TIMEOUT_S."""


@contextlib.contextmanager
def _time_limit(seconds: float):
    def _ring(signum, frame):
        raise Hang(f"ran past {seconds:g} s")

    old = signal.signal(signal.SIGALRM, _ring)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def run_cli(entry: Entry, args: list[str], timeout_s: float = TIMEOUT_S) -> tuple[int, str, str]:
    """entry(args), the command line's entry point, in this process: (exit code, stdout, stderr);
    a Hang past timeout_s."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), _time_limit(timeout_s):
        try:
            rc = entry(args)
        except SystemExit as exc:
            rc = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    return rc, out.getvalue(), err.getvalue()


def verdict(rc: int, stderr: str, outputs: list[Path], folder: Path) -> str | None:
    """Why a CLI run failed the fuzz contract, or None: exit 0 with its outputs whole, or exit 2
    with one `brushwork: error:` line and no output file or temporary file left."""
    left = sorted(p.name for p in folder.iterdir() if p.name.startswith((".tmp-", ".brushwork-")))
    if left:
        return f"temporary files left: {left}"
    if rc == 0:
        return _partial(outputs)
    if rc != 2:
        return f"exit code {rc}: {stderr.strip()[-300:]}"
    lines = stderr.strip().splitlines()
    if len(lines) != 1 or not lines[0].startswith("brushwork: error: "):
        return f"not one error line: {stderr.strip()[-300:]}"
    written = [p.name for p in outputs if p.is_file()]
    return f"exit 2 left an output file {written}" if written else None


def _partial(outputs: list[Path]) -> str | None:
    """An image among `outputs` that does not decode, or None."""
    from ..files import decodes

    broken = [p.name for p in outputs if p.is_file() and p.suffix.lower() != ".json" and not decodes(p)]
    return f"exit 0 with a partial file {broken}" if broken else None


def check_argv(entry: Entry, args: list[str], folder: Path) -> str | None:
    """Run a command line in `folder` (emptied first); why it failed, or None."""
    _empty(folder)
    cwd = os.getcwd()
    os.chdir(folder)
    try:
        rc, _out, err = run_cli(entry, args)
    except Hang as exc:
        return f"hang: {exc}"
    except Exception as exc:  # noqa: BLE001 - a traceback is what the fuzz looks for
        return f"traceback: {type(exc).__name__}: {exc}"
    finally:
        os.chdir(cwd)
    outputs = [folder / a for a in args if a.startswith("o")] + list((folder / "out").glob("*.png"))
    return verdict(rc, err, outputs, folder)


def _empty(folder: Path) -> None:
    for p in folder.iterdir():
        if p.is_dir():
            for q in p.iterdir():
                q.unlink()
            p.rmdir()
        else:
            p.unlink()


def _render_args(extra: list[str]) -> list[str]:
    return ["render", CHAR, "-o", "o.png", "--size", "16", "--samples", "1"] + extra


def check_glyph(entry: Entry, text: str, folder: Path, render: bool) -> str | None:
    """A glyph file: loading it ends in a Glyph or a GlyphError; rendered through the CLI when
    `render` (a valid one then writes its image, a broken one one error line)."""
    from ..glyphs import GlyphError, load_glyph

    _empty(folder)
    (folder / "g").mkdir()
    path = folder / "g" / f"U+{ord(CHAR):04X}.json"
    path.write_text(text, encoding="utf-8")
    if render:
        return check_argv(entry, _render_args(["--source", f"glyphs:{folder / 'g'}"]), folder)
    return _load_only(lambda: load_glyph(path), GlyphError)


def check_style(entry: Entry, text: str, folder: Path, render: bool) -> str | None:
    """A style file: loading it ends in a Style or a StyleError; rendered when `render`."""
    from ..writing import Style, StyleError

    _empty(folder)
    path = folder / "style.json"
    path.write_text(text, encoding="utf-8")
    if render:
        return check_argv(entry, _render_args(["--style", str(path), "--source", "default"]), folder)
    return _load_only(lambda: Style.load(str(path)), StyleError)


def check_svg(d: str) -> str | None:
    """SVG path data: parsing ends in polylines or a GlyphError."""
    from ..glyphs import GlyphError
    from ..glyphs.svgpath import parse_svg_path

    return _load_only(lambda: parse_svg_path(d), GlyphError)


def _load_only(load: Callable, allowed: type) -> str | None:
    try:
        with _time_limit(TIMEOUT_S):
            load()
    except allowed as exc:
        return None if "\n" not in str(exc) else f"a multi-line error: {exc!s:.200}"
    except Hang as exc:
        return f"hang: {exc}"
    except Exception as exc:  # noqa: BLE001 - a traceback is what the fuzz looks for
        return f"traceback: {type(exc).__name__}: {exc}"
    return None


# --- the benchmark ---
KINDS = ("glyph", "style", "svg", "argv")


def _one(entry: Entry, kind: str, rng: random.Random, folder: Path, render: bool) -> tuple[object, str | None]:
    """(the input, why it failed or None) for one input of `kind`."""
    if kind == "glyph":
        text = glyph_json(rng)
        return text, check_glyph(entry, text, folder, render)
    if kind == "style":
        text = style_json(rng)
        return text, check_style(entry, text, folder, render)
    if kind == "svg":
        d = svg_path(rng)
        return d, check_svg(d)
    args = argv(rng)
    return args, check_argv(entry, args, folder)


def run(entry: Entry, n: int, seed: int = 0, render_every: int = 500, argv_share: float = 0.01,
        progress=None) -> dict:
    """n inputs spread over KINDS (command lines, which may render, `argv_share` of them), run
    through the command line's entry point `entry` (argv -> exit code); per kind: tried, failed,
    the first failing input and why."""
    rng = random.Random(seed)
    stats = {k: {"tried": 0, "failed": 0, "first_failure": None, "why": None} for k in KINDS}
    weights = [(1 - argv_share) / 3] * 3 + [argv_share]
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="brushwork-fuzz-") as tmp:
        for i in range(n):
            kind = rng.choices(KINDS, weights)[0]
            data, why = _one(entry, kind, rng, Path(tmp), render=stats[kind]["tried"] % render_every == 0)
            _count(stats[kind], data, why)
            if progress and (i + 1) % 10000 == 0:
                progress(f"{i + 1}/{n} inputs, {time.perf_counter() - t0:.0f} s")
    return {"n": n, "seed": seed, "seconds": time.perf_counter() - t0, "kinds": stats}


def _count(row: dict, data, why: str | None) -> None:
    row["tried"] += 1
    if why is not None:
        row["failed"] += 1
        if row["first_failure"] is None:
            row["first_failure"], row["why"] = (data if isinstance(data, list) else str(data)[:500]), why


def table(result: dict) -> str:
    from .report import markdown_table

    rows = [{"kind": k, **{c: v for c, v in r.items() if c != "first_failure"},
             "first failing input": json.dumps(r["first_failure"], ensure_ascii=False)[:120] if r["first_failure"]
             else ""} for k, r in result["kinds"].items()]
    return (markdown_table(rows, ["kind", "tried", "failed", "why", "first failing input"])
            + f"\n\n{result['n']} inputs in {result['seconds']:.1f} s (seed {result['seed']})")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--n", type=int, default=10000, help="inputs to try (default 10000)")
    p.add_argument("--seed", type=int, default=0, help="seed of the generators (default 0)")
    p.add_argument("--render-every", type=int, default=500,
                   help="render one valid-or-broken glyph or style file through the CLI every this many (default 500)")
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")


def handle(args: argparse.Namespace) -> int:
    from .report import progress, run_benchmark

    if args.n < 1 or args.render_every < 1:
        raise ValueError(f"--n {args.n} --render-every {args.render_every}: expected >= 1")
    return run_benchmark("fuzz", args, lambda: run(args.entry, args.n, args.seed, args.render_every,
                                                   progress=progress), table)
