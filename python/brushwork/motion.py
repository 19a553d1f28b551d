"""The calligraphic driver: a glyph's strokes become brush motions on the paper (DESIGN motion.py).

A glyph is laid out in a physical em box (`Style.em_mm`, 100 mm for the medium brush) and written
stroke by stroke, frame by frame. Like a calligrapher watching the tip, the driver closes two
loops on what the brush actually does:

- position: the root is placed so that the footprint's centre (area centroid of the core's
  footprint polygons) follows the centreline; the root-to-footprint offset is learned frame by
  frame and carried, in the stroke's own frame (along, across), into the next stroke;
- width: the press depth is adjusted so that the footprint's width across the travel follows
  the stroke type's width profile (entry press 顿, travel, pressed corners 折, the thinning exit
  of a left-falling stroke 撇, the flared exit of a right-falling stroke 捺, the dot 点, the
  rising stroke 提, the hook's flick 钩).

Between strokes the brush lifts, travels in the air and comes down again; ink and wetness carry
through the character. Styles are data (`styles/*.json`); variation is seeded.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import _core
from .brush import Brush, Pose
from .paper import Paper
from .scene import Scene

STYLE_DIR = Path(__file__).parent / "styles"

# stroke type -> width-profile family (the kinds are CJK Strokes characters, glyphs.STROKE_TYPES)
FAMILIES = {
    "tapered": "㇒㇓㇢㇛㇜㇇㇋",        # left-falling: thin out and lift
    "flared": "㇏㇝",                  # right-falling: press, flare, lift
    "rising": "㇀㇙㇊",                # rising: start pressed, flick up thin
    "dot": "㇔",
    "hook": "㇚㇁㇂㇃㇆㇈㇉㇌㇖㇟㇠㇡",   # a hook's flick at the end
}


def family(kind: str) -> str:
    """The width-profile family of a stroke type ("plain" for the rest: ㇐ ㇑ ㇕ ㇗ ...)."""
    for name, kinds in FAMILIES.items():
        if kind in kinds:
            return name
    return "plain"


@dataclass
class Style:
    """How a hand writes: the brush, the em size, the nominal stroke width, the tilt, the speed,
    the width profile of each stroke family and the ink. Loaded from `styles/<name>.json`."""
    name: str
    description: str = ""
    preset: str = "medium"
    em_mm: float = 100.0          # physical size of the em box on the paper, mm
    width_em: float = 0.06        # nominal stroke width / em
    tilt_deg: float = 15.0        # handle against the paper's normal, leaning along the travel
    step_mm: float = 1.0          # travel per frame
    press_start: float = 0.2      # first guess of the press depth, fraction of the tuft length
    position_gain: float = 0.8    # fraction of the footprint's position error corrected per frame
    across_gain: float = 0.8      # the same, across the stroke
    width_gain: float = 0.06      # press change (L) per unit of relative width error
    press_feedforward: float = 0.0  # press change (L) per unit change of the profile's width / nominal
    entry_frames: int = 5         # frames pressing down at a stroke's start
    exit_frames: int = 4          # frames lifting at its end
    air_frames: int = 0           # frames hovering over a stroke's start, aiming the tip, before the entry
    hover: float = 0.12           # height above first contact between strokes, fraction of L
    ink_mm2: float = 6000.0       # ink the brush is dipped with, mm^2 of paper at full density
    scene: dict = field(default_factory=lambda: {"depletion": True})
    jitter: float = 0.03          # seeded relative variation of stroke width and pressure
    corner_press: float = 1.2     # width factor at a corner of the centreline (折)
    density_gain: float = 0.0     # width factor 1 - g (n - density_strokes) for a character of n strokes:
    density_strokes: float = 9.3  # a Kai hand thins the strokes of a busy character, fattens a sparse one
    direction_gain: float = 0.0   # plain strokes and hooks: width factor 1 + g (2 |sin heading| - 1),
                                  # Kai's verticals 竖 broader than its horizontals 横 (the brush held slanted)
    end_reach_em: float | None = None  # how far the footprint may reach past a median's end, em
                                  # (None: half the stroke's width)
    start_reach_em: float | None = None  # the same before its start (None: as end_reach_em)
    taper_from: float | None = None  # 出锋 exits (tapered, rising families): from this fraction of the
                                  # median on, where the profile thins, the width loop only eases the
                                  # press, and the stroke lifts where it stands (None: off)
    taper_collapse: float = 0.5   # ... and the travel ends once the footprint is narrower than this
                                  # fraction of the profile's width there (the belly has left the paper)
    offset_em: tuple = (0.0, 0.0)  # (x, y) em added to every centreline point: a Kai stroke's body
                                  # hangs below-right of the line its tip follows (笔锋 on the upper left)
    profiles: dict = field(default_factory=dict)  # family -> [[s in 0..1, width factor], ...]

    @classmethod
    def load(cls, name_or_path: str) -> "Style":
        """A style by name (kai, xing) or from a JSON file."""
        path = Path(name_or_path)
        if not path.suffix:
            path = STYLE_DIR / f"{name_or_path}.json"
        if not path.is_file():
            known = ", ".join(sorted(p.stem for p in STYLE_DIR.glob("*.json")))
            raise ValueError(f"unknown style {name_or_path!r} (known: {known})")
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
            style = cls(**data)
        except (json.JSONDecodeError, TypeError) as err:
            raise ValueError(f"{path}: not a style file: {err}") from err
        missing = {"plain", "tapered", "flared", "rising", "dot", "hook"} - set(style.profiles)
        if missing:
            raise ValueError(f"{path}: profiles lack {', '.join(sorted(missing))}")
        if style.taper_from is not None and not 0.0 <= style.taper_from <= 1.0:
            raise ValueError(f"{path}: taper_from {style.taper_from}: expected a fraction of the median, 0..1, or null")
        if not 0.0 <= style.taper_collapse <= 1.0:
            raise ValueError(f"{path}: taper_collapse {style.taper_collapse}: expected a fraction of the width, 0..1")
        return style

    def density(self, strokes: int) -> float:
        """Width factor of a character of `strokes` strokes (density_gain), within 0.7..1.3."""
        return float(np.clip(1.0 - self.density_gain * (strokes - self.density_strokes), 0.7, 1.3))

    @staticmethod
    def names() -> list[str]:
        return sorted(p.stem for p in STYLE_DIR.glob("*.json"))


def _clip(x: float, lo: float, hi: float) -> float:
    """np.clip for one number (lo <= hi), without numpy's per-call cost: the driver clips a few
    numbers every frame (~7 ms of a 1024 px character through np.clip)."""
    return lo if x < lo else hi if x > hi else x


def _resample(points: np.ndarray, step: float) -> tuple[np.ndarray, np.ndarray]:
    """(n, 2) points every `step` mm along the polyline and their arc lengths (n,) mm."""
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    n = max(2, int(math.ceil(s[-1] / step)) + 1)
    ss = np.linspace(0.0, s[-1], n)
    return np.stack([np.interp(ss, s, points[:, 0]), np.interp(ss, s, points[:, 1])], axis=1), ss


def _corners(path: np.ndarray, min_turn_deg: float = 55.0) -> np.ndarray:
    """(n,) in [0, 1]: how close each point is to a sharp turn of the centreline (1 at it)."""
    n = len(path)
    out = np.zeros(n)
    if n < 5:
        return out
    d = np.diff(path, axis=0)
    ang = np.arctan2(d[:, 1], d[:, 0])
    for i in range(2, n - 2):
        turn = abs(math.degrees(math.remainder(ang[i + 1] - ang[i - 2], 2 * math.pi)))
        if turn >= min_turn_deg:
            out[max(0, i - 2):i + 3] = np.maximum(out[max(0, i - 2):i + 3], [0.4, 0.8, 1.0, 0.8, 0.4][:min(5, n - max(0, i - 2))])
    return out


def _centroid_and_width(loops, heading: float) -> tuple[np.ndarray, float, float, float] | None:
    """Area centroid (mm) of the footprint polygons, their width across `heading` (mm), and how
    far they reach behind and ahead of the centroid along `heading` (mm); None without a
    footprint. (In the core: read every frame, it took 86 us in numpy, 1-2 us there. A sliver
    whose outer loop and hole nearly cancel has its area centroid anywhere: one 200 mm from a
    100 mm em box threw the root there and swept a band across 蒙; such a centroid, outside the
    points' bounds, is replaced by their mean.)"""
    if not loops:
        return None
    return _core.footprint_span(loops, float(heading))


def stroke_targets(style: Style, points_mm: np.ndarray, kind: str,
                   w_nom: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """What the driver aims a stroke at: its centreline `points_mm` ((k, 2) mm) resampled every
    `step_mm` -> path (n, 2) mm, arc length s (n,) mm, heading (n,) rad, and the target footprint
    width (n,) mm: `w_nom` (mm) times the family's profile over s / length, pressed at corners
    (折) and, for plain strokes and hooks, broader when vertical."""
    path, s = _resample(points_mm, style.step_mm)
    d = np.gradient(path, axis=0)
    heading = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
    prof = np.asarray(style.profiles[family(kind)], dtype=float)
    width = w_nom * np.interp(s / max(s[-1], 1e-6), prof[:, 0], prof[:, 1])
    width *= 1.0 + (style.corner_press - 1.0) * _corners(path)
    if family(kind) in ("plain", "hook"):
        width *= 1.0 + style.direction_gain * (2.0 * np.abs(np.sin(heading)) - 1.0)
    return path, s, heading, width


class Writer:
    """Writes glyphs with one brush on one paper; `write(glyph, origin_mm)` draws a character
    whose em box's bottom-left corner sits at `origin_mm` on the paper."""

    def __init__(self, paper: Paper, style: Style, seed: int = 0):
        self.paper, self.style = paper, style
        self.brush = Brush(style.preset)
        self.rng = np.random.default_rng(seed)
        self.L = self.brush.model.tuft_length
        self.press = style.press_start
        self.offset_local = np.zeros(2)   # root - footprint centre, in the stroke frame (along, across), mm
        self.behind = self.ahead = 0.0    # mm the footprint reaches behind / ahead of its centre
        self.frames = 0
        self.touching = False             # the last deposit touched the paper
        self.touched_in_stroke = False    # a deposit of this stroke touched it
        self.breaks = 0                   # strokes broken: down again after a lift within one stroke
        self.holds = 0                    # frames a pose was held because the solver left the brush floating
        self.contact = []                 # the brush's contact polygon after the last frame (Brush.footprint)
        self.density = 1.0                # width factor of the character being written (density_gain)

    def _z(self, press: float, tilt: float) -> float:
        return self.L * math.cos(math.radians(tilt)) - press * self.L

    def _step(self, target: np.ndarray, heading: float, press: float, tilt: float) -> None:
        c, s = math.cos(heading), math.sin(heading)
        off = np.array([c * self.offset_local[0] - s * self.offset_local[1],
                        s * self.offset_local[0] + c * self.offset_local[1]])
        root = target + off
        pose = Pose((root[0], root[1], self._z(press, tilt)), tilt, math.degrees(heading))
        stats = self.brush.step(pose)
        self.contact = self.brush.footprint()   # the contact polygon, once a frame (~20 µs)
        # a pressed brush cannot float: the root is below where the straight tuft's tip touches.
        # When the solver stopped at q_max on an iterate that does (a bent tuft held up on its
        # way to the new pose), hold the pose for up to three more frames rather than lay a gap in
        # the stroke (one more frame left 46 broken strokes in the 301 dev characters, three 29)
        for _ in range(3):
            if not (self.touching and press > 0.0 and not stats.converged and stats.status == "iteration cap"
                    and not self.contact):
                break
            stats = self.brush.step(pose)
            self.contact = self.brush.footprint()
            self.frames += 1
            self.holds += 1
        dep = self.paper.deposit(self.brush)
        # a break: the brush came down again after leaving the paper within one stroke
        self.breaks += int(dep.new_stroke and self.touched_in_stroke)
        self.touched_in_stroke = self.touched_in_stroke or dep.contact
        self.touching = dep.contact
        self.frames += 1

    def _observe(self, target: np.ndarray, heading: float, width_target: float | None) -> None:
        seen = _centroid_and_width(self.contact, heading)
        st = self.style
        if seen is None:
            if width_target is not None:
                self.press = min(self.press + 0.02, 0.45)   # not touching yet: press on
            return
        centre, width, self.behind, self.ahead = seen
        c, s = math.cos(heading), math.sin(heading)
        err = target - centre                               # mm, on the paper
        # along the stroke the offset follows quickly; across it, gently (the footprint's centre
        # wanders a little from frame to frame, and chasing it widens the stroke)
        self.offset_local += np.array([st.position_gain * (c * err[0] + s * err[1]),
                                       st.across_gain * (-s * err[0] + c * err[1])])
        # the root is never farther than a tuft length from where the tuft touches
        reach = float(np.linalg.norm(self.offset_local))
        if reach > self.L:
            self.offset_local *= self.L / reach
        if width_target is not None:
            rel = (width_target - width) / max(width_target, 1e-3)
            self.press = float(_clip(self.press + st.width_gain * rel, 0.0, 0.45))

    def write_stroke(self, points_mm: np.ndarray, kind: str) -> None:
        st = self.style
        # (the last stroke's deposits say nothing of this one: the brush travelled in the air)
        self.touched_in_stroke = self.touching = False
        w_nom = st.width_em * st.em_mm * self.density * (1.0 + st.jitter * self.rng.standard_normal())
        path, s, heading, width = stroke_targets(st, points_mm, kind, w_nom)
        length = max(s[-1], 1e-6)
        tilt = st.tilt_deg

        # the footprint must not reach past the stroke's ends by more than `reach` (mm; half a
        # width unless the style says): its centre's arc length is held within
        # [behind - reach, length + reach - ahead]
        def reach(r_em: float | None, j: int) -> float:
            return 0.5 * width[j] if r_em is None else r_em * st.em_mm

        start_reach = st.end_reach_em if st.start_reach_em is None else st.start_reach_em

        def target(j: int) -> np.ndarray:
            lo, hi = self.behind - reach(start_reach, j), length + reach(st.end_reach_em, j) - self.ahead
            sj = 0.5 * (lo + hi) if lo > hi else float(_clip(s[j], lo, hi))
            sj = float(_clip(sj, 0.0, length))
            return np.array([np.interp(sj, s, path[:, 0]), np.interp(sj, s, path[:, 1])])

        # come down at the start: while in the air the tip is aimed at the stroke's start (the
        # tuft lies down from its tip, so the tip marks the stroke's rear end), then pressed
        self.behind = self.ahead = 0.5 * width[0]
        c, sn = math.cos(heading[0]), math.sin(heading[0])
        for j in range(-st.air_frames, st.entry_frames):
            # first `air_frames` frames hovering, the tip swung over the start before it touches
            # (a descent still being aimed lays ink on its way in), then pressing down
            t = max(0, j + 1) / st.entry_frames
            p0 = target(0)
            self._step(p0, heading[0], -st.hover + (self.press + st.hover) * t, tilt)
            if not self.contact:
                tip = np.asarray(self.brush.skeleton()[-1][:2])
                err = path[0] - tip
                self.offset_local += np.array([c * err[0] + sn * err[1], -sn * err[0] + c * err[1]])
            else:
                self._observe(p0, heading[0], width[0] if t >= 1.0 else None)
        # 出锋: near the end of a tapering stroke the press only eases. The footprint does not
        # thin with the press: the spread belly keeps its width, then leaves the paper within a
        # frame or two and only the tip touches. A loop free to press again brought the belly
        # down on a folded tip, a bead at the end of 68% of the 撇 (docs/experiments, session
        # 12); eased only, the tip alone drew a hairline past the end. So the travel ends where
        # the belly has left, and the brush lifts there
        tapering = st.taper_from is not None and family(kind) in ("tapered", "rising")
        # travel
        for j in range(len(path)):
            if j > 0:
                # feedforward: the press follows the profile's own change at once (L per unit of
                # relative width change); the footprint loop only trims. A spread tuft keeps its
                # width while the press eases (the hairs stick splayed), so a tapering exit 出锋
                # must lift ahead of what the footprint shows
                self.press = float(_clip(self.press + st.press_feedforward * (width[j] - width[j - 1]) / w_nom, 0.0, 0.45))
            pj = target(j)
            self._step(pj, heading[j], self.press, tilt)
            eased = self.press
            self._observe(pj, heading[j], width[j])
            if tapering and s[j] > st.taper_from * length and j + 1 < len(path) and width[j + 1] < width[j]:
                self.press = min(self.press, eased)
                seen = _centroid_and_width(self.contact, heading[j])
                if seen is None or seen[1] < st.taper_collapse * width[j]:
                    break
        # lift while drawing the root back over the footprint (回锋, returning the tip), so the
        # unbending tuft does not sweep ink past the stroke's end; a tapered exit has no tip
        # to return (only the tip touches as the travel ends): it lifts where it stands
        end, h = target(j), heading[j]
        back = np.array([math.cos(h), math.sin(h)]) * (0.0 if tapering else self.offset_local[0])
        # Once a deposit leaves no ink (the belly may already have left on the travel's last
        # frame) the rest of the lift is one frame: eased out over the remaining frames, the tuft
        # springing back as the root rose slowly swung its tip down onto the paper again, a dot
        # past the stroke's end (session 14: most of the strokes that broke did so on an exit
        # frame; broken strokes in the 301 development characters 4 -> 1, in xing's 600 unseen 80 -> 51)
        for j in range(st.exit_frames):
            if not self.touching:
                self._step(end - back, h, -st.hover, tilt)
                break
            t = (j + 1) / st.exit_frames
            self._step(end - back * t, h, self.press * (1 - t) - st.hover * t, tilt)
        self.paper.end_stroke()

    def travel(self, to_mm: np.ndarray, heading: float) -> None:
        """Lift and carry the brush in the air to above `to_mm`, turning toward `heading`."""
        st = self.style
        root = np.asarray(self.brush.skeleton()[0][:2])
        dist = float(np.linalg.norm(to_mm - root))
        n = int(np.clip(math.ceil(dist / (4.0 * st.step_mm)), 2, 10))
        for j in range(n):
            t = (j + 1) / n
            self.brush.step(Pose((root[0] + (to_mm[0] - root[0]) * t, root[1] + (to_mm[1] - root[1]) * t,
                                  self._z(-st.hover, st.tilt_deg)), st.tilt_deg, math.degrees(heading)))
            self.paper.deposit(self.brush)
            self.frames += 1

    def write(self, glyph, origin_mm=(0.0, 0.0)) -> None:
        st = self.style
        self.brush.load_ink(total_mm2=st.ink_mm2, excess=0.0)
        o = np.asarray(origin_mm, dtype=float)
        self.density = st.density(len(glyph.strokes))
        for stroke in glyph.strokes:
            pts = o + (np.asarray(stroke.points, dtype=float) + np.asarray(st.offset_em, dtype=float)) * st.em_mm
            d0 = pts[min(1, len(pts) - 1)] - pts[0]
            h0 = math.atan2(d0[1], d0[0])
            self.travel(pts[0], h0)
            self.write_stroke(pts, stroke.kind)


MAX_SIDE = 32768     # px: the paper's largest side


def check_size(size: int) -> int:
    """px per character: 16..8192."""
    size = int(size)
    if not 16 <= size <= 8192:
        raise ValueError(f"size {size} px: expected 16..8192 px")
    return size


def check_samples(samples: int | None) -> int | None:
    """Multisampling of the stroke layer: None (the style's) or 1, 2, 4, 8."""
    if samples is not None and samples not in (1, 2, 4, 8):
        raise ValueError(f"samples {samples}: expected 1, 2, 4 or 8")
    return samples


def writing_paper(style: Style, size: int, chars: int = 1, samples: int | None = None) -> Paper:
    """A paper for `chars` characters in a row, each em box a size x size px square, with the
    style's scene; `samples` overrides its multisampling (1 is ~2.5x faster on a software
    renderer, its edges stepped at the pixel)."""
    size, samples = check_size(size), check_samples(samples)
    if chars < 1:
        raise ValueError("no characters to render")
    if chars * size > MAX_SIDE:
        raise ValueError(f"{chars} characters x {size} px = {chars * size} px wide: more than {MAX_SIDE}; "
                         "use a smaller size or `brushwork batch`")
    scene = dict(style.scene, **({"samples": samples} if samples else {}))
    return Paper(chars * style.em_mm, style.em_mm, size / style.em_mm, scene=Scene(**scene))


def render_glyph(glyph, size: int = 1024, style: Style | str = "kai", seed: int = 0) -> Paper:
    """A paper of `size` x `size` px whose em box is the whole image (so a Make Me a Hanzi glyph
    lands where its SVG recipe draws the outlines), with the glyph written on it."""
    st = style if isinstance(style, Style) else Style.load(style)
    paper = writing_paper(st, size)
    Writer(paper, st, seed).write(glyph)
    return paper
