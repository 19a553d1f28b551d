"""A painting: one brush, one paper, the log of the motion that made it, and undo; no web.

Everything that changes the paper is an *event*, a JSON list: ``["pose", x, y, z, tilt, azimuth,
twist]`` (the root in mm, paper coordinates with y up, the angles in degrees), ``["up"]`` (the pen
leaves the paper), ``["undo"]``, ``["clear"]``, ``["dip", ink, wetness]`` and ``["settings",
{"preset": ..., "scene": {...}}]``. A `Painting` applies events and logs them; the same events
applied to a `Painting` of any resolution paint the same picture (`replay`).
"""
from __future__ import annotations

import json
import math

import numpy as np

from .. import BrushModel
from ..brush import Brush, Pose, lerp_angle
from ..paper import Paper
from ..recorded import HOVER, PRESS_MAX, root_height
from ..scene import Scene

TILT_MAX = 60.0      # deg: steepest handle the pen may ask for
STEP_MM = 1.0        # mm: a longer move between samples is simulated in frames of at most this
SUBSTEPS_MAX = 32    # frames one sample is divided into at most
LIFT_FRAMES = 6      # frames the brush rises at most when the pen leaves the paper
UNDO_DEPTH = 20      # pen strokes undo remembers
UNDO_BYTES = 64 * 2 ** 20  # bytes of paper undo keeps at the painted resolution (at least one
                           # whole paper, so that a clear can be undone)
SCENE_FLAGS = ("split_map", "dry_map", "grain", "depletion")
LOG_FORMAT = "brushwork-paint"
MAX_PX = 8192        # px: largest side of a paper
MAX_TUFTS = 9        # tufts of a brush: the main one and up to 8 children (BrushModel.tufts)

Rect = tuple  # (x0, y0, x1, y1) px, y up, exclusive


def show(value, limit: int = 24) -> str:
    """`value` for an error message: its repr, cut to `limit` characters (a huge input is never
    echoed in full; an integer too long to print is named by its size)."""
    try:
        text = repr(value)
    except ValueError:                    # (an int beyond Python's digit limit for str)
        return f"an integer of {value.bit_length()} bits"
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _number(value, name: str, lo: float, hi: float) -> float:
    # (compared before conversion: an integer too large for a float is out of range, NaN never in)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not lo <= value <= hi:
        raise ValueError(f"{name} = {show(value)}: expected a number in {lo:g}..{hi:g}")
    return float(value)


def check_settings(s) -> dict:
    """The settings of a painting, checked: {width_mm, height_mm, px_per_mm, preset, tufts (1..9:
    the main tuft and the children it may split into), scene (flag -> bool), ink (0..1 of a full
    dip), wetness (0..1)}."""
    if not isinstance(s, dict):
        raise ValueError("settings: expected an object")
    known = {"width_mm", "height_mm", "px_per_mm", "preset", "tufts", "scene", "ink", "wetness"}
    if set(s) - known:
        raise ValueError(f"settings: unknown field {show(sorted(set(s) - known)[0])}")
    out = {name: _number(s.get(name), name, 1.0, 10000.0) for name in ("width_mm", "height_mm")}
    out["px_per_mm"] = _number(s.get("px_per_mm"), "px_per_mm", 0.1, 100.0)
    if max(out["width_mm"], out["height_mm"]) * out["px_per_mm"] > MAX_PX + 0.5:
        raise ValueError(f"settings: the paper would be larger than {MAX_PX} px")
    out.update(check_change({"preset": s.get("preset", "medium"), "tufts": s.get("tufts", 1),
                             "scene": s.get("scene", {})}))
    out["ink"], out["wetness"] = (_number(s.get(k, 1.0), k, 0.0, 1.0) for k in ("ink", "wetness"))
    return out


def check_change(c) -> dict:
    """A change of brush preset, tuft count and/or scene flags, checked."""
    if not isinstance(c, dict) or set(c) - {"preset", "tufts", "scene"}:
        raise ValueError("settings change: expected an object with preset, tufts and/or scene")
    out = {}
    if "preset" in c:
        if c["preset"] not in BrushModel.presets():
            raise ValueError(f"preset {show(c['preset'])}: choose from {', '.join(BrushModel.presets())}")
        out["preset"] = c["preset"]
    if "tufts" in c:
        if isinstance(c["tufts"], bool) or not isinstance(c["tufts"], int) or not 1 <= c["tufts"] <= MAX_TUFTS:
            raise ValueError(f"tufts = {show(c['tufts'])}: expected a whole number in 1..{MAX_TUFTS}")
        out["tufts"] = c["tufts"]
    if "scene" in c:
        scene = c["scene"]
        if not isinstance(scene, dict) or set(scene) - set(SCENE_FLAGS) or \
                not all(isinstance(v, bool) for v in scene.values()):
            raise ValueError(f"scene: expected an object of booleans named from {', '.join(SCENE_FLAGS)}")
        out["scene"] = dict(scene)
    return out


def check_event(ev) -> list:
    """One event, checked (ValueError otherwise); numbers as floats."""
    if not isinstance(ev, list) or not ev or not isinstance(ev[0], str):
        raise ValueError(f"event {show(ev, 40)}: expected a list starting with its name")
    name, args = ev[0], ev[1:]
    if name == "pose" and len(args) == 6:
        lim = ("x", -1e5, 1e5), ("y", -1e5, 1e5), ("z", -1e4, 1e4), ("tilt", 0.0, TILT_MAX), \
              ("azimuth", -1e4, 1e4), ("twist", -1e4, 1e4)
        return ["pose"] + [_number(v, n, lo, hi) for v, (n, lo, hi) in zip(args, lim)]
    if name in ("up", "undo", "clear") and not args:
        return [name]
    if name == "dip" and len(args) == 2:
        return ["dip", _number(args[0], "ink", 0.0, 1.0), _number(args[1], "wetness", 0.0, 1.0)]
    if name == "settings" and len(args) == 1:
        return ["settings", check_change(args[0])]
    raise ValueError(f"event {show(ev, 40)}: unknown name or wrong number of arguments")


def unite(a: Rect | None, b: Rect | None) -> Rect | None:
    """The smallest rectangle holding both (None: empty)."""
    if a is None or a[0] >= a[2] or a[1] >= a[3]:
        return b if b is not None and b[0] < b[2] and b[1] < b[3] else None
    if b is None or b[0] >= b[2] or b[1] >= b[3]:
        return a
    return (min(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), max(a[3], b[3]))


class Painting:
    """A brush painting on a paper, driven by events (see the module); `log()` is everything
    applied so far. `px_per_mm` overrides the settings' resolution (a replay at another size)."""

    def __init__(self, settings: dict, px_per_mm: float | None = None):
        self.settings = check_settings(settings)
        self.initial = {**self.settings, "scene": dict(self.settings["scene"])}
        s = self.settings
        self.ppm = float(px_per_mm or s["px_per_mm"])
        self.paper = Paper(s["width_mm"], s["height_mm"], self.ppm, self._scene())
        self.brush = self._new_brush()
        self.events: list = []
        self.down = False                  # the pen is on the paper (a pen stroke is open)
        self.last = None                   # the last simulated pose: (x, y, z, tilt, azimuth, twist)
        self.stroke_rect: Rect | None = None
        self.undo_stack: list = []         # [(rect, (h, w, 4) float32 premultiplied RGBA before a pen stroke)]
        self._before = np.zeros((self.paper.height_px, self.paper.width_px, 4), np.float32)
        # the bytes undo keeps: UNDO_BYTES at the painted resolution, scaled with the area of a
        # pixel so that a replay at another size keeps the same strokes
        self.undo_budget = max(UNDO_BYTES * (self.ppm / s["px_per_mm"]) ** 2, self._before.nbytes)
        self._encoded: list = []           # the events as JSON text, each encoded once (log_json)
        self.frames, self.sim_s = 0, 0.0   # simulated frames and their time (step + deposit), s
        self.split_frames = 0              # frames the brush was split into several tufts

    # --- set-up
    def _scene(self) -> Scene:
        return Scene(**self.settings["scene"])

    def _new_brush(self) -> Brush:
        model = BrushModel.preset(self.settings["preset"])
        model.tufts = self.settings.get("tufts", 1) - 1  # the children the main tuft may split into
        brush = Brush(model)
        self.model = brush.model           # (a copy: its tuft length sets the root heights)
        self._dip(brush, self.settings["ink"], self.settings["wetness"])
        return brush

    @staticmethod
    def _dip(brush: Brush, ink: float, wetness: float) -> None:
        """Dip: `ink` of a full load (Brush.load_ink), every node's wetness `wetness`."""
        brush.load_ink(ink * brush.default_ink_mm2())
        brush.wetness = np.full(brush.model.n_segments + 1, wetness)

    @property
    def size_px(self) -> tuple[int, int]:
        return self.paper.width_px, self.paper.height_px

    # --- pen samples to poses
    def sample_pose(self, x_px: float, y_px: float, pressure: float, tilt: float, azimuth: float,
                    twist: float) -> list:
        """The pose event of a pen sample: (x_px, y_px) on the page's canvas (y down) where the tip
        touches, pressure 0..1 (0: the tip just touches; the root PRESS_MAX L lower at 1), the handle `tilt` deg
        from the normal leaning toward `azimuth` (deg, paper's frame, counter-clockwise from +x)."""
        t = min(max(tilt, 0.0), TILT_MAX)
        # the root sits up the handle from the pen's point, so the straight tuft's tip touches
        # the paper under the pen: L sin(tilt) toward the azimuth
        reach, a = self.model.tuft_length * math.sin(math.radians(t)), math.radians(azimuth)
        w, h = self.settings["width_mm"], self.settings["height_mm"]
        # (a pen far off the paper is held a paper's size beyond its edge)
        x = min(max(x_px / self.ppm, -w), 2.0 * w) + reach * math.cos(a)
        y = min(max(h - y_px / self.ppm, -h), 2.0 * h) + reach * math.sin(a)
        z = root_height(self.model, t, PRESS_MAX * min(max(pressure, 0.0), 1.0))
        return ["pose", x, y, z, t, azimuth % 360.0, twist % 360.0]

    # --- events
    def apply(self, event: list) -> Rect | None:
        """Apply one checked event (`check_event`), log it; the px rectangle it changed (y up) or None."""
        name = event[0]
        self.events.append(event)
        if name == "pose":
            return self._pose(tuple(event[1:]))
        if name == "up":
            return self._up()
        if name == "undo":
            return self._undo()
        if name == "clear":
            return self._clear()
        if name == "dip":
            self._dip(self.brush, event[1], event[2])
            return None
        return self._change(event[1])

    def _frame(self, pose: tuple) -> Rect | None:
        """One simulated frame at `pose` and its deposit."""
        import time

        t0 = time.perf_counter()
        split = self.brush.step(Pose(pose[:3], *pose[3:])).tufts_active > 0
        stats = self.paper.deposit(self.brush)
        self.sim_s += time.perf_counter() - t0
        self.frames += 1
        self.split_frames += split
        self.last = pose
        return tuple(stats.rect) if stats.contact else None

    def _pose(self, pose: tuple) -> Rect | None:
        rect = None
        if not self.down:
            # a new pen stroke: the brush comes down from the air above the sample
            self.prepare_undo()
            self.down, self.stroke_rect = True, None
            z_air = root_height(self.model, pose[3], -HOVER)
            rect = self._frame(pose[:2] + (max(z_air, pose[2]),) + pose[3:])
        a = self.last
        n = min(SUBSTEPS_MAX, max(1, math.ceil(math.hypot(pose[0] - a[0], pose[1] - a[1]) / STEP_MM)))
        for k in range(1, n + 1):
            t = k / n
            sub = tuple(a[i] + (pose[i] - a[i]) * t for i in range(4)) + \
                (lerp_angle(a[4], pose[4], t), lerp_angle(a[5], pose[5], t))
            rect = unite(rect, self._frame(pose if k == n else sub))
        self.stroke_rect = unite(self.stroke_rect, rect)
        return rect

    def _up(self) -> Rect | None:
        """The pen leaves the paper: the brush rises until it is off the paper (LIFT_FRAMES at
        most), the stroke ends, and undo keeps what the pen stroke covered."""
        if not self.down:
            return None
        x, y, z, tilt, az, tw = self.last
        z_air = root_height(self.model, tilt, -HOVER)
        for k in range(1, LIFT_FRAMES + 1):
            r = self._frame((x, y, z + (z_air - z) * k / LIFT_FRAMES, tilt, az, tw))
            if r is None:
                break
            self.stroke_rect = unite(self.stroke_rect, r)
        self.paper.end_stroke()
        rect = self.stroke_rect
        if rect is not None:
            self._keep_undo(rect, self._crop(self._before, rect))
            self._before = None
        self.down = False
        return rect

    def _keep_undo(self, rect: Rect, kept: np.ndarray) -> None:
        """Remember `kept` for undo: the newest UNDO_DEPTH entries at most, and the oldest dropped
        while they hold more than the budget of bytes (the newest always stays)."""
        self.undo_stack = (self.undo_stack + [(rect, kept)])[-UNDO_DEPTH:]
        while len(self.undo_stack) > 1 and self.undo_bytes() > self.undo_budget:
            self.undo_stack.pop(0)

    def undo_bytes(self) -> int:
        """Bytes of paper undo keeps."""
        return sum(kept.nbytes for _, kept in self.undo_stack)

    def prepare_undo(self) -> None:
        """Keep the paper as it is before the next pen stroke (idle time is the time to do it)."""
        if self._before is None and not self.down:
            self._before = self.paper.rgba()

    def _crop(self, rgba: np.ndarray, rect: Rect) -> np.ndarray:
        h = self.paper.height_px
        return rgba[h - rect[3]:h - rect[1], rect[0]:rect[2]].copy()

    def _undo(self) -> Rect | None:
        """Put back what the last pen stroke (or clear) covered."""
        self._up()
        if not self.undo_stack:
            return None
        rect, kept = self.undo_stack.pop()
        rgba = self.paper.rgba()
        h = self.paper.height_px
        rgba[h - rect[3]:h - rect[1], rect[0]:rect[2]] = kept
        self.paper.set_rgba(rgba)
        self._before = rgba
        return rect

    def full_rect(self) -> Rect:
        return (0, 0, self.paper.width_px, self.paper.height_px)

    def _clear(self) -> Rect:
        self._up()
        self.prepare_undo()
        self._keep_undo(self.full_rect(), self._before)
        self.paper.clear()
        self._before = np.zeros_like(self._before)
        return self.full_rect()

    def _change(self, change: dict) -> Rect | None:
        """A new brush (preset) or a new paper with the picture carried over (scene flags)."""
        self._up()
        self.settings.update(change)
        if "preset" in change or "tufts" in change:
            self.brush = self._new_brush()
        if "scene" in change:
            rgba = self.paper.rgba()
            self.paper = Paper(self.settings["width_mm"], self.settings["height_mm"], self.ppm, self._scene())
            self.paper.set_rgba(rgba)
            self._before = rgba
            return self.full_rect()
        return None

    # --- output
    def image(self) -> np.ndarray:
        """(H, W, 3) uint8 RGB, row 0 at the top: the paper now, a stroke in progress included."""
        return self.paper.image()

    def contact_px(self) -> list:
        """The brush's contact polygons on the page's canvas, px (y down), rounded to 0.1 px."""
        h = self.settings["height_mm"]
        return [[round(v, 1) for x, y in poly for v in (x * self.ppm, (h - y) * self.ppm)]
                for poly in self.brush.footprint()]

    def log(self) -> dict:
        """Settings at the start and every event since: replays to this picture."""
        return {"format": LOG_FORMAT, "version": 1, "settings": self.initial, "events": self.events}

    def log_json(self) -> str:
        """log() as compact JSON text; each event is encoded once, so a long log is not encoded
        again on every save."""
        enc = self._encoded
        enc.extend(json.dumps(ev, separators=(",", ":")) for ev in self.events[len(enc):])
        head = json.dumps({"format": LOG_FORMAT, "version": 1, "settings": self.initial}, separators=(",", ":"))
        return head[:-1] + ',"events":[' + ",".join(enc) + "]}"
