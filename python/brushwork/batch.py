"""A whole set of characters to PNG files, one file each, in parallel (`brushwork batch`), and a
contact sheet of them.

A batch is resumable: outputs are named by code point (U+6C38.png), every write is atomic (a
temporary file renamed into place), and a file that already exists is skipped, so an interrupted
batch run again picks up where it stopped. A character that fails (unknown to the source, a bad
glyph file, a rendering error) is reported at the end and the rest go on; the exit code is then 2.
"""
from __future__ import annotations

import os
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .files import check_bits, decodes, os_error_text, save_paper
from .glyphs import load_source
from .glyphs.sources import add_source_hint
from .paper import ink_path
from .pool import Progress, check_executor, parallel_map
from .scene import Scene
from .writing import Style, check_samples, check_seed, check_size, text_paper


def output_name(char: str) -> str:
    """The batch's file name for char: U+XXXX.png (upper-case hex, at least 4 digits)."""
    return f"U+{ord(char):04X}.png"


# --- the worker side (one process per job; each owns a brush, a GL context and its papers) ---
_JOB: dict = {}


def _init_worker(style_name: str, size: int, seed: int, bits: int, background: str, samples: int | None,
                 ink: str = "gl", plans: str | None = None) -> None:
    # a paper kept from an earlier batch in this process (--jobs 1 runs here) has that batch's
    # size and scene: drop it
    _JOB.clear()
    _JOB.update(style=Style.load(style_name), size=size, seed=seed, bits=bits, background=background,
                samples=samples, ink=ink, plans=plans)


def _render_one(task: tuple) -> tuple:
    """(char, Glyph, output path) -> (char, seconds, error text or None). The worker keeps its
    paper from character to character (cleared each time); after a failure it makes a new one."""
    char, glyph, out = task
    t0 = time.perf_counter()
    try:
        paper = text_paper([glyph], _JOB["size"], _JOB["style"], _JOB["seed"], _JOB["samples"],
                           paper=_JOB.get("paper"), ink=_JOB["ink"], plans=_JOB.get("plans"))
        _JOB["paper"] = paper
        save_paper(paper, out, bits=_JOB["bits"], background=_JOB["background"])
    except Exception as err:     # reported at the end with the character; the batch goes on
        _JOB.pop("paper", None)
        return char, time.perf_counter() - t0, f"{type(err).__name__}: {err}"
    return char, time.perf_counter() - t0, None


@dataclass
class BatchResult:
    written: list = field(default_factory=list)    # characters rendered in this run
    skipped: list = field(default_factory=list)    # already there from an earlier run
    failed: list = field(default_factory=list)     # (char, one-line reason)
    seconds: float = 0.0
    interrupted: bool = False
    unknown: int = 0                               # of the failed, characters no source had
    source: str = "default"                        # where the glyphs came from (a --source spec)

    @property
    def chars_per_s(self) -> float:
        return len(self.written) / self.seconds if self.seconds > 0 else 0.0


def run_batch(chars: str, out_dir: str | os.PathLike, source: str = "default", jobs: int = 1,
              size: int = 1024, style: str = "kai", seed: int = 0, bits: int = 8, background: str = "white",
              progress: bool = True, variant: str | None = None, samples: int | None = None,
              executor: str = "local", ink: str = "gl", plans: str | None = None) -> BatchResult:
    """Render each character of `chars` to out_dir/U+XXXX.png, skipping those already there
    (whole: a file that does not decode is rendered again), in local worker processes or on Ray."""
    check_executor(executor)
    size, bits, seed, samples = check_size(size), check_bits(bits), check_seed(seed), check_samples(samples)
    ink_path(Scene(**Style.load(style).scene), ink)           # a bad style or ink fails now, not in every worker
    jobs = int(jobs)
    if jobs < 1:
        raise ValueError(f"--jobs {jobs}: expected >= 1")
    out = _output_folder(out_dir)
    result = BatchResult(source=source)
    todo = _plan(chars, out, result)
    errors: list = []
    glyphs = load_source(source, "".join(todo), variant=variant, errors=errors) if todo else {}
    result.failed += [(getattr(e, "char", None) or "?", str(e)) for e in errors]
    result.unknown = sum(bool(getattr(e, "unknown", False)) for e in errors)
    tasks = [(c, glyphs[c], str(out / output_name(c))) for c in todo if c in glyphs]
    if plans is not None and not os.path.isdir(plans):
        raise ValueError(f"--plans {plans}: not a folder")
    _run_tasks(tasks, jobs, (style, size, seed, bits, background, samples, ink, plans), result, progress, executor)
    return result


def _output_folder(out_dir: str | os.PathLike) -> Path:
    """The batch's output folder, made when missing; OSError in plain words when it cannot be."""
    out = Path(out_dir)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise NotADirectoryError(f"cannot write into {out}: it is a file, not a folder") from None
    except OSError as err:
        raise OSError(err.errno, os_error_text(err, out, "make the folder")) from None
    if not os.access(out, os.W_OK):
        raise PermissionError(f"cannot write into {out}: the folder is not writable")
    return out


def _plan(chars: str, out: Path, result: BatchResult) -> list:
    """The characters to render; those whose file is there and decodes go to result.skipped."""
    todo = []
    for c in dict.fromkeys(chars):
        path = out / output_name(c)
        (result.skipped if path.is_file() and decodes(path) else todo).append(c)
    return todo


def _run_tasks(tasks: list, jobs: int, init: tuple, result: BatchResult, progress: bool,
               executor: str = "local") -> None:
    """Render the tasks in `jobs` workers into result (written, failed, seconds, interrupted)."""
    bar = Progress(len(tasks)) if progress and tasks else None
    t0 = time.perf_counter()
    try:
        for char, _secs, err in parallel_map(_render_one, tasks, jobs, _init_worker, init, executor):
            if err is None:
                result.written.append(char)
            else:
                result.failed.append((char, err))
            if bar is not None:
                bar.update(err is None)
    except KeyboardInterrupt:
        result.interrupted = True
    finally:
        result.seconds = time.perf_counter() - t0
        if bar is not None:
            bar.close()


def sheet_cells(chars: str, out_dir: str | os.PathLike, failed: dict) -> list:
    """Contact-sheet cells for chars from the PNGs in out_dir (a crossed box where one failed)."""
    import cv2

    from .sheet import Cell

    cells = []
    for c in dict.fromkeys(chars):
        path = Path(out_dir) / output_name(c)
        img = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE) if path.is_file() else None
        if img is not None and img.dtype != np.uint8:
            img = (img // 257).astype(np.uint8)
        note = "failed" if c in failed else ""
        cells.append(Cell(c, img, note))
    return cells


SHOWN_FAILURES = 20   # failures listed in the summary; all of them go to OUT/failed.txt


def _failure_line(char: str, why: str) -> str:
    return f"failed {char} (U+{ord(char):04X}): {why}" if len(char) == 1 else f"failed: {why}"


def write_failures(result: BatchResult, out_dir: str | os.PathLike) -> Path | None:
    """Every failure of this run, a line each, in out_dir/failed.txt (atomically); the file is
    removed when nothing failed. Returns its path or None."""
    path = Path(out_dir) / "failed.txt"
    if not result.failed:
        path.unlink(missing_ok=True)
        return None
    tmp = path.with_name(".failed.txt.tmp")
    tmp.write_text("".join(_failure_line(c, w) + "\n" for c, w in result.failed), encoding="utf-8")
    os.replace(tmp, path)
    return path


def summary(result: BatchResult, failures_file: Path | None = None) -> str:
    """The lines printed at the end of a batch: counts, then the first SHOWN_FAILURES failures."""
    lines = [f"{len(result.written)} written, {len(result.skipped)} already there, {len(result.failed)} failed"
             f" in {result.seconds:.1f} s ({result.chars_per_s:.2f} chars/s)"]
    if result.interrupted:
        lines.append("interrupted: run the same command again to resume (finished files are kept)")
    lines += ["  " + _failure_line(c, w) for c, w in result.failed[:SHOWN_FAILURES]]
    if len(result.failed) > SHOWN_FAILURES:
        lines.append(f"  ... and {len(result.failed) - SHOWN_FAILURES} more"
                     + (f": every failure is listed in {failures_file}" if failures_file else ""))
    elif failures_file:
        lines.append(f"  (also listed in {failures_file})")
    if result.unknown:
        lines.append(f"  {result.unknown} character(s) are in none of the source's glyphs: {add_source_hint(result.source)}")
    return "\n".join(lines)
