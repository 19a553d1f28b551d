"""What every fuzz check shares: the odd values broken inputs carry, a time limit, and the verdict
on a loader that must end in its value or one line of its own error."""
from __future__ import annotations

import contextlib
import signal
from typing import Callable

TIMEOUT_S = 20.0      # an input running longer than this is a hang

# numbers a broken input puts where a value belongs: edge values, wrong types, huge, tiny, non-finite
ODD_VALUES = [0, -1, 1, 2.5, 1e300, -1e300, 1e-300, 1e6, -1e6, float("nan"), float("inf"), "abc", "", None, True,
              [], {}, [1], [[0, 0]], 10 ** 30]


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
