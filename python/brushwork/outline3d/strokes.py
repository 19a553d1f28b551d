"""Chains as brush motions: styles as data, the press profile of a stroke, and the drawing.

A style (JSON under outline3d/styles/, or a file) names the brush preset, how many mm the
image's longer side spans on the paper (so the brush's size against the drawing), tilt, step,
the press depth per line kind (fraction of the tuft length L below first contact; silhouettes
heavier than creases), the calligraphic entry (a press `entry_press` times the line's over
`entry_mm`) and exit (a taper to `exit_press` times it over `exit_mm`, lifting while moving),
the ink (mm^2 per dip; `dip_mm` of drawn line between dips, 0: before every chain), how hidden
lines are drawn under --hidden faint, the chains' minimum length (of the image diagonal) and
smoothing, and `depth_press`: how much nearer lines are pressed harder than farther ones.
"""
from __future__ import annotations

import json
import os
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import _core
from ..brush import Brush, Pose
from ..paper import Paper
from ..recorded import HOVER, along_path
from ..scene import Scene
from .lines import KINDS, SILHOUETTE

STYLE_DIR = Path(__file__).with_name("styles")
APPROACH_FRAMES = 2     # frames of the descent onto the first point
LIFT_FRAMES = 1         # frames of the lift after the last (one: the tip leaves at once, not flicked forward)
ENTRY_START = 0.0       # of the line's press where the tip first touches
ENTRY_PEAK = 0.4        # of the entry where the entry press is deepest
OFFSET_GAIN = 0.25      # of the footprint centre's miss added to the root's offset each frame
REHEARSAL_MM = 40.0     # length of the stroke that learns the offset before the first chain


@dataclass
class OutlineStyle:
    name: str
    description: str
    preset: str
    paper_mm: float
    tilt_deg: float
    step_mm: float
    press: dict
    entry_mm: float
    entry_press: float
    exit_mm: float
    exit_press: float
    ink_mm2: float
    dip_mm: float
    hidden_alpha: float
    hidden_press: float
    min_length: float
    smooth_passes: int
    scene: dict = field(default_factory=dict)
    depth_press: float = 0.0     # nearest lines pressed 1 + this/2 times, farthest 1 - this/2

    @classmethod
    def names(cls) -> list[str]:
        return sorted(p.stem for p in STYLE_DIR.glob("*.json"))

    @classmethod
    def load(cls, spec: str) -> "OutlineStyle":
        """A bundled style by name, or a JSON file; ValueError names what is wrong."""
        path = Path(spec) if spec.endswith(".json") or os.sep in spec else STYLE_DIR / f"{spec}.json"
        if not path.is_file():
            raise ValueError(f"outline style {spec!r}: not a bundled style ({', '.join(cls.names())}) nor a JSON file")
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
            style = cls(**data)
        except (json.JSONDecodeError, TypeError, UnicodeDecodeError) as err:
            raise ValueError(f"outline style {path}: {err}") from None
        except RecursionError:
            raise ValueError(f"outline style {path}: malformed JSON, nested too deeply") from None
        style.validate()
        return style

    def validate(self) -> None:
        missing = [k for k in KINDS if k not in self.press]
        if missing:
            raise ValueError(f"outline style {self.name}: press lacks {', '.join(missing)}")
        positive = {"paper_mm": self.paper_mm, "step_mm": self.step_mm, "ink_mm2": self.ink_mm2}
        bad = [k for k, v in positive.items() if not (isinstance(v, (int, float)) and v > 0)]
        if bad:
            raise ValueError(f"outline style {self.name}: {', '.join(bad)} must be > 0")
        Scene(**self.scene)


def press_profile(s: np.ndarray, base: float, style: OutlineStyle) -> np.ndarray:
    """(k,) press depth at arc lengths s (mm) of a stroke of press `base`: the tip touches down
    light (ENTRY_START of it) while already moving, presses to `entry_press` times it
    ENTRY_PEAK of the way into `entry_mm` and eases back to `base` by its end; over the last
    `exit_mm` it tapers to `exit_press` times it.  The deeper of the two envelopes never
    wins: a stroke shorter than its entry and exit stays lighter, its press never rising
    faster than the entry's (a quick press of the straight tuft lays a blot)."""
    total = float(s[-1]) if len(s) else 0.0
    entry = np.interp(s, [0.0, ENTRY_PEAK * style.entry_mm, style.entry_mm],
                      [ENTRY_START, style.entry_press, 1.0])
    exit_ = np.interp(total - s, [0.0, style.exit_mm], [style.exit_press, 1.0])
    return base * np.minimum(entry, exit_)


@dataclass
class StrokeTimes:
    brush: float = 0.0     # s in Brush.step
    deposit: float = 0.0   # s in Paper.deposit
    strokes: int = 0
    frames: int = 0


class OutlineDrawer:
    """Draws chains (px, y down, on a W x H image) with one brush on one paper."""

    def __init__(self, style: OutlineStyle, size: tuple[int, int]):
        self.style = style
        w, h = size
        self.ppm = max(w, h) / style.paper_mm
        self.height_px = h
        self.paper = Paper(w / self.ppm, h / self.ppm, self.ppm, scene=Scene(**style.scene))
        self.brush = Brush(style.preset)
        self.times = StrokeTimes()
        self._since_dip = None
        self.offset = np.zeros(2)      # mm, root - footprint centre along and across the heading
        self._rehearse()

    def _dip(self, alpha: float, length_mm: float) -> None:
        st = self.style
        if self._since_dip is None or st.dip_mm <= 0 or self._since_dip >= st.dip_mm:
            self.brush.load_ink(total_mm2=st.ink_mm2, ramp=[(0.0, 0.0, 0.0, 1.0)])
            self._since_dip = 0.0
        self.brush.ink.ramp = [(0.0, 0.0, 0.0, float(alpha))]
        self._since_dip += length_mm

    def draw(self, chain, nearness: np.ndarray | None = None) -> None:
        """One chain as one stroke: descend, move along it with the style's press, lift.
        nearness: (k,) per point of the chain, 1 at the nearest line of the view, 0 at the
        farthest (None: all 0.5), scaling the press by the style's depth_press."""
        st = self.style
        pts = np.column_stack([chain.points[:, 0], self.height_px - chain.points[:, 1]]) / self.ppm
        near = np.full(len(pts), 0.5) if nearness is None else np.asarray(nearness, dtype=float)
        if chain.closed:
            pts = np.vstack([pts, pts[1:3]])              # close the loop, a little overlap
            near = np.concatenate([near, near[1:3]])
        s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
        if s[-1] <= 0:
            return
        base = st.press[KINDS[chain.kind]] * (1.0 if chain.visible else st.hidden_press)
        self._dip(1.0 if chain.visible else st.hidden_alpha, float(s[-1]))
        press = press_profile(s, base, st) * (1.0 + st.depth_press * (near - 0.5))
        poses = along_path(self.brush.model, pts, press, st.tilt_deg, None,
                           step_mm=st.step_mm, approach_frames=APPROACH_FRAMES, lift_frames=LIFT_FRAMES, hover=HOVER)
        self._follow(poses)
        self.paper.end_stroke()
        self.times.strokes += 1
        self.times.frames += len(poses)

    def _rehearse(self) -> None:
        """Learn the root's offset from the footprint's centre before the first stroke: a straight
        stroke of REHEARSAL_MM at the silhouette's press, with a scratch brush and no paper, so
        that the first chain starts where it should and not a trailing tuft's length early."""
        st = self.style
        brush, times = self.brush, self.times
        self.brush, self.times = Brush(st.preset), StrokeTimes()
        path = np.array([[0.0, 0.0], [REHEARSAL_MM, 0.0]])
        press = st.press[KINDS[SILHOUETTE]] * press_profile(np.array([0.0, REHEARSAL_MM]), 1.0, st)
        self._follow(along_path(self.brush.model, path, press, st.tilt_deg, None, step_mm=st.step_mm,
                                approach_frames=APPROACH_FRAMES, lift_frames=LIFT_FRAMES, hover=HOVER), deposit=False)
        self.brush, self.times = brush, times

    def _follow(self, poses: list, deposit: bool = True) -> None:
        """Step and deposit along `poses`, the root shifted so that the footprint's centre (not
        the root, which the tilted, trailing tuft leaves behind and beside the line) follows the
        path.  The shift is kept in the path's frame (along, across the heading), where it hardly
        changes, learns OFFSET_GAIN of each frame's miss there, and carries over from stroke to
        stroke; it never exceeds a tuft length.  The footprint's front stops at the path's end:
        where the centre's target comes nearer the end than the footprint reaches ahead of its
        centre (last frame's reach), the target is held back by the difference, so a line ends
        where its chain ends instead of overshooting it (two lines meeting at a point would
        cross there)."""
        reach = self.brush.model.tuft_length
        ahead = 0.0
        xy = np.array([p.position[:2] for p in poses], dtype=float)
        along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(xy, axis=0), axis=1))])
        for pose, s in zip(poses, along):
            a = np.radians(pose.azimuth_deg)
            frame = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])   # columns: along, across
            target = np.asarray(pose.position[:2], dtype=float) - frame[:, 0] * max(0.0, ahead - (along[-1] - s))
            root = target + frame @ self.offset
            t0 = time.perf_counter()
            self.brush.step(Pose((root[0], root[1], pose.position[2]), pose.tilt_deg, pose.azimuth_deg))
            t1 = time.perf_counter()
            if deposit:
                self.paper.deposit(self.brush)
            loops = self.brush.footprint()
            seen = _core.footprint_span(loops, float(a)) if loops else None
            if seen is not None:
                self.offset += OFFSET_GAIN * (frame.T @ (target - np.asarray(seen[0])))
                self.offset *= min(1.0, reach / max(float(np.hypot(*self.offset)), 1e-12))
                ahead = float(seen[3])
            self.times.brush += t1 - t0
            self.times.deposit += time.perf_counter() - t1
