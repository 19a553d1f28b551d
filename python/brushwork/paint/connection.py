"""One painting per WebSocket connection: its own brush, pen, undo and motion log, painted on a
thread of its own.

An EGL context is current on one thread at a time, so each painting's thread makes its `Painting`
(paper, brush, brush view: its own GL context) and does every piece of its work: the event loop
only reads messages, checks them, and sends what the thread made. Messages waiting together are
applied together and answered by one tile, so a slow paper never falls behind the pen by more
than one readback; `closed` set (the client left, the server stops) stops the work between two
events, and the painting is taken apart on its own thread.
"""
from __future__ import annotations

import asyncio
import base64
import json
import os
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from .painting import Painting, show, unite

QUEUE_MAX = 64               # messages waiting for the painting's thread; the reader waits beyond
VIEW_PX = 256                # side of the brush view, px
VIEW_PERIOD = 0.1            # s: the brush view is re-rendered at most this often, when idle
LOG_PERIOD = 2.0             # s: the log file is rewritten at most this often, when idle


def png_bytes(rgb: np.ndarray) -> bytes:
    """(h, w, 3) uint8 RGB -> PNG."""
    import cv2

    ok, data = cv2.imencode(".png", np.ascontiguousarray(rgb[..., ::-1]))
    if not ok:
        raise RuntimeError("PNG encoding failed")
    return data.tobytes()


def message_events(painting: Painting, msg: dict) -> list:
    """The painting events of a checked message (a ping has none: the event loop answers it)."""
    kind = msg["type"]
    if kind == "ping":
        return []
    if kind == "samples":
        return [painting.sample_pose(*s) for s in msg["samples"]]
    if kind == "dip":
        return [["dip"] + msg["dip"]]
    if kind == "settings":
        return [["settings", msg["change"]]]
    return [[kind]]


def create_log(folder: str, stamp: str, sid: str) -> str:
    """A new, empty log file paint-STAMP-ID.json in `folder` (created exclusively: never another's)."""
    for k in range(100):
        path = os.path.join(folder, f"paint-{stamp}-{sid}{f'-{k}' if k else ''}.json")
        try:
            with open(path, "x", encoding="utf-8"):
                return path
        except FileExistsError:
            continue
    raise OSError(f"{folder}: no free log name for paint-{stamp}-{sid}")


class Connection:
    """A painting and the connection that paints it; `call` runs work on the painting's thread."""

    def __init__(self, sid: str, ws, log_dir: str | None = None):
        self.id, self.ws, self.log_dir = sid, ws, log_dir
        self.log_path: str | None = None
        self.queue: asyncio.Queue = asyncio.Queue(maxsize=QUEUE_MAX)
        self.closed = threading.Event()
        self.executor = ThreadPoolExecutor(1, thread_name_prefix=f"painting-{sid}")
        self.painting: Painting | None = None
        self.view = None                   # the BrushView, made on first use
        self.view_t = self.log_t = 0.0
        self.dirty_view = self.dirty_log = True
        self.rerendering = False           # a re-render of this painting is running

    async def call(self, fn, *args):
        """fn(*args) on the painting's thread."""
        return await asyncio.get_running_loop().run_in_executor(self.executor, fn, *args)

    async def open(self, settings: dict) -> None:
        self.painting = await self.call(Painting, settings)

    async def run(self) -> None:
        """Apply the queued messages in order, answer each batch with one tile, and do the idle
        work (brush view, undo's copy of the paper, the log file) when none waits."""
        while not self.closed.is_set():
            jobs = [await self.queue.get()]
            while not self.queue.empty():
                jobs.append(self.queue.get_nowait())
            await self.send(await self.call(self.apply, jobs))
            if self.queue.empty() and not self.closed.is_set():
                view = await self.call(self.idle)
                if view is not None:
                    await self.send(view)

    # --- on the painting's thread
    def apply(self, jobs: list) -> dict:
        """The events of `jobs` applied; the tile answering the last (or an error)."""
        s, rect, full = self.painting, None, False
        try:
            for msg in jobs:
                for ev in message_events(s, msg):
                    if self.closed.is_set():
                        return {"type": "error", "message": "the painting is closing"}
                    rect = unite(rect, s.apply(ev))
                    full = full or ev[0] in ("undo", "clear", "settings")
        except Exception as err:  # noqa: BLE001 - the core refused an event: tell, keep painting
            return {"type": "error", "message": f"painting failed: {show(str(err), 200)}"}
        finally:
            self.dirty_view = self.dirty_log = True
        seq = next((m["seq"] for m in reversed(jobs) if m["seq"] is not None), None)
        return self.tile_message(s.full_rect() if full else rect, seq)

    def idle(self) -> dict | None:
        """Work for when no message waits: undo's copy of the paper, the log file; the brush
        view's message when it is due."""
        now = time.monotonic()
        self.painting.prepare_undo()
        if self.dirty_log and self.log_dir and now - self.log_t >= LOG_PERIOD:
            self.write_log()
        if self.dirty_view and now - self.view_t >= VIEW_PERIOD:
            self.view_t, self.dirty_view = now, False
            return self.view_message()
        return None

    def write_log(self) -> None:
        """The motion log to its file (made on the first write, so a painting without a single
        event leaves none)."""
        from ..files import write_atomic

        if not self.painting.events:
            return
        if self.log_path is None:
            self.log_path = create_log(self.log_dir, time.strftime("%Y%m%d-%H%M%S"), self.id)
        text = self.painting.log_json()

        def write(tmp: str) -> None:
            with open(tmp, "w", encoding="utf-8") as f:
                f.write(text)

        write_atomic(self.log_path, write, suffix=".json")
        self.log_t, self.dirty_log = time.monotonic(), False

    def view_message(self) -> dict:
        from ..view import BrushView

        if self.view is None:
            self.view = BrushView(VIEW_PX, VIEW_PX)
        rgba = self.view.render(self.painting.brush, self.painting.paper)
        return {"type": "view", "png": base64.b64encode(png_bytes(rgba[..., :3])).decode()}

    def tile_message(self, rect, seq=None) -> dict:
        """The paper inside `rect` (px, y up) as a PNG tile placed at (x, y) on the canvas (y down)."""
        s = self.painting
        w, h = s.size_px
        msg = {"type": "tile", "seq": seq, "down": s.down, "contact": s.contact_px()}
        if rect is not None:
            x0, y0, x1, y1 = max(rect[0], 0), max(rect[1], 0), min(rect[2], w), min(rect[3], h)
            if x0 < x1 and y0 < y1:
                crop = s.image()[h - y1:h - y0, x0:x1]
                msg.update(x=x0, y=h - y1, w=x1 - x0, h=y1 - y0, png=base64.b64encode(png_bytes(crop)).decode())
        return msg

    def greeting(self, hello: dict) -> list:
        """The first messages: hello, the whole paper, the brush view."""
        s = self.painting
        hello = {**hello, "painting": self.id, "width": s.size_px[0], "height": s.size_px[1], "settings": s.settings}
        return [hello, self.tile_message(s.full_rect()), self.view_message()]

    def png(self) -> bytes:
        return png_bytes(self.painting.image())

    def finish(self) -> None:
        """The last log write; the painting and its brush view taken apart here, on their thread."""
        try:
            if self.log_dir:
                self.write_log()
        finally:
            self.painting = self.view = None

    # --- on the event loop
    async def send(self, msg: dict) -> None:
        try:
            await self.ws.send_str(json.dumps(msg))
        except (ConnectionError, RuntimeError):
            pass                           # (the connection is closing: its reader ends it)

    async def close(self) -> None:
        """Stop the work in flight, close the connection, write the log and free the painting on
        its thread (once)."""
        if self.closed.is_set():
            return
        self.closed.set()
        while not self.queue.empty():
            self.queue.get_nowait()
        try:
            await self.ws.close()
            await self.call(self.finish)
        finally:
            self.executor.shutdown(wait=False)
