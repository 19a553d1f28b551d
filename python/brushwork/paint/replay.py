"""Render a painting's motion log (`Painting.log()`, the page's /log.json) without a browser:
`brushwork replay LOG -o out.png [--size N]`."""
from __future__ import annotations

import json
import os

from .painting import LOG_FORMAT, MAX_PX, Painting, check_event

MAX_LOG_BYTES = 256 * 1024 * 1024


def read_log(path: str | os.PathLike) -> dict:
    """The log at `path`, its settings and events checked (ValueError naming what is wrong)."""
    path = os.fspath(path)
    if os.path.getsize(path) > MAX_LOG_BYTES:
        raise ValueError(f"{path}: larger than {MAX_LOG_BYTES // 2**20} MiB")
    with open(path, encoding="utf-8") as f:
        try:
            log = json.load(f)
        except (json.JSONDecodeError, UnicodeDecodeError) as err:
            raise ValueError(f"{path}: not a JSON log ({err})") from None
        except RecursionError:
            raise ValueError(f"{path}: not a JSON log (nested too deeply)") from None
    if not isinstance(log, dict) or log.get("format") != LOG_FORMAT or log.get("version") != 1:
        raise ValueError(f"{path}: not a {LOG_FORMAT} log of version 1")
    if not isinstance(log.get("events"), list):
        raise ValueError(f"{path}: events: expected a list")
    try:
        settings = log.get("settings")
        events = [check_event(ev) for ev in log["events"]]
    except ValueError as err:
        raise ValueError(f"{path}: {err}") from None
    return {"settings": settings, "events": events}


class Cancelled(Exception):
    """A replay stopped because its `cancel` event was set."""


def replay(log: dict, size: int | None = None, cancel=None) -> Painting:
    """A painting that has applied every event of `log`; `size`: the longer side of the paper in
    px (default: the size it was painted at). `cancel` (a threading.Event) set stops it between
    two events with Cancelled."""
    s = log["settings"]
    ppm = None
    if size is not None:
        if not 16 <= size <= MAX_PX:
            raise ValueError(f"size {size}: expected 16..{MAX_PX} px (the longer side)")
        ppm = size / max(s["width_mm"], s["height_mm"])
    painting = Painting(s, px_per_mm=ppm)
    for ev in log["events"]:
        if cancel is not None and cancel.is_set():
            raise Cancelled("the replay was cancelled")
        painting.apply(ev)
    return painting


def replay_file(path: str | os.PathLike, out: str | os.PathLike, size: int | None = None) -> tuple:
    """Render the log at `path` into the image `out`; (width, height, events)."""
    from ..files import check_image_path, save_paper

    log = read_log(path)
    check_image_path(out)
    try:
        painting = replay(log, size)
    except ValueError as err:
        raise ValueError(f"{os.fspath(path)}: {err}") from None
    save_paper(painting.paper, out)
    return painting.paper.width_px, painting.paper.height_px, len(log["events"])
