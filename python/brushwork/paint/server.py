"""The web app of `brushwork paint`: the page, each painting as PNG and log, and a WebSocket that
takes pen samples and answers with the changed part of the paper (the protocol: docs/paint.md).

Each WebSocket connection paints a painting of its own (`connection.Connection`: its brush, pen, undo
and log, worked on a thread of its own); `GET /image.png` and `/log.json` name one with
`?painting=ID` (the `hello` message's `painting`), or take the only one. The event loop does no
painting: it checks messages, answers `ping` at once and passes the rest on. A re-render from the
log runs on a thread of its own too, within a budget of pixels and frames, and stops when its
client leaves or the server stops.
"""
from __future__ import annotations

import asyncio
import hmac
import ipaddress
import secrets
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from importlib import resources

from aiohttp import WSMsgType, web

from .painting import MAX_TUFTS, SCENE_FLAGS, show
from .protocol import MAX_FRAME, MAX_SAMPLES, RATE, Bucket, Pen, admit, parse_message
from .connection import Connection, png_bytes

DEFAULT_PPM = 5.0            # px per mm of the page's paper
MAX_PAINTINGS = 16           # paintings (connections) at once; another is told so and closed
RERENDER_MAX_PX = 4096       # px: the longest side the server re-renders (`brushwork replay` goes to 8192)
RERENDER_MAX_FRAMES = 200_000  # simulated frames a re-render may replay
RERENDER_SLOTS = 2           # re-renders at once (one per painting)
RERENDER_TIMEOUT_S = 120.0   # s: a re-render still running then is stopped
STATIC = {"": ("index.html", "text/html"), "paint.js": ("paint.js", "text/javascript"),
          "paint.css": ("paint.css", "text/css")}


def is_loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def host_name(host: str) -> str:
    """The name of a Host header or an address, without port or IPv6 brackets, lower case."""
    host = host.strip().lower()
    if host.startswith("["):
        return host[1:host.find("]")] if "]" in host else host
    return host.rsplit(":", 1)[0] if host.count(":") == 1 else host


class Server:
    """The paintings of one app and how each is made."""

    def __init__(self, settings: dict, log_dir: str | None):
        self.settings, self.log_dir = settings, log_dir
        self.connections: dict[str, Connection] = {}
        self.tasks: dict[str, asyncio.Task] = {}
        self.rerenders = 0                 # re-renders running
        self.stopping = threading.Event()  # set when the server stops: every re-render ends

    async def open(self, ws) -> Connection:
        conn = Connection(secrets.token_hex(4), ws, self.log_dir)
        self.connections[conn.id] = conn
        await conn.open(self.settings)
        self.tasks[conn.id] = asyncio.ensure_future(conn.run())
        return conn

    async def close(self, conn: Connection) -> None:
        self.connections.pop(conn.id, None)
        task = self.tasks.pop(conn.id, None)
        if task is not None:
            task.cancel()
        await conn.close()

    async def close_all(self) -> None:
        self.stopping.set()
        await asyncio.gather(*(self.close(s) for s in list(self.connections.values())), return_exceptions=True)

    def find(self, request: web.Request) -> Connection:
        """The painting ?painting=ID names, or the only one (HTTP 404 / 400 otherwise)."""
        sid = request.query.get("painting")
        if sid is not None:
            if sid not in self.connections or self.connections[sid].closed.is_set():
                raise web.HTTPNotFound(text=f"painting = {show(sid)}: no such painting (it ends when its page closes)")
            return self.connections[sid]
        if len(self.connections) == 1:
            return next(iter(self.connections.values()))
        raise web.HTTPBadRequest(text="painting: name one with ?painting=ID (the page's hello message)"
                                 if self.connections else "no painting: open the page to start one")

    @staticmethod
    def hello() -> dict:
        from .. import BrushModel

        return {"type": "hello", "presets": BrushModel.presets(), "flags": list(SCENE_FLAGS),
                "max_samples": MAX_SAMPLES, "max_tufts": MAX_TUFTS}


SERVER = web.AppKey("server", Server)


def _check_origin(request: web.Request) -> None:
    origin = request.headers.get("Origin")
    if origin is not None and origin.split("://", 1)[-1] != request.host:
        raise web.HTTPForbidden(text="cross-origin WebSocket refused")


async def _ws(request: web.Request) -> web.WebSocketResponse:
    _check_origin(request)
    server: Server = request.app[SERVER]
    ws = web.WebSocketResponse(max_msg_size=MAX_FRAME, heartbeat=30.0, timeout=1.0)
    await ws.prepare(request)
    if len(server.connections) >= MAX_PAINTINGS:
        await ws.send_json({"type": "error", "message": f"the server paints {MAX_PAINTINGS} paintings at "
                            "once: try again when one closes"})
        await ws.close()
        return ws
    conn = await server.open(ws)
    try:
        for msg in await conn.call(conn.greeting, server.hello()):
            await conn.send(msg)
        await _read(ws, conn)
    finally:
        await server.close(conn)
    return ws


async def _read(ws: web.WebSocketResponse, conn: Connection) -> None:
    """Check each message; answer pings at once, pass the rest to the painting's queue."""
    buckets = {k: Bucket(*v) for k, v in RATE.items()}
    pen = Pen(conn.painting.ppm)
    async for m in ws:
        if m.type != WSMsgType.TEXT:
            await conn.send({"type": "error", "message": "only text messages (JSON) are accepted"})
            continue
        err = admit(m.data, buckets)
        if err is None:
            try:
                msg = parse_message(m.data)
                err = pen.budget(msg, buckets["frames"])
            except ValueError as e:
                err = str(e)
        if err is not None:
            await conn.send({"type": "error", "message": err})
        elif msg["type"] == "ping":
            await conn.send({"type": "pong", "seq": msg["seq"]})
        else:
            await conn.queue.put(msg)


async def _static(request: web.Request) -> web.Response:
    name = request.match_info.get("name", "")
    if name not in STATIC:
        raise web.HTTPNotFound()
    file, kind = STATIC[name]
    text = resources.files("brushwork.paint").joinpath("static", file).read_text(encoding="utf-8")
    return web.Response(text=text, content_type=kind)


def parse_size(text: str) -> int:
    """?size=: a whole number of px, 16..RERENDER_MAX_PX (HTTP 400 naming `size` otherwise)."""
    if not text.isascii() or not text.isdigit() or not 16 <= int(text[:6]) <= RERENDER_MAX_PX:
        raise web.HTTPBadRequest(text=f"size = {show(text)}: expected a whole number of px, 16..{RERENDER_MAX_PX} "
                                 "(`brushwork replay LOG --size N` renders up to 8192)")
    return int(text)


async def _image(request: web.Request) -> web.Response:
    """A painting now, or (?size=N) re-rendered from its log with its longer side N px."""
    server: Server = request.app[SERVER]
    size = request.query.get("size")
    n = parse_size(size) if size is not None else None
    conn = server.find(request)
    if n is None:
        return web.Response(body=await conn.call(conn.png), content_type="image/png")
    body = await _rerender(request, server, conn, n)
    return web.Response(body=body, content_type="image/png",
                        headers={"Content-Disposition": f'attachment; filename="paint-{n}.png"'})


def _render_png(log: dict, size: int, cancel: threading.Event) -> bytes | str:
    """The log replayed at `size` as PNG, or why not (on a thread of its own: its own GL
    context, and the painting taken apart on it)."""
    from .replay import replay

    try:
        return png_bytes(replay(log, size, cancel).image())
    except Exception as err:  # noqa: BLE001 - said to the client; nothing held past this thread
        return show(str(err), 200)


async def _rerender(request: web.Request, server: Server, conn: Connection, size: int) -> bytes:
    """Re-render `conn`'s log at `size` within the budgets; stopped when its client leaves,
    the painting closes, the server stops or RERENDER_TIMEOUT_S passes."""
    frames = conn.painting.frames
    if frames > RERENDER_MAX_FRAMES:
        raise web.HTTPRequestEntityTooLarge(
            max_size=RERENDER_MAX_FRAMES, actual_size=frames,
            text=f"the painting holds {frames} simulated frames: the server re-renders at most "
                 f"{RERENDER_MAX_FRAMES}; save its log and use `brushwork replay`")
    if conn.rerendering or server.rerenders >= RERENDER_SLOTS:
        raise web.HTTPServiceUnavailable(text="a re-render is running: try again when it ends",
                                         headers={"Retry-After": "5"})
    log = await conn.call(conn.painting.log)
    log = {**log, "events": list(log["events"])}
    cancel = threading.Event()
    conn.rerendering, server.rerenders = True, server.rerenders + 1
    pool = ThreadPoolExecutor(1, thread_name_prefix=f"rerender-{conn.id}")
    try:
        job = asyncio.get_running_loop().run_in_executor(pool, _render_png, log, size, cancel)
        result = await _watch(job, cancel, request, server, conn)
    finally:
        cancel.set()
        pool.shutdown(wait=False)
        conn.rerendering, server.rerenders = False, server.rerenders - 1
    if isinstance(result, str):
        raise web.HTTPServiceUnavailable(text=f"re-render stopped: {result}")
    return result


async def _watch(job, cancel: threading.Event, request: web.Request, server: Server, conn: Connection):
    """The result of `job`, or `cancel` set once nobody waits for it any more."""
    deadline = time.monotonic() + RERENDER_TIMEOUT_S
    while not job.done():
        await asyncio.wait([job], timeout=0.2)
        transport = request.transport
        gone = transport is None or transport.is_closing()
        if gone or conn.closed.is_set() or server.stopping.is_set() or time.monotonic() > deadline:
            cancel.set()
    return await job


async def _log(request: web.Request) -> web.Response:
    conn = request.app[SERVER].find(request)
    return web.Response(text=await conn.call(conn.painting.log_json), content_type="application/json",
                        headers={"Content-Disposition": 'attachment; filename="paint-log.json"'})


def _guard(token: str | None, hosts: frozenset | None):
    """A middleware: every request's Host among `hosts` (None: any; DNS rebinding ends here) and,
    with a token, its ?token= equal to it (compared in constant time, as bytes)."""
    want = None if token is None else token.encode("utf-8")

    @web.middleware
    async def check(request: web.Request, handler):
        if hosts is not None and host_name(request.host) not in hosts:
            raise web.HTTPForbidden(text=f"Host {show(request.host)} refused: serving "
                                    f"{', '.join(sorted(hosts))} (--allow-host adds a name)")
        given = request.query.get("token", "").encode("utf-8", "surrogateescape")
        if want is not None and not hmac.compare_digest(given, want):
            raise web.HTTPForbidden(text="a token is needed: open the URL brushwork paint printed")
        return await handler(request)

    return check


def allowed_hosts(host: str, allow: tuple = ()) -> frozenset | None:
    """The Host names a server bound to `host` answers: that address, localhost (on loopback) and
    `allow`; None (any) for a wildcard address, which --token guards."""
    name = host_name(host)
    if name in ("0.0.0.0", "::", ""):
        return None
    names = {name, *(host_name(a) for a in allow)}
    if is_loopback(name):
        names |= {"localhost", "127.0.0.1", "::1"}
    return frozenset(names)


def make_app(size=(960, 640), preset: str = "medium", token: str | None = None,
             log_dir: str | None = None, px_per_mm: float = DEFAULT_PPM, tufts: int = 1,
             host: str = "127.0.0.1", allow_hosts: tuple = ()) -> web.Application:
    """The app: each connection paints a fresh painting `size` px (width, height) with the
    `preset` brush of `tufts` tufts (the main one and the children it may split into); its log
    goes to `log_dir` (None: none). Requests must name `host` (or `allow_hosts`) as their Host."""
    w, h = size
    settings = {"width_mm": w / px_per_mm, "height_mm": h / px_per_mm, "px_per_mm": px_per_mm,
                "preset": preset, "tufts": tufts, "scene": {"depletion": True}}
    app = web.Application(middlewares=[_guard(token, allowed_hosts(host, allow_hosts))], client_max_size=MAX_FRAME)
    app[SERVER] = Server(settings, log_dir)
    app.router.add_get("/", _static)
    app.router.add_get("/static/{name}", _static)
    app.router.add_get("/image.png", _image)
    app.router.add_get("/log.json", _log)
    app.router.add_get("/ws", _ws)

    async def stop(app: web.Application) -> None:
        await app[SERVER].close_all()

    app.on_shutdown.append(stop)
    return app


STOP_GRACE_S = 4.0           # s: after SIGTERM, work still running then is abandoned


async def serve(app: web.Application, host: str, port: int, announce) -> None:
    """Serve `app` until SIGINT or SIGTERM (then every painting's log is written); `announce(port)`
    once it listens. The process ends within STOP_GRACE_S of the signal whatever runs."""
    import signal

    stop = asyncio.Event()
    for sig in (signal.SIGINT, signal.SIGTERM):
        asyncio.get_running_loop().add_signal_handler(sig, stop.set)
    runner = web.AppRunner(app, shutdown_timeout=1.0)
    await runner.setup()
    try:
        site = web.TCPSite(runner, host, port)
        await site.start()
        bound = site._server.sockets[0].getsockname()[1] if port == 0 else port
        announce(bound)
        await stop.wait()
        _exit_after(STOP_GRACE_S)
    finally:
        app[SERVER].stopping.set()
        await runner.cleanup()


def _exit_after(seconds: float) -> None:
    """End the process `seconds` from now if it is still running (a thread deep in a frame)."""
    import os
    import sys

    def force() -> None:
        print("brushwork paint: stopped with work unfinished", file=sys.stderr, flush=True)
        os._exit(1)

    timer = threading.Timer(seconds, force)
    timer.daemon = True
    timer.start()
