"""A font of many characters: each glyph's outline made by the brush in worker processes (or
on Ray), kept in a cache beside the font so that a run stopped part way resumes where it stopped
and another format of the same font is built without writing a glyph again; then the font.

The cache is OUT's folder/.brushwork-font-cache/KEY/U+XXXX-HASH.json, KEY naming the style, seed,
size, tolerance, the ink's path (geometry or gl) and brush (brushwork's version, the preset's parameters) and HASH the glyph's
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
from ..paper import ink_path
from ..scene import Scene
from ..writing import Style, check_size, text_paper
from .build import SPACES, FontInfo, check_font_path, make_font, write_font
from .check import glyph_points
from .outline import FIT_TOL_PX, TRACE_SIZE, Em, outline_of_paper, point_count
from .variable import MASTERS, master_outlines, write_variable
from .web import SLICE_CHARS, check_slice_chars, write_web

CACHE_DIR = ".brushwork-font-cache"
MAX_UNITS = 32767           # font units: every coordinate of a font fits a signed 16-bit integer
OUTLINE_FORMAT = 5          # the cache files' layout and the fitter's: a change makes new keys


@dataclass
class FontResult:
    path: str = ""
    web: object = None                              # the WebFont written at --web, or None
    made: list = field(default_factory=list)        # characters whose outline this run made
    cached: list = field(default_factory=list)      # characters whose outline came from the cache
    failed: list = field(default_factory=list)      # (char, one-line reason): not in the font
    unknown: int = 0                                # of the failed, characters no source has
    points: list = field(default_factory=list)      # points of each glyph in the font (check.glyph_points)
    seconds: float = 0.0
    cpu_seconds: float = 0.0                        # the workers' CPU time on the glyphs made
    write_seconds: float = 0.0                      # assembling and writing the font
    interrupted: bool = False
    source: str = "default"
    ink: str = ""                                   # the path the ink took: geometry or gl

    @property
    def glyphs(self) -> int:
        return len(self.made) + len(self.cached)


def check_tolerance(tol: float) -> float:
    tol = float(tol)
    if not 0.05 <= tol <= 8.0:
        raise ValueError(f"--tolerance {tol}: expected 0.05..8 px")
    return tol


def _cache_key(style: Style, seed: int, size: int, tol: float, variable: bool = False, ink: str = "gl") -> str:
    """What the cached outlines depend on: the style, seed, size and tolerance, the ink's path
    (geometry's exact loops or the traced image), the outline format,
    the weight masters of a variable font, and the brush (brushwork's version and every parameter
    of the style's brush), so that another brush never reuses them."""
    from .. import __version__

    model = style.model()
    brush = {p["name"]: getattr(model, p["name"]) for p in model.parameters()}
    masters = MASTERS if variable else None
    doc = json.dumps([asdict(style), seed, size, tol, OUTLINE_FORMAT, __version__, brush, masters, ink], sort_keys=True,
                     default=str)
    return hashlib.sha1(doc.encode()).hexdigest()[:16]


def _glyph_file(folder: Path, char: str, glyph) -> Path:
    digest = hashlib.sha1(pickle.dumps(glyph, protocol=4)).hexdigest()[:12]
    return folder / f"U+{ord(char):04X}-{digest}.json"


def save_outline(path: Path, contours) -> None:
    """The contours (each (m, 4, 2) font units), or a variable glyph's {wght: contours}, as JSON at
    path, atomically."""
    def rounded(cs: list) -> list:
        return [np.round(c, 3).tolist() for c in cs]

    tree = {str(w): rounded(cs) for w, cs in contours.items()} if isinstance(contours, dict) else rounded(contours)
    doc = json.dumps(tree, separators=(",", ":"))
    write_atomic(path, lambda tmp: Path(tmp).write_text(doc, encoding="utf-8"), suffix=".json")


def load_outline(path: Path) -> list | dict | None:
    """The contours (or {wght: contours}) cached at path, or None when the file is missing, not
    whole or not an outline (then the glyph is made again)."""
    try:
        tree = json.loads(path.read_text(encoding="utf-8"))
        if isinstance(tree, dict):
            if not tree:
                raise ValueError("no masters")
            return {int(w): check_outline(cs) for w, cs in tree.items()}
        return check_outline(tree)
    except (OSError, ValueError, TypeError, RecursionError):
        return None


def check_outline(doc) -> list:
    """A cache file's document as contours, each (m, 4, 2) font units: a non-empty list of
    non-empty contours of cubic segments with finite coordinates a font can hold (ValueError)."""
    if not isinstance(doc, list) or not doc:
        raise ValueError("no contours")
    contours = [np.array(c, dtype=float).reshape(-1, 4, 2) for c in doc]
    for c in contours:
        if len(c) == 0 or not np.isfinite(c).all() or np.abs(c).max() > MAX_UNITS:
            raise ValueError("a contour empty, not finite or beyond a font's coordinates")
    return contours


# --- the worker side: one process (or Ray worker) per job, each keeping its paper ---
_JOB: dict = {}


def _init_worker(style: str, size: int, seed: int, tol: float, variable: bool = False, ink: str = "gl") -> None:
    _JOB.clear()
    _JOB.update(style=Style.load(style), em=Em(size), seed=seed, tol=tol, variable=variable, ink=ink)


def _outline_one(task: tuple) -> tuple:
    """(char, Glyph, cache path) -> (char, CPU seconds, error text or None); the outline goes to
    the cache."""
    char, glyph, out = task
    t0 = time.process_time()
    try:
        em = _JOB["em"]
        if _JOB["variable"]:
            save_outline(Path(out), master_outlines(glyph, em, _JOB["style"], _JOB["seed"], ink=_JOB["ink"]))
        else:
            paper = text_paper([glyph], em.size, _JOB["style"], _JOB["seed"], paper=_JOB.get("paper"), ink=_JOB["ink"])
            _JOB["paper"] = paper
            save_outline(Path(out), outline_of_paper(paper, em, _JOB["tol"]))
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


def _write(outlines: dict, order: list, path, web, slice_chars: int, info: FontInfo, result: FontResult,
           variable: bool = False) -> None:
    """The font at path (variable: a wght axis of the masters) and its web slices in the folder
    web (either may be None)."""
    t1 = time.perf_counter()
    if path is not None:
        (write_variable if variable else write_font)(outlines, path, info)
    if web is not None:
        text = "".join(c for c in order if c in outlines)
        result.web = write_web(make_font(outlines, info), text, web, info.family, info.ps_name, slice_chars,
                               first="".join(SPACES))
    result.write_seconds = time.perf_counter() - t1
    if path is not None and not os.fspath(path).lower().endswith(".ufo"):
        stored = glyph_points(path)
        result.points = [stored[c] for c in outlines]
    else:
        result.points = [point_count(outlines[c]) for c in outlines if not variable]


def _cache_root(path, web) -> Path:
    """The folder the cache lives in: the font's, else the web folder (made when missing)."""
    if path is not None:
        return Path(os.path.abspath(os.fspath(path))).parent
    Path(web).mkdir(parents=True, exist_ok=True)
    return Path(os.path.abspath(os.fspath(web)))


def _check_args(path, web, slice_chars: int, size: int, tolerance: float, executor: str, jobs: int,
                variable: bool = False) -> tuple:
    """(size, tolerance, executor) checked, and the outputs and job count; ValueError in one line."""
    if path is None and web is None:
        raise ValueError("name a font to write (-o) or a folder for the web font (--web)")
    if variable and (web is not None or path is None or os.fspath(path).lower().endswith(".ufo")):
        raise ValueError("--variable writes one .otf, .ttf or .woff2 (-o), not a .ufo or --web slices")
    if path is not None:
        check_font_path(path)
    check_slice_chars(slice_chars)
    if int(jobs) < 1:
        raise ValueError(f"--jobs {jobs}: expected >= 1")
    return check_size(size), check_tolerance(tolerance), check_executor(executor)


def build_font(glyphs, path: str | os.PathLike | None, *, source: str = "default", style: str = "kai", seed: int = 0,
               size: int = TRACE_SIZE, tolerance: float = FIT_TOL_PX, info: FontInfo | None = None, jobs: int = 1,
               executor: str = "local", progress: bool = False, web: str | os.PathLike | None = None,
               slice_chars: int = SLICE_CHARS, variable: bool = False, ink: str = "auto") -> FontResult:
    """A font at path (.otf .ttf .woff2 .ufo) of glyphs: a string of characters (their strokes
    from `source`) or a {char: Glyph} dict, each outline traced from the brush's size x size
    render (as `brushwork render CHAR --size SIZE` draws it) and fitted within `tolerance` px;
    with `web` a folder, also the font cut in unicode-range WOFF2 slices of `slice_chars`
    characters with their CSS and a demo page (web.py; path may then be None); with `variable`,
    a variable font whose wght axis runs through the brush's weight masters (variable.py). `ink`
    picks how the ink is made (paper.ink_path): geometry's exact contours, fitted; gl's image,
    traced; auto, geometry for an opaque style.
    Characters that fail are listed in the result and left out; the font is written when any
    glyph was made, atomically."""
    t0 = time.perf_counter()
    info = (info or FontInfo()).check()
    size, tolerance, executor = _check_args(path, web, slice_chars, size, tolerance, executor, jobs, variable)
    st = Style.load(style)
    ink = ink_path(Scene(**st.scene), ink)
    result = FontResult(path=os.fspath(path) if path is not None else "", source=source, ink=ink)
    loaded = _load_glyphs(glyphs, source, result)
    folder = _cache_root(path, web) / CACHE_DIR / _cache_key(st, seed, size, tolerance, variable, ink)
    folder.mkdir(parents=True, exist_ok=True)
    files = {c: _glyph_file(folder, c, g) for c, g in loaded.items()}
    todo = [c for c in loaded if load_outline(files[c]) is None]
    making = set(todo)
    result.cached = [c for c in loaded if c not in making]
    _run([(c, loaded[c], str(files[c])) for c in todo], int(jobs), (style, size, seed, tolerance, variable, ink),
         executor, result, progress)
    outlines = _outlines(files, loaded, result)
    if outlines and not result.interrupted:
        _write(outlines, list(loaded), path, web, slice_chars, info, result, variable)
    result.seconds = time.perf_counter() - t0
    return result


def _outlines(files: dict, loaded: dict, result: FontResult) -> dict:
    """The outlines made or cached, read back; one that is not an outline (an empty trace) is
    listed as failed and left out."""
    done = set(result.made) | set(result.cached)
    outlines = {c: load_outline(files[c]) for c in loaded if c in done}
    for c in [c for c, o in outlines.items() if o is None]:
        del outlines[c]
        result.made, result.cached = [m for m in result.made if m != c], [m for m in result.cached if m != c]
        result.failed.append((c, f"{files[c]}: its outline is empty or not an outline"))
    return outlines


def summary(result: FontResult, shown: int = 20) -> str:
    """The lines printed after a build: what was written, then the characters left out."""
    pts = f", median {int(np.median(result.points))} points a glyph" if result.points else ""
    lines = [f"{result.glyphs} glyphs ({len(result.made)} made, {len(result.cached)} from the cache), "
             f"{len(result.failed)} failed in {result.seconds:.1f} s{pts}"]
    if result.interrupted:
        lines.append("interrupted: run the same command again to resume (finished glyphs are cached)")
    elif result.points:
        lines += [f"wrote {result.path}"] if result.path else []
        if result.web is not None:
            lines.append(f"wrote {len(result.web.slices)} WOFF2 slices, {result.web.css} and {result.web.page}")
    lines += [f"  failed {c} (U+{ord(c):04X}): {w}" if len(c) == 1 else f"  failed: {w}"
              for c, w in result.failed[:shown]]
    if len(result.failed) > shown:
        lines.append(f"  ... and {len(result.failed) - shown} more")
    missing = "".join(c for c, _ in result.failed if len(c) == 1)
    if missing:
        lines.append(f"missing from the font: {missing}")
    return "\n".join(lines)
