"""The web app of `brushwork paint`: the page, the paper as PNG, and a WebSocket that takes pen
samples and answers with the changed part of the paper (the protocol: README "Painting").

Every message is handled in order by one worker that owns the `Painting` (the core's GL context
lives on the event loop's thread): messages waiting together are applied together and answered by
one tile, so a slow paper never falls behind the pen by more than one readback.
"""
from __future__ import annotations

import asyncio
import base64
import hmac
import ipaddress
import json
import math
import os
import time
from importlib import resources

import numpy as np
from aiohttp import WSMsgType, web

from .painting import MAX_TUFTS, SCENE_FLAGS, Painting, check_change, unite

MAX_MESSAGE = 64 * 1024      # bytes: a longer text message is refused with an error
MAX_FRAME = 1024 * 1024      # bytes: a longer frame closes the connection (aiohttp's limit)
MAX_SAMPLES = 256            # samples in one message
RATE = {"messages": (200.0, 400.0), "samples": (2000.0, 4000.0)}   # per second, burst
QUEUE_MAX = 64               # messages waiting for the worker; the reader waits beyond
VIEW_PX = 256                # side of the brush view, px
VIEW_PERIOD = 0.1            # s: the brush view is re-rendered at most this often, when idle
LOG_PERIOD = 2.0             # s: the log file is rewritten at most this often, when idle
DEFAULT_PPM = 5.0            # px per mm of the page's paper
STATIC = {"": ("index.html", "text/html"), "paint.js": ("paint.js", "text/javascript"),
          "paint.css": ("paint.css", "text/css")}


def is_loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def png_bytes(rgb: np.ndarray) -> bytes:
    """(h, w, 3) uint8 RGB -> PNG."""
    import cv2

    ok, data = cv2.imencode(".png", np.ascontiguousarray(rgb[..., ::-1]))
    if not ok:
        raise RuntimeError("PNG encoding failed")
    return data.tobytes()


class Bucket:
    """A token bucket: `rate` per second, at most `burst` at once."""

    def __init__(self, rate: float, burst: float):
        self.rate, self.burst, self.level, self.t = rate, burst, burst, time.monotonic()

    def take(self, n: float) -> bool:
        now = time.monotonic()
        self.level = min(self.burst, self.level + (now - self.t) * self.rate)
        self.t = now
        if n > self.level:
            return False
        self.level -= n
        return True


def _num(obj: dict, key: str, lo: float, hi: float, default=None) -> float:
    v = obj.get(key, default)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or not lo <= v <= hi:
        raise ValueError(f"{key} = {str(v)[:20]}: expected a number in {lo:g}..{hi:g}")
    return float(v)


def pen_angles(tilt_x: float, tilt_y: float) -> tuple[float, float]:
    """Pointer Events' tiltX, tiltY (deg, the pen leaning toward +x right and +y down the
    screen) -> (tilt from the normal, azimuth on the paper counter-clockwise from +x, y up), deg."""
    tx, ty = math.tan(math.radians(tilt_x)), math.tan(math.radians(tilt_y))
    tilt = math.degrees(math.atan(math.hypot(tx, ty)))
    return tilt, (math.degrees(math.atan2(-ty, tx)) if tilt > 0 else 0.0)


def parse_sample(s) -> tuple:
    """One sample of a `samples` message -> (x, y, pressure, tilt, azimuth, twist): x, y canvas
    px (y down); either tiltX, tiltY (deg) or tilt, azimuth (deg, paper frame); twist deg."""
    if not isinstance(s, dict):
        raise ValueError("a sample must be an object")
    xy = _num(s, "x", -1e5, 1e5), _num(s, "y", -1e5, 1e5)
    pressure = _num(s, "pressure", 0.0, 1.0, 0.5)
    if "tiltX" in s or "tiltY" in s:
        angles = pen_angles(_num(s, "tiltX", -90, 90, 0.0), _num(s, "tiltY", -90, 90, 0.0))
    else:
        angles = _num(s, "tilt", 0.0, 90.0, 0.0), _num(s, "azimuth", -720.0, 720.0, 0.0)
    return xy + (pressure,) + angles + (_num(s, "twist", -360.0, 720.0, 0.0),)


def parse_message(text: str) -> dict:
    """A client's text message, checked: {"type", "seq", ...} (ValueError naming the problem)."""
    try:
        msg = json.loads(text)
    except (ValueError, RecursionError):      # (RecursionError: nested too deeply)
        raise ValueError("not JSON, or nested too deeply") from None
    if not isinstance(msg, dict) or not isinstance(msg.get("type"), str):
        raise ValueError("expected an object with a string `type`")
    seq = msg.get("seq")
    if seq is not None and (isinstance(seq, bool) or not isinstance(seq, int) or not 0 <= seq < 2 ** 53):
        raise ValueError("seq: expected a non-negative integer")
    return {"type": msg["type"], "seq": seq, **_body(msg)}


def _body(msg: dict) -> dict:
    """The checked contents of a message of each type."""
    kind = msg["type"]
    if kind == "samples":
        samples = msg.get("samples")
        if not isinstance(samples, list) or not 1 <= len(samples) <= MAX_SAMPLES:
            raise ValueError(f"samples: expected a list of 1..{MAX_SAMPLES} samples")
        return {"samples": [parse_sample(s) for s in samples]}
    if kind == "dip":
        return {"dip": [_num(msg, "ink", 0.0, 1.0, 1.0), _num(msg, "wetness", 0.0, 1.0, 1.0)]}
    if kind == "settings":
        return {"change": check_change({k: msg[k] for k in ("preset", "tufts", "scene") if k in msg})}
    if kind not in ("up", "undo", "clear"):
        raise ValueError(f"unknown type {kind[:20]!r}")
    return {}


def message_events(painting: Painting, msg: dict) -> list:
    """The painting events of a checked message."""
    kind = msg["type"]
    if kind == "samples":
        return [painting.sample_pose(*s) for s in msg["samples"]]
    if kind == "dip":
        return [["dip"] + msg["dip"]]
    if kind == "settings":
        return [["settings", msg["change"]]]
    return [[kind]]


class Painter:
    """The painting and its clients: a queue of checked messages, one worker applying them."""

    def __init__(self, painting: Painting, log_path: str | None = None):
        self.painting, self.log_path = painting, log_path
        self.queue: asyncio.Queue = asyncio.Queue(maxsize=QUEUE_MAX)
        self.sockets: set = set()
        self.view = None                   # the BrushView, made on first use
        self.view_t = self.log_t = 0.0
        self.dirty_view = self.dirty_log = True

    async def run(self) -> None:
        while True:
            jobs = [await self.queue.get()]
            while not self.queue.empty():
                jobs.append(self.queue.get_nowait())
            try:
                await self._apply(jobs)
            except Exception as err:  # noqa: BLE001 - the core refused an event: tell, keep painting
                await self.broadcast({"type": "error", "message": f"painting failed: {err}"})
            if self.queue.empty():
                await self._idle()

    async def _apply(self, jobs: list) -> None:
        s = self.painting
        rect, seqs, full = None, {}, False
        for ws, msg in jobs:
            for ev in message_events(s, msg):
                r = s.apply(ev)
                full = full or ev[0] in ("undo", "clear", "settings")
                rect = unite(rect, r)
            seqs[ws] = msg["seq"]
        self.dirty_view = self.dirty_log = True
        await self.send_tile(s.full_rect() if full else rect, seqs)

    async def _idle(self) -> None:
        """Work for when no message waits: the brush view, undo's copy of the paper, the log file."""
        now = time.monotonic()
        if self.dirty_view and now - self.view_t >= VIEW_PERIOD and self.sockets:
            await self.broadcast(self.view_message())
            self.view_t, self.dirty_view = now, False
        self.painting.prepare_undo()
        if self.dirty_log and self.log_path and now - self.log_t >= LOG_PERIOD:
            self.write_log()

    def write_log(self) -> None:
        from ..files import write_atomic

        def write(tmp: str) -> None:
            with open(tmp, "w", encoding="utf-8") as f:
                json.dump(self.painting.log(), f, separators=(",", ":"))

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

    async def send_tile(self, rect, seqs: dict) -> None:
        msg = self.tile_message(rect)
        for ws in list(self.sockets):
            await self.send(ws, {**msg, "seq": seqs.get(ws)})

    async def send(self, ws, msg: dict) -> None:
        try:
            await ws.send_str(json.dumps(msg))
        except (ConnectionError, RuntimeError):
            self.sockets.discard(ws)

    async def broadcast(self, msg: dict) -> None:
        for ws in list(self.sockets):
            await self.send(ws, msg)

    def hello(self) -> dict:
        s = self.painting
        from .. import BrushModel

        return {"type": "hello", "width": s.size_px[0], "height": s.size_px[1], "settings": s.settings,
                "presets": BrushModel.presets(), "flags": list(SCENE_FLAGS), "max_samples": MAX_SAMPLES,
                "max_tufts": MAX_TUFTS}


PAINTER = web.AppKey("painter", Painter)


async def _ws(request: web.Request) -> web.WebSocketResponse:
    origin = request.headers.get("Origin")
    if origin is not None and origin.split("://", 1)[-1] != request.host:
        raise web.HTTPForbidden(text="cross-origin WebSocket refused")
    painter: Painter = request.app[PAINTER]
    ws = web.WebSocketResponse(max_msg_size=MAX_FRAME, heartbeat=30.0)
    await ws.prepare(request)
    painter.sockets.add(ws)
    await painter.send(ws, painter.hello())
    await painter.send(ws, painter.tile_message(painter.painting.full_rect()))
    await painter.send(ws, painter.view_message())
    buckets = {k: Bucket(*v) for k, v in RATE.items()}
    try:
        async for m in ws:
            if m.type != WSMsgType.TEXT:
                await painter.send(ws, {"type": "error", "message": "only text messages (JSON) are accepted"})
                continue
            err = _admit(m.data, buckets)
            if err is None:
                try:
                    await painter.queue.put((ws, parse_message(m.data)))
                    continue
                except ValueError as e:
                    err = str(e)
            await painter.send(ws, {"type": "error", "message": err})
    finally:
        painter.sockets.discard(ws)
    return ws


def _admit(text: str, buckets: dict) -> str | None:
    """Why a message is refused before it is read (size, rate), or None."""
    if len(text) > MAX_MESSAGE:
        return f"message of {len(text)} bytes refused: at most {MAX_MESSAGE}"
    if not buckets["messages"].take(1):
        return "too many messages: slow down"
    if not buckets["samples"].take(min(text.count("{"), MAX_SAMPLES)):
        return "too many samples: slow down"
    return None


async def _static(request: web.Request) -> web.Response:
    name = request.match_info.get("name", "")
    if name not in STATIC:
        raise web.HTTPNotFound()
    file, kind = STATIC[name]
    text = resources.files("brushwork.paint").joinpath("static", file).read_text(encoding="utf-8")
    return web.Response(text=text, content_type=kind)


async def _image(request: web.Request) -> web.Response:
    """The paper now, or (?size=N) re-rendered from the log with its longer side N px."""
    painting: Painting = request.app[PAINTER].painting
    size = request.query.get("size")
    if size is None:
        return web.Response(body=png_bytes(painting.image()), content_type="image/png")
    from .replay import replay

    try:
        paper = replay(painting.log(), int(size)).paper
    except ValueError as err:
        raise web.HTTPBadRequest(text=str(err)) from None
    return web.Response(body=png_bytes(paper.image()), content_type="image/png",
                        headers={"Content-Disposition": f'attachment; filename="paint-{size}.png"'})


async def _log(request: web.Request) -> web.Response:
    return web.json_response(request.app[PAINTER].painting.log(),
                             headers={"Content-Disposition": 'attachment; filename="paint-log.json"'})


def _token_check(token: str | None):
    @web.middleware
    async def check(request: web.Request, handler):
        if token is not None and not hmac.compare_digest(request.query.get("token", ""), token):
            raise web.HTTPForbidden(text="a token is needed: open the URL brushwork paint printed")
        return await handler(request)

    return check


def make_app(size=(960, 640), preset: str = "medium", token: str | None = None,
             log_path: str | None = None, px_per_mm: float = DEFAULT_PPM, tufts: int = 1) -> web.Application:
    """The app: a fresh painting `size` px (width, height) with the `preset` brush of `tufts`
    tufts (the main one and the children it may split into)."""
    w, h = size
    painting = Painting({"width_mm": w / px_per_mm, "height_mm": h / px_per_mm, "px_per_mm": px_per_mm,
                       "preset": preset, "tufts": tufts, "scene": {"depletion": True}})
    app = web.Application(middlewares=[_token_check(token)], client_max_size=MAX_FRAME)
    app[PAINTER] = Painter(painting, log_path)
    app.router.add_get("/", _static)
    app.router.add_get("/static/{name}", _static)
    app.router.add_get("/image.png", _image)
    app.router.add_get("/log.json", _log)
    app.router.add_get("/ws", _ws)

    async def worker(app: web.Application):
        task = asyncio.ensure_future(app[PAINTER].run())
        yield
        task.cancel()
        if app[PAINTER].log_path:
            app[PAINTER].write_log()

    app.cleanup_ctx.append(worker)
    return app


async def serve(app: web.Application, host: str, port: int, announce) -> None:
    """Serve `app` until SIGINT or SIGTERM (then the log is written); `announce(port)` once it listens."""
    import signal

    stop = asyncio.Event()
    for sig in (signal.SIGINT, signal.SIGTERM):
        asyncio.get_running_loop().add_signal_handler(sig, stop.set)
    runner = web.AppRunner(app)
    await runner.setup()
    try:
        site = web.TCPSite(runner, host, port)
        await site.start()
        bound = site._server.sockets[0].getsockname()[1] if port == 0 else port
        announce(bound)
        await stop.wait()
    finally:
        await runner.cleanup()
