"""Rendering characters to PNG files: one text on one image (`brushwork render`) or a whole set
of characters, one file each, in parallel (`brushwork batch`).

A batch is resumable: outputs are named by code point (U+6C38.png), every write is atomic (a
temporary file renamed into place), and a file that already exists is skipped, so an interrupted
batch run again picks up where it stopped. A character that fails (unknown to the source, a bad
glyph file, a rendering error) is reported at the end and the rest go on; the exit code is then 2.
"""
from __future__ import annotations

import multiprocessing as mp
import os
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .glyphs import charsets, load_source
from .glyphs.charsets import gb2312  # noqa: F401  (batch.gb2312: the benchmarks' pool)
from .glyphs.sources import add_source_hint
from .files import decodes, os_error_text, save_paper
from .paper import Paper
from .writing import Style, Writer, check_samples, check_size, writing_paper
from .writing.driver import MAX_SIDE
from .writing.plan import load_plan

# each worker on one core: llvmpipe rasterises in the calling thread (LP_NUM_THREADS=0; with 1
# it hands every draw to a second thread and the two take turns: ~18% slower, measured on
# kai 1024 px with one sample), one BLAS thread
_ONE_THREAD = {"LP_NUM_THREADS": "0", "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}


def output_name(char: str) -> str:
    """The batch's file name for char: U+XXXX.png (upper-case hex, at least 4 digits)."""
    return f"U+{ord(char):04X}.png"


MAX_TEXT_CHARS = 256     # characters `brushwork render` writes on one image (a batch takes any number)
MAX_SEED = 2 ** 63 - 1


def check_bits(bits: int) -> int:
    if bits not in (8, 16):
        raise ValueError(f"--bits {bits}: expected 8 or 16")
    return bits


def check_seed(seed: int) -> int:
    if not 0 <= seed <= MAX_SEED:
        raise ValueError(f"--seed {seed}: expected a non-negative integer (0..2^63-1)")
    return seed


def text_chars(text: str) -> str:
    """The characters `render` writes: every non-space character of text, in order, a repeated
    one written again; ValueError when there are none or more than MAX_TEXT_CHARS."""
    chars = "".join(c for c in text if not c.isspace())
    if not chars:
        raise ValueError("no characters to render")
    if len(chars) > MAX_TEXT_CHARS:
        raise ValueError(f"{len(chars)} characters: `render` writes at most {MAX_TEXT_CHARS} on one image; "
                         "use `brushwork batch` for more")
    return chars


def check_request(chars: str, size: int, bits: int, samples: int | None, seed: int) -> None:
    """The numbers of a render request, checked before any work: size, bits, samples, seed and
    the image's width (chars x size px, at most writing.MAX_SIDE)."""
    check_size(size)
    check_bits(bits)
    check_samples(samples)
    check_seed(seed)
    if len(chars) * size > MAX_SIDE:
        raise ValueError(f"{len(chars)} characters x {size} px = {len(chars) * size} px wide: more than "
                         f"{MAX_SIDE}; use a smaller size or `brushwork batch`")


def text_paper(glyphs: list, size: int = 1024, style: Style | str = "kai", seed: int = 0,
               samples: int | None = None, counts: dict | None = None, paper: Paper | None = None,
               plans: str | os.PathLike | None = None) -> Paper:
    """A paper (len(glyphs) * size) x size px with the glyphs written left to right, one em box
    per glyph filling a size x size square, by one brush: ink and wetness carry from character
    to character (re-dipped at each), as in a hand-written line. samples: multisampling of the
    stroke layer (None: the style's scene, 4 unless it says otherwise; 1 is ~2.5x faster on a
    software renderer, with edges stepped at the pixel). counts: a dict that receives the frames
    written, the strokes broken (the brush down again after a lift within one stroke), the
    frames held (Writer._step), the beads at exits by stroke family (Writer.beads) and the
    solver's figures (Writer.solver). paper: one made earlier by writing_paper for as many glyphs
    at this size, style and samples, cleared and written again (a batch worker keeps one: a new 1024 px
    paper allocates and clears its textures, ~12 ms, and page-faults them in again as it draws).
    plans: a folder of plan files (brushwork fit): each glyph is written from its plan, in the
    source's em box."""
    st = style if isinstance(style, Style) else Style.load(style)
    if paper is None:
        paper = writing_paper(st, size, len(glyphs), samples)
    else:
        if (paper.width_px, paper.height_px) != (len(glyphs) * size, size):
            raise ValueError(f"a {paper.width_px} x {paper.height_px} px paper cannot take {len(glyphs)} "
                             f"character(s) at {size} px")
        paper.clear()
    writer = Writer(paper, st, seed)
    for k, glyph in enumerate(glyphs):
        if plans is not None:
            writer.write_planned(glyph, load_plan(plans, glyph.char, len(glyph.strokes)), (k * st.em_mm, 0.0))
        else:
            writer.write(glyph, origin_mm=(k * st.em_mm, 0.0))
    if counts is not None:
        counts.update(frames=writer.frames, breaks=writer.breaks, holds=writer.holds, beads=writer.beads,
                      solver=writer.solver)
    return paper


def writing_stats(counts: dict) -> dict:
    """The figures of a writing from text_paper's `counts`: frames, frames held, strokes broken,
    solver steps and those stopped at the iteration cap q_max, SQP iterations, sub-steps, the
    deepest penetration (mm), beads at exits by stroke family ([beaded, strokes])."""
    solver = counts["solver"]
    return {"frames": counts["frames"], "frames_held": counts["holds"], "strokes_broken": counts["breaks"],
            "solver_steps": solver["steps"], "frames_at_q_max": solver["steps_at_q_max"],
            "iterations": solver["iterations"], "substeps": solver["substeps"],
            "max_penetration_mm": solver["max_penetration_mm"], "beads": counts["beads"]}


def parse_charset(text: str) -> str:
    """The characters of a charset: every non-space character, in order, duplicates dropped."""
    return "".join(dict.fromkeys(c for c in text if not c.isspace()))


def read_charset(path: str | os.PathLike) -> str:
    """A charset file's characters; the names gb2312, gb2312-1 and gb2312-2 are built in."""
    builtin = None if Path(path).exists() else charsets.named(str(path))
    if builtin is not None:
        return builtin
    try:
        text = Path(path).read_text(encoding="utf-8")
    except UnicodeDecodeError as err:
        raise ValueError(f"{path}: not UTF-8 text: {err}") from None
    chars = parse_charset(text)
    if not chars:
        raise ValueError(f"{path}: no characters in the charset file")
    return chars


# --- the worker side (one process per job; each owns a brush, a GL context and its papers) ---
_JOB: dict = {}


def _init_worker(style_name: str, size: int, seed: int, bits: int, background: str, samples: int | None,
                 plans: str | None = None) -> None:
    # a paper kept from an earlier batch in this process (--jobs 1 runs here) has that batch's
    # size and scene: drop it
    _JOB.clear()
    _JOB.update(style=Style.load(style_name), size=size, seed=seed, bits=bits, background=background,
                samples=samples, plans=plans)


def _render_one(task: tuple) -> tuple:
    """(char, Glyph, output path) -> (char, seconds, error text or None). The worker keeps its
    paper from character to character (cleared each time); after a failure it makes a new one."""
    char, glyph, out = task
    t0 = time.perf_counter()
    try:
        paper = text_paper([glyph], _JOB["size"], _JOB["style"], _JOB["seed"], _JOB["samples"],
                           paper=_JOB.get("paper"), plans=_JOB.get("plans"))
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


class Progress:
    """A progress bar on stderr: redrawn in place on a terminal, a line every few seconds otherwise."""

    def __init__(self, total: int, stream=None, every_s: float = 5.0):
        self.total, self.done, self.failed = total, 0, 0
        self.stream = stream or sys.stderr
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.t0 = self.last = time.monotonic()
        self.every = every_s

    def update(self, ok: bool) -> None:
        self.done += 1
        self.failed += 0 if ok else 1
        now = time.monotonic()
        if self.tty or now - self.last >= self.every or self.done == self.total:
            self.last = now
            self._draw(now)

    def _draw(self, now: float) -> None:
        rate = self.done / max(now - self.t0, 1e-9)
        left = (self.total - self.done) / rate if rate > 0 else 0.0
        filled = int(30 * self.done / max(self.total, 1))
        line = (f"[{'#' * filled}{'.' * (30 - filled)}] {self.done}/{self.total}  {rate:.2f} chars/s  "
                f"ETA {int(left // 60)}:{int(left % 60):02d}" + (f"  {self.failed} failed" if self.failed else ""))
        self.stream.write(("\r" + line) if self.tty else (line + "\n"))
        self.stream.flush()

    def close(self) -> None:
        if self.tty:
            self.stream.write("\n")
            self.stream.flush()


def run_batch(chars: str, out_dir: str | os.PathLike, source: str = "default", jobs: int = 1,
              size: int = 1024, style: str = "kai", seed: int = 0, bits: int = 8, background: str = "white",
              progress: bool = True, variant: str | None = None, samples: int | None = None,
              executor: str = "local", plans: str | None = None) -> BatchResult:
    """Render each character of `chars` to out_dir/U+XXXX.png, skipping those already there
    (whole: a file that does not decode is rendered again), in local worker processes or on Ray;
    `plans`: a folder of plan files to write the characters from."""
    from .raymap import check_executor

    check_executor(executor)
    size, bits, seed, samples = check_size(size), check_bits(bits), check_seed(seed), check_samples(samples)
    Style.load(style)                                        # a bad style fails now, not in every worker
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
    _run_tasks(tasks, jobs, (style, size, seed, bits, background, samples, plans), result, progress, executor)
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


def parallel_map(fn, tasks: list, jobs: int, initializer, initargs: tuple, executor: str = "local"):
    """fn over tasks in `jobs` worker processes (in this one when jobs is 1), or as Ray tasks
    (executor "ray"), results in the order they finish. Workers are spawned, not forked: a forked
    child must not inherit a GL context."""
    if executor == "ray":
        from .raymap import ray_map

        yield from ray_map(fn, tasks, jobs, initializer, initargs)
        return
    if jobs == 1 or len(tasks) <= 1:
        initializer(*initargs)
        yield from map(fn, tasks)
        return
    # each worker rasterises on one thread: with as many workers as cores, llvmpipe's and
    # OpenBLAS's own threads only contend (2 jobs on 2 cores: 2.1 -> 2.8 chars/s measured)
    saved = {k: os.environ.get(k) for k in _ONE_THREAD}
    os.environ.update(_ONE_THREAD)
    try:
        pool = mp.get_context("spawn").Pool(min(jobs, len(tasks)), _quiet_init, (initializer, initargs))
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    with pool:
        yield from pool.imap_unordered(fn, tasks)


def _quiet_init(initializer, initargs: tuple) -> None:
    """A worker leaves Ctrl-C to the parent, which stops the pool and prints the summary."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    initializer(*initargs)


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
