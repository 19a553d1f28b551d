"""Glyph tasks on a Ray cluster (`--executor ray`): the same worker functions a local process
pool runs, each Ray worker process initialised once per batch, results in the order they finish.
Ray is optional (`pip install brushwork[ray]`); RAY_ADDRESS names a cluster to join, and without
one a local cluster is started on this machine."""
from __future__ import annotations

import os

EXECUTORS = ("local", "ray")

_READY: dict = {}     # in a Ray worker: the (initializer, initargs) it was last set up with


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


def _run(fn, initializer, initargs: tuple, task):
    """One task in a Ray worker, after setting the worker up when this batch has not yet."""
    key = (initializer, initargs)
    if _READY.get("key") != key:
        initializer(*initargs)
        _READY["key"] = key
    return fn(task)


def _start(jobs: int) -> None:
    """Join the cluster RAY_ADDRESS names, or start a local one of `jobs` CPUs; the workers see
    this process's brushwork (its folder goes onto their PYTHONPATH) and draw on one thread."""
    import ray

    if ray.is_initialized():
        return
    from .batch import _ONE_THREAD

    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    path = os.pathsep.join(p for p in (here, os.environ.get("PYTHONPATH", "")) if p)
    env = dict(_ONE_THREAD, PYTHONPATH=path)
    address = os.environ.get("RAY_ADDRESS")
    ray.init(address=address, num_cpus=None if address else jobs, include_dashboard=False,
             log_to_driver=False, runtime_env={"env_vars": env}, logging_level="ERROR")


def ray_map(fn, tasks: list, jobs: int, initializer, initargs: tuple):
    """fn over tasks as Ray tasks of one CPU each, results in the order they finish."""
    import ray

    _start(jobs)
    remote = ray.remote(num_cpus=1)(_run)
    pending = [remote.remote(fn, initializer, initargs, t) for t in tasks]
    while pending:
        done, pending = ray.wait(pending, num_returns=1)
        yield ray.get(done[0])
