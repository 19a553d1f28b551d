"""The messages a page sends over the WebSocket, checked before any work (the protocol:
docs/paint.md): size, rate and work budgets, and every value's type and range. A refusal is a
ValueError of one short line that never echoes a long input in full."""
from __future__ import annotations

import json
import math
import time

from .painting import STEP_MM, SUBSTEPS_MAX, check_change, show

MAX_MESSAGE = 64 * 1024      # bytes: a longer text message is refused with an error
MAX_FRAME = 1024 * 1024      # bytes: a longer frame closes the connection (aiohttp's limit)
MAX_SAMPLES = 256            # samples in one message
# per second and burst, per connection: messages, samples, and simulated frames (the work a
# samples message asks for: each sample SUBSTEPS_MAX frames at most, one per STEP_MM of travel)
RATE = {"messages": (200.0, 400.0), "samples": (2000.0, 4000.0), "frames": (600.0, 2400.0)}


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
    # (compared before any conversion: an integer too large for a float is out of range, and NaN
    # fails every comparison)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not lo <= v <= hi:
        raise ValueError(f"{key} = {show(v)}: expected a number in {lo:g}..{hi:g}")
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
        raise ValueError(f"seq = {show(seq)}: expected a non-negative integer")
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
    if kind not in ("up", "undo", "clear", "ping"):
        raise ValueError(f"unknown type {show(kind)}")
    return {}


def admit(text: str, buckets: dict) -> str | None:
    """Why a message is refused before it is read (size, rate), or None."""
    if len(text) > MAX_MESSAGE:
        return f"message of {len(text)} bytes refused: at most {MAX_MESSAGE}"
    if not buckets["messages"].take(1):
        return "too many messages: slow down"
    if not buckets["samples"].take(min(text.count("{"), MAX_SAMPLES)):
        return "too many samples: slow down"
    return None


class Pen:
    """Where a connection's pen was (canvas px), to count the frames its next samples ask for."""

    def __init__(self, px_per_mm: float):
        self.ppm, self.last = px_per_mm, None

    def frames(self, samples: list) -> int:
        """Simulated frames of `samples` (as Painting._pose divides them), the first after a jump."""
        n, last = 0, self.last
        for s in samples:
            d = 0.0 if last is None else math.hypot(s[0] - last[0], s[1] - last[1]) / self.ppm
            n += min(SUBSTEPS_MAX, max(1, math.ceil(d / STEP_MM)))
            last = s
        return n

    def budget(self, msg: dict, frames: Bucket) -> str | None:
        """Why a checked message asks for more work than the frame budget allows, or None; the
        pen moves only when the message is taken."""
        if msg["type"] == "up":
            self.last = None
        if msg["type"] != "samples":
            return None
        n = self.frames(msg["samples"])
        if n > frames.burst:
            return f"a message of {n} simulated frames refused: at most {frames.burst:.0f} (move less far per message)"
        if not frames.take(n):
            return "too fast: the pen asks for more frames a second than the brush simulates; slow down"
        self.last = msg["samples"][-1][:2]
        return None
