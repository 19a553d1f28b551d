"""Fuzzing what reaches `brushwork paint`'s server: WebSocket messages (checked as the server checks
them, and now and then applied to a painting), and HTTP query strings and headers (through the
app's middleware and handlers on a mocked request). An input must end in a checked message, an
`error` of one short line, or an HTTP 4xx of one short line: never a traceback."""
from __future__ import annotations

import json
import random

from .fuzzcheck import ODD_VALUES

_TYPES = ["samples", "up", "undo", "clear", "dip", "settings", "ping", "paint", "", 3, None]
_KEYS = ["x", "y", "pressure", "tiltX", "tiltY", "tilt", "azimuth", "twist"]
_NUMBERS = [0, 1, -1, 0.5, 90, -90, 720, 1e5, -1e5, 1e400, 10 ** 400, float("nan"), float("inf")]


def _sample(rng: random.Random) -> dict:
    s = {"x": rng.uniform(-50, 1000), "y": rng.uniform(-50, 700), "pressure": rng.random()}
    for _ in range(rng.randrange(3)):
        s[rng.choice(_KEYS)] = rng.choice(ODD_VALUES + _NUMBERS)
    return s


def ws_message(rng: random.Random) -> str:
    """A message a page might send: mostly well formed, one thing odd, or not JSON."""
    kind = rng.choice(_TYPES)
    msg = {"type": kind, "seq": rng.choice([None, 1, rng.randrange(2 ** 53), -1, 2 ** 60, "a"])}
    if kind == "samples":
        msg["samples"] = [_sample(rng) for _ in range(rng.choice([0, 1, 3, 40, 256, 300]))]
    elif kind == "dip":
        msg.update(ink=rng.choice(ODD_VALUES + [0.5]), wetness=rng.choice([0.2, 1, -1, "x"]))
    elif kind == "settings":
        msg.update(rng.choice([{"preset": rng.choice(["small", "huge", 7])}, {"tufts": rng.choice([1, 5, 10, 1.5])},
                               {"scene": rng.choice([{"grain": True}, {"fog": True}, {"grain": 1}, []])}]))
    text = json.dumps(msg, allow_nan=True)
    text = text.replace("Infinity", "1" + "0" * rng.choice([3, 400, 5000])) if rng.random() < 0.2 else text
    if rng.random() < 0.1:
        text = text[:rng.randrange(len(text) + 1)]
    return text


class Painter:
    """The server's checks for one connection, and a small painting that applies what passes
    (made once, on the thread that runs the fuzz)."""

    def __init__(self):
        from ..paint.protocol import RATE, Bucket, Pen

        self.buckets = {k: Bucket(*v) for k, v in RATE.items()}
        self.pen, self.painting, self.applied = Pen(5.0), None, 0

    def check(self, text: str, apply: bool) -> str | None:
        """Why the server's handling of `text` broke the contract, or None."""
        from ..paint.protocol import admit, parse_message

        try:
            err = admit(text, self.buckets)
            if err is None:
                msg = parse_message(text)
                err = self.pen.budget(msg, self.buckets["frames"])
                if err is None and apply:
                    self._apply(msg)
        except ValueError as exc:
            err = str(exc)
        except Exception as exc:  # noqa: BLE001 - a traceback is what the fuzz looks for
            return f"traceback: {type(exc).__name__}: {exc!s:.200}"
        if err is not None and ("\n" in err or len(err) > 200):
            return f"an error of {len(err)} characters or several lines: {err[:120]}"
        return None

    def _apply(self, msg: dict) -> None:
        from ..paint.painting import Painting
        from ..paint.connection import message_events

        if self.painting is None:
            self.painting = Painting({"width_mm": 40, "height_mm": 30, "px_per_mm": 2.0})
        for ev in message_events(self.painting, msg):
            self.painting.apply(ev)
        self.applied += 1


# --- HTTP query strings and headers ---
_PATHS = ["/", "/image.png", "/log.json", "/static/paint.js", "/static/../../etc/passwd", "/ws"]
_QUERY_VALUES = ["", "abc", "16", "4096", "8192", "-1", "1e3", "0x10", "９９", "1" * 400, "%00", "%ff%fe", "é",
                 "16&size=32", "feedbeef"]
_HOSTS = ["127.0.0.1", "127.0.0.1:8765", "localhost", "evil.example", "[::1]:1", "", ":", "[", "a" * 300, "é.example"]


def http_request(rng: random.Random) -> tuple[str, dict]:
    """(path with query, headers) of a request."""
    query = "&".join(f"{rng.choice(['size', 'painting', 'token', 'x', ''])}={rng.choice(_QUERY_VALUES)}"
                     for _ in range(rng.randrange(4)))
    headers = {"Host": rng.choice(_HOSTS)}
    if rng.random() < 0.3:
        headers["Origin"] = rng.choice(["http://evil.example", "http://127.0.0.1:8765", "null", "x" * 500])
    return rng.choice(_PATHS) + ("?" + query if query else ""), headers


class Site:
    """The app's middleware and handlers, run on mocked requests in one event loop."""

    def __init__(self):
        import asyncio

        from ..paint.server import make_app

        self.loop = asyncio.new_event_loop()
        self.app = make_app(size=(128, 96), token=None)

    def close(self) -> None:
        self.loop.close()

    def check(self, path: str, headers: dict) -> str | None:
        from aiohttp import web
        from aiohttp.test_utils import make_mocked_request

        from ..paint.server import _ws

        async def one():
            request = make_mocked_request("GET", path, headers=headers, app=self.app)
            match = await self.app.router.resolve(request)
            match.add_app(self.app)
            request._match_info = match
            # (a WebSocket needs a connection: its Origin check alone)
            handler = _origin_only if match.handler is _ws else match.handler
            for mw in reversed(self.app.middlewares):
                handler = _wrap(mw, handler)
            return await handler(request)

        try:
            self.loop.run_until_complete(one())
        except web.HTTPException as exc:
            text = exc.text or ""
            if exc.status >= 500 or "\n" in text.strip() or len(text) > 300:
                return f"HTTP {exc.status}: {text[:120]}"
        except Exception as exc:  # noqa: BLE001 - a traceback is what the fuzz looks for
            return f"traceback: {type(exc).__name__}: {exc!s:.200}"
        return None


async def _origin_only(request):
    from aiohttp import web

    from ..paint.server import _check_origin

    _check_origin(request)
    return web.Response(text="would open a WebSocket")


def _wrap(middleware, handler):
    async def call(request):
        return await middleware(request, handler)
    return call
