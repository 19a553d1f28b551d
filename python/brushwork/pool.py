"""Work spread over processes: a function over tasks in local worker processes or as Ray tasks
(`--executor ray`), each worker set up once by an initialiser, results in the order they finish,
and a progress bar for the caller.

Ray is optional (`pip install brushwork[ray]`); RAY_ADDRESS names a cluster to join, and without
one a local cluster is started on this machine."""
from __future__ import annotations

import multiprocessing as mp
import os
import sys
import time

EXECUTORS = ("local", "ray")

# each worker on one core: llvmpipe rasterises in the calling thread (LP_NUM_THREADS=0; with 1
# it hands every draw to a second thread and the two take turns: ~18% slower, measured on
# kai 1024 px with one sample), one BLAS thread
_ONE_THREAD = {"LP_NUM_THREADS": "0", "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}


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


def check_executor(name: str) -> str:
    """name when it is an executor brushwork knows and can use here; ValueError otherwise."""
    if name not in EXECUTORS:
        raise ValueError(f"--executor {name!r}: expected one of {', '.join(EXECUTORS)}")
    if name == "ray":
        try:
            import ray  # noqa: F401
        except ImportError:
            raise ValueError("--executor ray needs Ray: pip install 'brushwork[ray]'") from None
    return name


def parallel_map(fn, tasks: list, jobs: int, initializer, initargs: tuple, executor: str = "local"):
    """fn over tasks in `jobs` worker processes (in this one when jobs is 1), or as Ray tasks
    (executor "ray"), results in the order they finish. Workers are spawned, not forked: a forked
    child must not inherit a GL context."""
    if executor == "ray":
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


# --- Ray: the same worker functions, each Ray worker process initialised once per batch ---
_READY: dict = {}     # in a Ray worker: the (initializer, initargs) it was last set up with


def _ray_run(fn, initializer, initargs: tuple, task):
    """One task in a Ray worker, after setting the worker up when this batch has not yet."""
    key = (initializer, initargs)
    if _READY.get("key") != key:
        initializer(*initargs)
        _READY["key"] = key
    return fn(task)


def _ray_start(jobs: int) -> None:
    """Join the cluster RAY_ADDRESS names, or start a local one of `jobs` CPUs; the workers see
    this process's brushwork (its folder goes onto their PYTHONPATH) and draw on one thread."""
    import ray

    if ray.is_initialized():
        return
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    path = os.pathsep.join(p for p in (here, os.environ.get("PYTHONPATH", "")) if p)
    env = dict(_ONE_THREAD, PYTHONPATH=path)
    address = os.environ.get("RAY_ADDRESS")
    ray.init(address=address, num_cpus=None if address else jobs, include_dashboard=False,
             log_to_driver=False, runtime_env={"env_vars": env}, logging_level="ERROR")


def ray_map(fn, tasks: list, jobs: int, initializer, initargs: tuple):
    """fn over tasks as Ray tasks of one CPU each, results in the order they finish."""
    import ray

    _ray_start(jobs)
    remote = ray.remote(num_cpus=1)(_ray_run)
    pending = [remote.remote(fn, initializer, initargs, t) for t in tasks]
    while pending:
        done, pending = ray.wait(pending, num_returns=1)
        yield ray.get(done[0])
