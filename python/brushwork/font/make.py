"""A font of many characters: each glyph's outline made by the brush in worker processes (or
on Ray), kept in a cache beside the font so that a run stopped part way resumes where it stopped
and another format of the same font is built without writing a glyph again; then the font.

The cache is OUT's folder/.brushwork-font-cache/KEY/U+XXXX-HASH.json, KEY naming the style, seed,
trace size, tolerance and brush (brushwork's version, the preset's parameters) and HASH the glyph's
strokes; each file is written atomically."""
from __future__ import annotations

import hashlib
import json
import os
import pickle
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from ..pool import Progress, check_executor, parallel_map
from ..files import write_atomic
from ..writing import Style, check_size, text_paper
from .build import FontInfo, check_font_path, write_font
from .outline import FIT_TOL_PX, TRACE_SIZE, Em, outline_from_image, point_count

CACHE_DIR = ".brushwork-font-cache"
OUTLINE_FORMAT = 2          # the cache files' layout and the tracer's: a change makes new keys


@dataclass
class FontResult:
    path: str = ""
    made: list = field(default_factory=list)        # characters whose outline this run made
    cached: list = field(default_factory=list)      # characters whose outline came from the cache
    failed: list = field(default_factory=list)      # (char, one-line reason): not in the font
    unknown: int = 0                                # of the failed, characters no source has
    points: list = field(default_factory=list)      # points of each glyph in the font
    seconds: float = 0.0
    cpu_seconds: float = 0.0                        # the workers' CPU time on the glyphs made
    write_seconds: float = 0.0                      # assembling and writing the font
    interrupted: bool = False
    source: str = "default"

    @property
    def glyphs(self) -> int:
        return len(self.made) + len(self.cached)


def check_tolerance(tol: float) -> float:
    tol = float(tol)
    if not 0.05 <= tol <= 8.0:
        raise ValueError(f"--tolerance {tol}: expected 0.05..8 px")
    return tol


def _cache_key(style: Style, seed: int, size: int, tol: float) -> str:
    """What the cached outlines depend on: the style, seed, size and tolerance, the outline format,
    and the brush (brushwork's version and every parameter of the style's preset), so that another
    brush never reuses them."""
    from .. import BrushModel, __version__

    model = BrushModel.preset(style.preset)
    brush = {p["name"]: getattr(model, p["name"]) for p in model.parameters()}
    doc = json.dumps([asdict(style), seed, size, tol, OUTLINE_FORMAT, __version__, brush], sort_keys=True, default=str)
    return hashlib.sha1(doc.encode()).hexdigest()[:16]


def _glyph_file(folder: Path, char: str, glyph) -> Path:
    digest = hashlib.sha1(pickle.dumps(glyph, protocol=4)).hexdigest()[:12]
    return folder / f"U+{ord(char):04X}-{digest}.json"


def save_outline(path: Path, contours: list) -> None:
    """The contours (each (m, 4, 2) font units) as JSON at path, atomically."""
    doc = json.dumps([np.round(c, 3).tolist() for c in contours], separators=(",", ":"))
    write_atomic(path, lambda tmp: Path(tmp).write_text(doc, encoding="utf-8"), suffix=".json")


def load_outline(path: Path) -> list | None:
    """The contours cached at path, or None when the file is missing or not whole."""
    try:
        return [np.array(c, dtype=float).reshape(-1, 4, 2) for c in json.loads(path.read_text(encoding="utf-8"))]
    except (OSError, ValueError):
        return None


# --- the worker side: one process (or Ray worker) per job, each keeping its paper ---
_JOB: dict = {}


def _init_worker(style: str, size: int, seed: int, tol: float) -> None:
    _JOB.clear()
    _JOB.update(style=Style.load(style), em=Em(size), seed=seed, tol=tol)


def _outline_one(task: tuple) -> tuple:
    """(char, Glyph, cache path) -> (char, CPU seconds, error text or None); the outline goes to
    the cache."""
    char, glyph, out = task
    t0 = time.process_time()
    try:
        em = _JOB["em"]
        paper = text_paper([glyph], em.size, _JOB["style"], _JOB["seed"], paper=_JOB.get("paper"))
        _JOB["paper"] = paper
        save_outline(Path(out), outline_from_image(paper.image(), em, _JOB["tol"]))
    except Exception as err:       # reported at the end with the character; the others go on
        _JOB.pop("paper", None)
        return char, time.process_time() - t0, f"{type(err).__name__}: {err}"
    return char, time.process_time() - t0, None


def _load_glyphs(glyphs, source: str, result: FontResult) -> dict:
    """{char: Glyph}: glyphs itself when it is a dict, else its characters from the source (those
    it lacks go to result.failed)."""
    if isinstance(glyphs, dict):
        return dict(glyphs)
    from ..glyphs import load_source

    chars = "".join(dict.fromkeys(c for c in glyphs if not c.isspace()))
    if not chars:
        raise ValueError("no characters to build a font of")
    errors: list = []
    loaded = load_source(source, chars, errors=errors)
    result.failed += [(getattr(e, "char", None) or "?", str(e)) for e in errors]
    result.unknown = sum(bool(getattr(e, "unknown", False)) for e in errors)
    return loaded


def _run(tasks: list, jobs: int, init: tuple, executor: str, result: FontResult, progress: bool) -> None:
    bar = Progress(len(tasks)) if progress and tasks else None
    try:
        for char, cpu, err in parallel_map(_outline_one, tasks, jobs, _init_worker, init, executor):
            (result.made.append(char) if err is None else result.failed.append((char, err)))
            result.cpu_seconds += cpu
            if bar is not None:
                bar.update(err is None)
    except KeyboardInterrupt:
        result.interrupted = True
    finally:
        if bar is not None:
            bar.close()


def build_font(glyphs, path: str | os.PathLike, *, source: str = "default", style: str = "kai", seed: int = 0,
               size: int = TRACE_SIZE, tolerance: float = FIT_TOL_PX, info: FontInfo | None = None, jobs: int = 1,
               executor: str = "local", progress: bool = False) -> FontResult:
    """A font at path (.otf .ttf .woff2 .ufo) of glyphs: a string of characters (their strokes
    from `source`) or a {char: Glyph} dict, each outline traced from the brush's size x size
    render (as `brushwork render CHAR --size SIZE` draws it) and fitted within `tolerance` px.
    Characters that fail are listed in the result and left out; the font is written when any
    glyph was made, atomically."""
    t0 = time.perf_counter()
    info = (info or FontInfo()).check()
    check_font_path(path)
    size, tolerance, executor = check_size(size), check_tolerance(tolerance), check_executor(executor)
    if int(jobs) < 1:
        raise ValueError(f"--jobs {jobs}: expected >= 1")
    st = Style.load(style)
    result = FontResult(path=os.fspath(path), source=source)
    loaded = _load_glyphs(glyphs, source, result)
    folder = Path(os.path.abspath(os.fspath(path))).parent / CACHE_DIR / _cache_key(st, seed, size, tolerance)
    folder.mkdir(parents=True, exist_ok=True)
    files = {c: _glyph_file(folder, c, g) for c, g in loaded.items()}
    todo = [c for c in loaded if load_outline(files[c]) is None]
    making = set(todo)
    result.cached = [c for c in loaded if c not in making]
    _run([(c, loaded[c], str(files[c])) for c in todo], int(jobs), (style, size, seed, tolerance), executor,
         result, progress)
    done = set(result.made) | set(result.cached)
    outlines = {c: load_outline(files[c]) for c in loaded if c in done}
    if outlines and not result.interrupted:
        t1 = time.perf_counter()
        write_font(outlines, path, info)
        result.write_seconds = time.perf_counter() - t1
        result.points = [point_count(outlines[c]) for c in outlines]
    result.seconds = time.perf_counter() - t0
    return result


def summary(result: FontResult, shown: int = 20) -> str:
    """The lines printed after a build: what was written, then the characters left out."""
    pts = f", median {int(np.median(result.points))} points a glyph" if result.points else ""
    lines = [f"{result.glyphs} glyphs ({len(result.made)} made, {len(result.cached)} from the cache), "
             f"{len(result.failed)} failed in {result.seconds:.1f} s{pts}"]
    if result.interrupted:
        lines.append("interrupted: run the same command again to resume (finished glyphs are cached)")
    elif result.points:
        lines.append(f"wrote {result.path}")
    lines += [f"  failed {c} (U+{ord(c):04X}): {w}" if len(c) == 1 else f"  failed: {w}"
              for c, w in result.failed[:shown]]
    if len(result.failed) > shown:
        lines.append(f"  ... and {len(result.failed) - shown} more")
    missing = "".join(c for c, _ in result.failed if len(c) == 1)
    if missing:
        lines.append(f"missing from the font: {missing}")
    return "\n".join(lines)
