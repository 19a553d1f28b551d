"""The calligraphic driver: a glyph's strokes become brush motions on the paper (DESIGN writing/driver.py).

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

import copy
import math

import numpy as np

from ..brush import Brush, Pose, solver_tally, tally_step
from ..glyphs.score import tally_bead
from ..paper import Paper
from ..recorded import PRESS_MAX, root_height
from .plan import FLICK_FROM, lowpass
from .style import Style, family
from .targets import _centroid_and_width, centreline, footprint_area, joins, stroke_targets

# the driver's constants (L: the tuft length)
PRESS_ON = 0.02           # L: press added per frame while a pressing brush has not touched yet
HOLD_FRAMES = 3           # frames a pressing brush is pressed deeper at most while it floats off the paper
TRAVEL_STEP = 4.0         # step_mm: the brush moves this many frame steps per frame in the air
TRAVEL_FRAMES = (2, 10)   # frames of one travel between strokes, fewest and most
# the stroke families whose exit tapers (出锋): the left-falling 撇 and rising 提 thin out, the
# right-falling 捺 leaves its pressed foot and the hook 钩 its flick as the press eases
TAPERING = ("tapered", "rising", "flared", "hook")
# a hook's flick: the median past its last turn of more than FLICK_TURN (rad) over the stretch
# from there to the end, where that turn lies past FLICK_FROM of the median
FLICK_TURN = 1.0
# ... and the flick goes on FLICK_PAST_EM (em) straight past the median's end while the press eases
# out: a Make Me a Hanzi median stops inside the hook, whose tip the trailing tuft reaches only
# when the root runs on (stopped at the median's end, the hook ended in a blunt pad)
FLICK_PAST_EM = 0.06


def _clip(x: float, lo: float, hi: float) -> float:
    """np.clip for one number (lo <= hi), without numpy's per-call cost: the driver clips a few
    numbers every frame (~7 ms of a 1024 px character through np.clip)."""
    return lo if x < lo else hi if x > hi else x


class Writer:
    """Writes glyphs with one brush on one paper; `write(glyph, origin_mm)` draws a character
    whose em box's bottom-left corner sits at `origin_mm` on the paper."""

    def __init__(self, paper: Paper, style: Style, seed: int = 0):
        self.paper, self.style = paper, style
        self.brush = Brush(style.model())
        self.rng = np.random.default_rng(seed)
        self.shape = self.brush.model     # a copy of the brush's model: its tuft length sets the root heights
        self.L = self.shape.tuft_length
        self.press = style.press_start
        self.offset_local = np.zeros(2)   # root - footprint centre, in the stroke frame (along, across), mm
        self.behind = self.ahead = 0.0    # mm the footprint reaches behind / ahead of its centre
        self.frames = 0
        self.touching = False             # the last deposit touched the paper
        self.touched_in_stroke = False    # a deposit of this stroke touched it
        self.breaks = 0                   # strokes broken: down again after a lift within one stroke
        self.holds = 0                    # frames re-stepped deeper (a pressing brush floated off, a footprint collapsed)
        self.contact = []                 # the brush's contact polygon after the last frame (Brush.footprint)
        self.density = 1.0                # width factor of the character being written (density_gain)
        self.widths: list[float] = []     # mm: the footprint's width across the travel, a frame, this stroke
        self.last_width = None            # mm: the footprint's width on the last frame (None: not touching)
        self.ending_area = None           # mm2: the footprint's area on the last frame of a stroke's end (_collapsed)
        self.corner_press = 0.0           # L: the press at a hook's corner, eased from along its flick
        self.beads: dict = {}             # stroke family -> [strokes ending in a bead, strokes]
        self.count_planned_beads = False  # planned strokes tallied in beads too (PlanWriter's beads)
        self.solver = solver_tally()      # the solver over every frame written (brush.tally_step)
        self.planning = False             # rehearsing a stroke (no deposit, no tallies)
        self.rehearsed = 0                # solver steps spent rehearsing
        self.root = np.zeros(2)           # mm: the root's xy on the last frame
        self.log = _Log()                 # the last travel along a centreline, frame by frame
        self.sprung = False               # the last travel ended where the footprint collapsed (_collapsed)

    def _solve(self, pose: Pose):
        """One brush step, tallied in self.solver; returns the core's StepStats."""
        stats = self.brush.step(pose)
        if self.planning:
            self.rehearsed += 1
            return stats
        tally_step(self.solver, stats)
        return stats

    def _step(self, target: np.ndarray, heading: float, press: float, tilt: float, keep_down: bool = False) -> None:
        """One frame at `target` (mm) heading `heading` (rad) with `press` (L) and `tilt` (deg), and
        its deposit; `keep_down`: the brush belongs on the paper (the travel before any exit)."""
        c, s = math.cos(heading), math.sin(heading)
        off = np.array([c * self.offset_local[0] - s * self.offset_local[1],
                        s * self.offset_local[0] + c * self.offset_local[1]])
        self._pose_step(target + off, heading, press, tilt, keep_down)

    def _pose_step(self, root: np.ndarray, heading: float, press: float, tilt: float, keep_down: bool = False) -> None:
        """One frame with the root over `root` (2,) mm, pressed `press` L; deposits unless planning;
        `keep_down` as for _step."""
        self.root = root
        z = root_height(self.shape, tilt, press)
        pose = Pose((root[0], root[1], z), tilt, math.degrees(heading))
        stats = self._solve(pose)
        self.contact = self.brush.footprint()   # the contact polygon, once a frame (~20 µs)
        # a pressing brush that leaves the paper in the travel of a stroke (a bent, plastically set
        # tuft whose tip curls up under a light press: a true equilibrium), or whose footprint
        # shrinks within a frame to under taper_collapse of its width (its belly springs off as
        # the travel turns back on itself, at the corner of a 竖提), is pressed PRESS_ON deeper
        # and stepped again, up to HOLD_FRAMES times, as a hand feels the brush lift, rather than
        # lay a gap or a neck in the stroke
        seen = _centroid_and_width(self.contact, heading)
        for _ in range(HOLD_FRAMES):
            if not (keep_down and self.touching and press > 0.0
                    and self._slipped(None if seen is None else seen[1], self.last_width)):
                break
            press = min(press + PRESS_ON, PRESS_MAX)
            pose = Pose((root[0], root[1], root_height(self.shape, tilt, press)), tilt, math.degrees(heading))
            stats = self._solve(pose)
            self.contact = self.brush.footprint()
            seen = _centroid_and_width(self.contact, heading)
            self.frames += 1
            self.holds += 1
        self.last_width = None if seen is None else seen[1]
        if self.planning:                   # a rehearsal: the paper is left alone
            self.touching = self.touched_in_stroke = bool(self.contact)
            return
        if seen is not None or self.widths:              # from the first touch on
            self.widths.append(0.0 if seen is None else seen[1])
        dep = self.paper.deposit(self.brush)
        # a break: the brush came down again after leaving the paper within one stroke
        self.breaks += int(dep.new_stroke and self.touched_in_stroke)
        # touching as the core's own footprint sees it (whatever the paper's resolution, which
        # only samples the scene: its mesh's contact may differ by a frame at a stroke's ends)
        self.touching = bool(self.contact)
        self.touched_in_stroke = self.touched_in_stroke or self.touching
        self.frames += 1

    def _slipped(self, width: float | None, before: float | None) -> bool:
        """The brush has left the paper (its footprint's `width` is None), or its footprint has
        shrunk to under taper_collapse of its width `before`, a frame earlier."""
        if width is None:
            return True
        return before is not None and width < self.style.taper_collapse * before

    def _observe(self, target: np.ndarray, heading: float, width_target: float | None) -> None:
        seen = _centroid_and_width(self.contact, heading)
        st = self.style
        if seen is None:
            if width_target is not None:
                self.press = min(self.press + PRESS_ON, PRESS_MAX)   # not touching yet: press on
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
            self.press = float(_clip(self.press + st.width_gain * rel, 0.0, PRESS_MAX))

    def write_stroke(self, points_mm: np.ndarray, kind: str, joined: tuple = (False, False),
                     line: tuple | None = None) -> None:
        """One stroke along its centreline `points_mm` ((k, 2) mm) of stroke type `kind`; `joined`:
        whether its start and its end lie on another stroke of the character (see joins); `line`:
        targets.centreline of it, when the caller has it."""
        st = self.style
        # (the last stroke's deposits say nothing of this one: the brush travelled in the air)
        self.touched_in_stroke = self.touching = False
        self.widths = []
        self.last_width = self.ending_area = None
        w_nom = st.width_em * st.em_mm * self.density * (1.0 + st.jitter * self.rng.standard_normal())
        path, s, heading, width = stroke_targets(st, points_mm, kind, w_nom, line)
        aim = _Aim(st, path, s, width, joined)
        # 出锋: near the end of a tapering stroke the press only eases. The footprint does not
        # thin with the press: the spread belly keeps its width, then leaves the paper within a
        # frame or two and only the tip touches. A loop free to press again brought the belly
        # down on a folded tip, a bead at the end of a left-falling stroke 撇; eased only, the tip
        # alone drew a hairline past the end. So the travel ends where the belly has left, and
        # the brush lifts there
        tapering = st.taper_from is not None and family(kind) in TAPERING
        if st.flick_press is not None and family(kind) == "hook":
            aim.flick = aim.flick_from(heading)
            aim.past = int(round(FLICK_PAST_EM * st.em_mm / st.step_mm)) if aim.flick is not None else 0
        plan = self._plan(aim, heading, w_nom, tapering) if st.plan_passes > 0 else None
        self._come_down(aim, heading[0])
        j = self._along(aim, heading, w_nom, tapering, plan)
        self._lift(aim.point(self, j), heading[aim.on_median(j)], tapering)
        self.paper.end_stroke()
        tally_bead(self.beads, family(kind), self.widths)

    # what a rehearsal must put back: the brush's state and the writer's own
    _REHEARSED = ("press", "offset_local", "behind", "ahead", "touching", "touched_in_stroke", "frames", "holds",
                  "last_width", "ending_area", "breaks", "widths", "contact", "root")

    def _plan(self, aim: "_Aim", heading: np.ndarray, w_nom: float, tapering: bool) -> "_Plan":
        """Iterative learning control of one stroke: rehearse it (the brush's state kept and put
        back, nothing deposited) with the frame-by-frame loops, take the poses they chose as a
        plan, low-pass it, and `plan_passes` times replay the plan open-loop, measure the
        footprint's centre and width against the aim, and correct the whole plan by the
        low-passed errors. Returns the plan whose rehearsal came closest (the loops' own poses
        among them)."""
        st = self.style
        snap = ({k: copy.deepcopy(getattr(self, k)) for k in self._REHEARSED}, self.brush.state().copy())
        self.planning = True
        try:
            log = self._rehearse(aim, heading, w_nom, tapering, None, snap)
            tried = [(log.error(aim), _Plan(log.root, log.press))]
            plan = tried[0][1].smoothed(log, st.plan_sigma_mm / st.step_mm)
            for _ in range(st.plan_passes):
                log = self._rehearse(aim, heading, w_nom, tapering, plan, snap)
                tried.append((log.error(aim), plan))
                plan = plan.corrected(log, aim, st)
            return min(tried, key=lambda t: t[0])[1]
        finally:
            self.planning = False
            self._restore(snap)

    def _restore(self, snap: tuple) -> None:
        for k, v in snap[0].items():
            setattr(self, k, copy.deepcopy(v))
        self.brush.set_state(snap[1].copy())

    def _rehearse(self, aim: "_Aim", heading: np.ndarray, w_nom: float, tapering: bool, plan: "_Plan | None",
                  snap: tuple) -> "_Log":
        """Come down and travel along (with the loops, or replaying `plan`) from the state `snap`."""
        self._restore(snap)
        self._come_down(aim, heading[0])
        self._along(aim, heading, w_nom, tapering, plan)
        return self.log

    def _come_down(self, aim: "_Aim", h0: float) -> None:
        """Come down at the start: while in the air the tip is aimed at the stroke's start (the
        tuft lies down from its tip, so the tip marks the stroke's rear end), then pressed."""
        st = self.style
        self.behind = self.ahead = 0.5 * aim.width[0]
        c, sn = math.cos(h0), math.sin(h0)
        # the tip lands on the stroke's start; a start on another stroke, join_reach before it,
        # in that stroke's ink
        land = aim.path[0] - max(aim.joined_reach(), 0.0) * np.array([c, sn])
        for j in range(-st.air_frames, st.entry_frames):
            # first `air_frames` frames hovering, the tip swung over the start before it touches
            # (a descent still being aimed lays ink on its way in), then pressing down
            t = max(0, j + 1) / st.entry_frames
            p0 = aim.target(self, 0)
            self._step(p0, h0, -st.hover + (self.press + st.hover) * t, st.tilt_deg)
            if not self.contact:
                tip = np.asarray(self.brush.skeleton()[-1][:2])
                err = land - tip
                self.offset_local += np.array([c * err[0] + sn * err[1], -sn * err[0] + c * err[1]])
            else:
                self._observe(p0, h0, aim.width[0] if t >= 1.0 else None)

    def _along(self, aim: "_Aim", heading: np.ndarray, w_nom: float, tapering: bool,
               plan: "_Plan | None" = None) -> int:
        """The travel along the centreline, with the loops or replaying `plan`; logged in
        self.log; returns the index of its last frame."""
        st, width = self.style, aim.width
        self.log = _Log()
        self.sprung = False
        for j in range(len(aim.path) + aim.past if plan is None else len(plan.press)):
            if aim.flick is not None and j >= aim.flick:
                if not self._flick_step(aim, heading, j):
                    break
                continue
            pj = aim.target(self, j)
            if plan is None:
                if j > 0:
                    # feedforward: the press follows the profile's own change at once (L per unit of
                    # relative width change); the footprint loop only trims. A spread tuft keeps its
                    # width while the press eases (the hairs stick splayed), so a tapering exit 出锋
                    # must lift ahead of what the footprint shows
                    self.press = float(_clip(self.press + st.press_feedforward * (width[j] - width[j - 1]) / w_nom,
                                             0.0, PRESS_MAX))
                self._step(pj, heading[j], self.press, st.tilt_deg, keep_down=not (tapering and aim.tapers_at(j)))
                eased = self.press
                self._observe(pj, heading[j], width[j])
            else:
                self.press = eased = float(plan.press[j])
                self._pose_step(plan.root[j], heading[j], eased, st.tilt_deg, keep_down=not (tapering and aim.tapers_at(j)))
                self._follow(pj, heading[j])
            self.log.add(self.root, eased, pj, heading[j], self.contact)
            if tapering and aim.tapers_at(j) and self._taper_ends(eased, heading[j], width[j]):
                break
            if aim.ending_at(j) and self._collapsed(heading[j], width[j]):
                # ended before the loops eased the press off a pressed end (a dot's belly): that
                # press is no guess for the next stroke's entry, which pressed as deep and
                # touched down in a knob
                self.sprung = True
                self.press = min(self.press, st.press_start)
                break
        return j

    def _flick_step(self, aim: "_Aim", heading: np.ndarray, j: int) -> bool:
        """One frame of a hook's flick 钩: out of the pressed corner the hand flicks the brush
        along the hook and aim.past frames on past the median's end while it eases the press in
        a straight line from the corner's to the style's flick_press there, without the loops
        (their width loop, pressing the belly back down as it swung round the corner, left a club
        or a knot where the flick belongs). False once the brush has left the paper, or its
        footprint has shrunk within the frame to under taper_collapse of its width (the belly
        sprang off: flicked on, the tip came down again behind it, a bead at the hook's end)."""
        if j == aim.flick:
            self.corner_press = self.press
        corner = aim.s[aim.flick]
        f = (aim.arc(j) - corner) / max(aim.arc(len(aim.path) - 1 + aim.past) - corner, 1e-6)
        eased = self.corner_press + (self.style.flick_press - self.corner_press) * f
        self.press = float(_clip(eased, 0.0, PRESS_MAX))
        pj, hj, before = aim.point(self, j), heading[aim.on_median(j)], self.last_width
        self._step(pj, hj, self.press, self.style.tilt_deg)
        self.log.add(self.root, self.press, pj, hj, self.contact)
        return not self._slipped(self.last_width, before)

    def _collapsed(self, heading: float, width: float) -> bool:
        """The footprint has shrunk to under taper_collapse of the aimed width, or its area to under
        taper_collapse of the last frame's, or it has gone: a bent tuft whose belly has sprung off
        the paper near a stroke's end. Pressing on (the width loop would, and a tip that came down
        again swelled into a bead after the neck) is not what a hand does there: the stroke ends.
        (The width alone misses a belly that springs off a dot: the tip's stretch still spans it
        across, while the area falls to a quarter; followed on, the loops threw the root 4 mm
        after the footprint's moved centre and the tip left a bead past the dot's end.)"""
        seen = _centroid_and_width(self.contact, heading)
        if seen is None:
            return True
        area, before = footprint_area(self.contact), self.ending_area
        self.ending_area = area
        collapse = self.style.taper_collapse
        return seen[1] < collapse * width or (before is not None and area < collapse * before)

    def _follow(self, target: np.ndarray, heading: float) -> None:
        """On a replayed plan: what the loops would have learned, the footprint's reach and the
        root's offset from the aim (the lift returns along it; the next stroke starts from it)."""
        seen = _centroid_and_width(self.contact, heading)
        if seen is not None:
            self.behind, self.ahead = seen[2], seen[3]
        c, s = math.cos(heading), math.sin(heading)
        d = self.root - target
        self.offset_local = np.array([c * d[0] + s * d[1], -s * d[0] + c * d[1]])

    def _taper_ends(self, eased: float, heading: float, width: float) -> bool:
        """On a tapering exit the press only eases; True once the belly has left the paper."""
        self.press = min(self.press, eased)
        return not self.contact or self._collapsed(heading, width)

    def _lift(self, end: np.ndarray, h: float, tapering: bool) -> None:
        """Lift while drawing the root back over the footprint (回锋, returning the tip), so the
        unbending tuft does not sweep ink past the stroke's end; a tapered exit, and a travel that
        ended where the footprint collapsed (self.sprung), have no tip to return (only the tip
        touches): the brush leaves the paper at once, where it stands (eased up, the folded tip of
        a 捺 or a hook came down again behind the collapsed footprint, a bead at the exit; drawn
        back within that one frame, the root swept a tuft length back over the stroke)."""
        st = self.style
        back = np.array([math.cos(h), math.sin(h)]) * (0.0 if tapering or self.sprung else self.offset_local[0])
        # Once a deposit leaves no ink (the belly may already have left on the travel's last
        # frame) the rest of the lift is one frame: eased out over the remaining frames, the tuft
        # springing back as the root rose slowly swung its tip down onto the paper again, a dot
        # past the stroke's end
        for j in range(st.exit_frames):
            if tapering or self.sprung or not self.touching:
                self._step(end - back, h, -st.hover, st.tilt_deg)
                break
            t = (j + 1) / st.exit_frames
            self._step(end - back * t, h, self.press * (1 - t) - st.hover * t, st.tilt_deg)

    def travel(self, to_mm: np.ndarray, heading: float) -> None:
        """Lift and carry the brush in the air to above `to_mm`, turning toward `heading`."""
        st = self.style
        root = np.asarray(self.brush.skeleton()[0][:2])
        dist = float(np.linalg.norm(to_mm - root))
        n = int(np.clip(math.ceil(dist / (TRAVEL_STEP * st.step_mm)), *TRAVEL_FRAMES))
        z_hover = root_height(self.shape, st.tilt_deg, -st.hover)
        for j in range(n):
            t = (j + 1) / n
            self._solve(Pose((root[0] + (to_mm[0] - root[0]) * t, root[1] + (to_mm[1] - root[1]) * t,
                                  z_hover), st.tilt_deg, math.degrees(heading)))
            self.paper.deposit(self.brush)
            self.frames += 1

    def write_planned(self, glyph, plan, origin_mm=(0.0, 0.0), on_stroke=None) -> None:
        """The glyph written open-loop from its GlyphPlan (writing/plan.py), in the source's em box
        with its bottom-left corner at `origin_mm`; on_stroke as in write."""
        from .planned import PlanWriter

        writer = PlanWriter(self.style, self.paper, self.brush, origin_mm, self.solver,
                            self.beads if self.count_planned_beads else None)
        writer.write(glyph, plan, on_stroke)
        self.frames += writer.frames

    def write(self, glyph, origin_mm=(0.0, 0.0), on_stroke=None) -> None:
        """glyph's strokes in order with the em box's corner at origin_mm; on_stroke(k), when
        given, is called once stroke k is written and the brush has left the paper (on its way
        to the next stroke's start, or at the end): the font's weight masters take each stroke's
        ink from the paper there."""
        st = self.style
        if st.hand is not None:           # a learned hand: the plans from the medians alone
            from .hand import Hand

            self.write_planned(glyph, Hand.cached(st.hand_path()).plan(glyph, st, self.rng), origin_mm, on_stroke)
            return
        self.brush.load_ink(total_mm2=st.ink_mm2, excess=0.0)
        o = np.asarray(origin_mm, dtype=float)
        self.density = st.density(len(glyph.strokes))
        medians = [o + (np.asarray(stroke.points, dtype=float) + np.asarray(st.offset_em, dtype=float)) * st.em_mm
                   for stroke in glyph.strokes]
        for k, (stroke, pts) in enumerate(zip(glyph.strokes, medians)):
            # in the air the brush turns to the heading it will come down with
            line = centreline(st, pts)
            self.travel(pts[0], float(line[2][0]))
            if on_stroke is not None and k > 0:
                on_stroke(k - 1)
            self.write_stroke(pts, stroke.kind, joins(medians, k, st.width_em * st.em_mm), line)
        if on_stroke is not None and glyph.strokes:
            on_stroke(len(glyph.strokes) - 1)


class _Aim:
    """One stroke's aim points: path (n, 2) mm at arc lengths s (n,) mm, target widths (n,) mm.
    The footprint must not reach past the stroke's ends by more than the style's reach (mm; half
    a width unless the style says): its centre's arc length is held within
    [behind - reach, length + reach - ahead]."""

    def __init__(self, st: Style, path: np.ndarray, s: np.ndarray, width: np.ndarray,
                 joined: tuple = (False, False)):
        self.st, self.path, self.s, self.width = st, path, s, width
        self.joined = joined
        self.flick: int | None = None     # the first frame of a hook's flick (flick_from), if written as one
        self.past = 0                     # frames the flick goes on past the median's end
        self.length = max(s[-1], 1e-6)
        self.start_reach = st.end_reach_em if st.start_reach_em is None else st.start_reach_em
        self.end_reach = st.end_reach_em
        # an end that lies on another stroke reaches into that stroke's ink (join_reach_em)
        if st.join_reach_em is not None:
            if joined[0]:
                self.start_reach = max(self.start_reach if self.start_reach is not None else -1.0, st.join_reach_em)
            if joined[1]:
                self.end_reach = max(self.end_reach if self.end_reach is not None else -1.0, st.join_reach_em)

    def joined_reach(self) -> float:
        """mm a start on another stroke reaches into it (join_reach_em), 0 for a free start."""
        st = self.st
        return st.join_reach_em * st.em_mm if self.joined[0] and st.join_reach_em is not None else 0.0

    def _reach(self, r_em: float | None, j: int) -> float:
        return 0.5 * self.width[j] if r_em is None else r_em * self.st.em_mm

    def target(self, writer: "Writer", j: int) -> np.ndarray:
        """The point (2,) mm the footprint's centre aims at on frame j, given how far the
        writer's footprint reaches behind and ahead of its centre."""
        lo = writer.behind - self._reach(self.start_reach, j)
        hi = self.length + self._reach(self.end_reach, j) - writer.ahead
        sj = 0.5 * (lo + hi) if lo > hi else float(_clip(self.s[j], lo, hi))
        sj = float(_clip(sj, 0.0, self.length))
        return np.array([np.interp(sj, self.s, self.path[:, 0]), np.interp(sj, self.s, self.path[:, 1])])

    def on_median(self, j: int) -> int:
        """The path's index of frame j: frames past the median's end (a flick's) stay at its end."""
        return min(j, len(self.path) - 1)

    def widths(self, m: int) -> np.ndarray:
        """(m,) the target widths of frames 0..m-1, the end's held past the median's end."""
        return self.width[np.minimum(np.arange(m), len(self.width) - 1)]

    def arc(self, j: int) -> float:
        """mm of arc of frame j, one step_mm a frame on past the median's end."""
        k = self.on_median(j)
        return float(self.s[k]) + (j - k) * self.st.step_mm

    def point(self, writer: "Writer", j: int) -> np.ndarray:
        """target(j), and past the median's end straight on along its last segment."""
        k = self.on_median(j)
        d = self.path[-1] - self.path[-2]          # (a resampled path has two points at least)
        return self.target(writer, k) + d / max(float(np.linalg.norm(d)), 1e-9) * (j - k) * self.st.step_mm

    def ending_at(self, j: int) -> bool:
        """Past taper_from along the median (any stroke's last stretch)."""
        return self.st.taper_from is not None and self.s[j] > self.st.taper_from * self.length

    def flick_from(self, heading: np.ndarray) -> int | None:
        """The first frame of the hook's flick: the last along the path whose heading differs by
        more than FLICK_TURN from the end's, where it lies past FLICK_FROM of the median; None
        where the path has no such turn."""
        turned = np.nonzero(np.abs(heading - heading[-1]) > FLICK_TURN)[0]
        if len(turned) == 0 or self.s[turned[-1]] < FLICK_FROM * self.length:
            return None
        return int(turned[-1])

    def tapers_at(self, j: int) -> bool:
        """Past taper_from along the median, where the profile thins toward the next point."""
        w = self.width
        return self.ending_at(j) and j + 1 < len(self.path) and w[j + 1] < w[j]


def _ramp(m: int, sigma: float) -> np.ndarray:
    """(m,) 0 at a travel's first frame rising to 1 over ~sigma frames: the travel starts where
    the come-down left the brush, and a plan's changes fade in from there."""
    return 1.0 - np.exp(-np.arange(m) / max(sigma, 1e-6))


def _pinned(a: np.ndarray, sigma: float) -> np.ndarray:
    """`a` (m, ...) low-passed (`sigma` frames), its first frame kept (faded in by _ramp)."""
    smooth = lowpass(a, sigma)
    ramp = _ramp(len(a), sigma).reshape((-1,) + (1,) * (a.ndim - 1))
    return smooth + (1.0 - ramp) * (a[:1] - smooth[:1])


class _Log:
    """One travel along a centreline, a row a frame: the root's xy (mm), the press (L), the aim
    point (mm), the footprint's centre (mm; NaN off the paper) and its width across the travel
    (mm; 0 off the paper)."""

    def __init__(self):
        self.rows: list = []

    def add(self, root, press: float, aim_point, heading: float, loops) -> None:
        """A frame: the footprint `loops` seen from `aim_point` (2,) mm, the travel along `heading`
        rad: its area centroid and its extent across the travel (the ink's edges)."""
        seen = _centroid_and_width(loops, heading)
        if seen is None:
            self.rows.append((*root, press, *aim_point, np.nan, np.nan, 0.0))
            return
        t = np.array([math.cos(heading), math.sin(heading)])
        n = np.array([-t[1], t[0]])
        across = np.concatenate([np.asarray(loop)[:, :2] for loop in loops]) @ n - float(np.dot(aim_point, n))
        lo, hi = float(across.min()), float(across.max())
        # the footprint's centre: along the travel its centroid, across it the middle of its edges
        centre = np.asarray(aim_point) + float(np.dot(seen[0] - aim_point, t)) * t + 0.5 * (lo + hi) * n
        self.rows.append((*root, press, *aim_point, *centre, hi - lo))

    @property
    def table(self) -> np.ndarray:
        """(m, 8): root x y, press, aim x y, centre x y, width."""
        return np.array(self.rows, dtype=float).reshape(-1, 8)

    root = property(lambda self: self.table[:, 0:2])
    press = property(lambda self: self.table[:, 2])

    def errors(self, aim: "_Aim") -> tuple[np.ndarray, np.ndarray]:
        """(m, 2) mm aim - centre (0 off the paper) and (m,) relative width error (w_aim - w) / w_aim."""
        t = self.table
        pos = np.nan_to_num(t[:, 3:5] - t[:, 5:7])
        w_aim = aim.widths(len(t))
        return pos, (w_aim - t[:, 7]) / np.maximum(w_aim, 1e-3)

    def error(self, aim: "_Aim") -> float:
        """How far the footprint's edges were from the aim's, mean square over the frames on the
        median (a flick's frames past its end aim at no width), in units of the width: (position
        error / width)^2 + (relative width error)^2 / 2."""
        if not self.rows:
            return math.inf
        pos, rel = self.errors(aim)
        m = min(len(rel), len(aim.path))
        pos, rel, w_aim = pos[:m], rel[:m], aim.width[:m]
        return float(np.mean((pos ** 2).sum(axis=1) / w_aim ** 2 + 0.5 * rel ** 2))


class _Plan:
    """A stroke's poses for its travel, a row a frame: root (m, 2) mm, press (m,) L."""

    def __init__(self, root: np.ndarray, press: np.ndarray):
        self.root, self.press = np.asarray(root, dtype=float), np.asarray(press, dtype=float)

    def smoothed(self, log: _Log, sigma: float) -> "_Plan":
        """The plan low-passed (`sigma` frames): the root's offset from the aim and the press."""
        aim = log.table[:, 3:5]
        return _Plan(aim + _pinned(self.root - aim, sigma), _pinned(self.press, sigma))

    def corrected(self, log: _Log, aim: "_Aim", st: Style) -> "_Plan":
        """The plan moved by the low-passed errors of its rehearsal `log`: the root by
        plan_position_gain of the footprint's position error, the press by plan_press_gain L per
        unit of relative width error. Frames past where the rehearsal stopped are dropped."""
        pos, rel = log.errors(aim)
        sigma = st.plan_sigma_mm / st.step_mm
        m = len(rel)
        ramp = _ramp(m, sigma)
        root = self.root[:m] + st.plan_position_gain * ramp[:, None] * lowpass(pos, sigma)
        press = np.clip(self.press[:m] + st.plan_press_gain * ramp * lowpass(rel, sigma), 0.0, PRESS_MAX)
        return _Plan(root, press)
