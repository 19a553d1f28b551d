"""Recorded brush motions: fixed pose sequences used by the tests and the benchmarks.

Every motion is a pure function of the model's size and its arguments, so the same call replays
the same stroke bit for bit (libmypaint's way: replay a recorded stroke as the benchmark).
Lengths scale with the tuft length L so that one motion suits every preset.
"""
from __future__ import annotations

import math

import numpy as np

from ._core import BrushModel, Pose

# how far the scripted and driven motions take the brush, in tuft lengths L (root_height's `press`)
HOVER = 0.1          # L: the straight tuft's tip this far above the paper while the brush travels in the air
PRESS_MAX = 0.45     # L: the deepest press below first contact a driver asks for (a pen at full pressure)


def _lerp(a: float, b: float, t: float) -> float:
    return a + (b - a) * t


def root_height(model: BrushModel, tilt_deg: float, press: float) -> float:
    """Height z (mm) of the brush root `press` L below first contact, the handle tilted
    `tilt_deg` from the vertical: L cos(tilt) - press L, L the tuft length (press 0: the straight
    tuft's tip just touches the paper; negative: the tip is above it)."""
    L = model.tuft_length
    return L * math.cos(math.radians(tilt_deg)) - press * L


def press_drag_turn_lift(model: BrushModel, frames: int = 320, press: float = 0.2,
                         tilt_deg: float = 15.0) -> list[Pose]:
    """A calligraphic stroke: descend and press (root `press` L below first contact), drag along +x,
    turn a quarter circle toward +y, then lift while moving, and hang in the air at the end.

    Phases as fractions of `frames`: 12% press, 38% drag, 25% turn, 19% lift, 6% in the air.
    The handle leans toward the direction of travel by `tilt_deg`, so the tip trails (a
    normal stroke; leaning it back would push the tip, see `pushed_stroke`).
    """
    if frames < 50:
        raise ValueError(f"press_drag_turn_lift: frames = {frames} is too few (at least 50)")
    L = model.tuft_length
    contact_z = root_height(model, tilt_deg, 0.0)
    z_air, z_press = contact_z + 0.15 * L, root_height(model, tilt_deg, press)
    n_press, n_drag, n_turn, n_lift = (int(frames * f) for f in (0.12, 0.38, 0.25, 0.19))
    n_air = frames - n_press - n_drag - n_turn - n_lift
    drag_len, radius = 2.0 * L, 0.8 * L
    poses: list[Pose] = []
    # press: straight down at the origin, the handle leaning toward +x (azimuth 0)
    for k in range(n_press):
        t = (k + 1) / n_press
        poses.append(Pose((0.0, 0.0, _lerp(z_air, z_press, t)), tilt_deg, 0.0))
    # drag along +x
    for k in range(n_drag):
        t = (k + 1) / n_drag
        poses.append(Pose((drag_len * t, 0.0, z_press), tilt_deg, 0.0))
    # turn: a quarter circle from heading +x to heading +y, the handle leaning into the heading
    cx, cy = drag_len, radius
    for k in range(n_turn):
        a = 0.5 * math.pi * (k + 1) / n_turn
        x, y = cx + radius * math.sin(a), cy - radius * math.cos(a)
        heading = math.degrees(a)
        poses.append(Pose((x, y, z_press), tilt_deg, heading))
    # lift while moving on along +y
    x0, y0 = cx + radius, cy
    for k in range(n_lift):
        t = (k + 1) / n_lift
        poses.append(Pose((x0, y0 + 0.5 * L * t, _lerp(z_press, z_air, t)), tilt_deg, 90.0))
    for _ in range(n_air):
        poses.append(Pose((x0, y0 + 0.5 * L, z_air), tilt_deg, 90.0))
    return poses


def pressed_drag(model: BrushModel, frames: int = 160, press: float = 0.2, tilt_deg: float = 30.0,
                 azimuth_deg: float = 0.0, heading_deg: float = 0.0,
                 speed: float = 0.02) -> list[Pose]:
    """Press at the origin over frames // 4, then drag along `heading_deg` at `speed` L per frame
    with the handle held at (`tilt_deg`, `azimuth_deg`). azimuth = heading: the tip trails;
    azimuth = heading + 180: the tip is pushed (seed Figure 11b); heading + 90: a biased tip."""
    L = model.tuft_length
    contact_z = root_height(model, tilt_deg, 0.0)
    z_air, z_press = contact_z + HOVER * L, root_height(model, tilt_deg, press)
    n_press = max(frames // 4, 1)
    h = math.radians(heading_deg)
    poses = []
    for k in range(n_press):
        poses.append(Pose((0.0, 0.0, _lerp(z_air, z_press, (k + 1) / n_press)), tilt_deg, azimuth_deg))
    for k in range(frames - n_press):
        d = speed * L * (k + 1)
        poses.append(Pose((d * math.cos(h), d * math.sin(h), z_press), tilt_deg, azimuth_deg))
    return poses


def flick(model: BrushModel, frames: int = 40, press: float = 0.15, tilt_deg: float = 20.0,
          reach: float = 1.5, heading_deg: float = 45.0) -> list[Pose]:
    """A fast flick, the hook's exit: press at the origin, hold, then sweep the root `reach` L
    along `heading_deg` while rising into the air within a few frames, and let the brush spring
    back in the air.  The handle leans toward the flick by `tilt_deg`.

    Phases as fractions of `frames`: 40% press, 10% hold, 15% flick (at 40 frames six frames of
    0.25 L each), 35% in the air at the end point.
    """
    if frames < 20:
        raise ValueError(f"flick: frames = {frames} is too few (at least 20)")
    L = model.tuft_length
    contact_z = root_height(model, tilt_deg, 0.0)
    z_air, z_press = contact_z + 0.15 * L, root_height(model, tilt_deg, press)
    n_press, n_hold, n_flick = (max(1, int(frames * f)) for f in (0.40, 0.10, 0.15))
    n_air = frames - n_press - n_hold - n_flick
    h = math.radians(heading_deg)
    poses: list[Pose] = []
    for k in range(n_press):
        poses.append(Pose((0.0, 0.0, _lerp(z_air, z_press, (k + 1) / n_press)), tilt_deg, heading_deg))
    poses += [Pose((0.0, 0.0, z_press), tilt_deg, heading_deg)] * n_hold
    # the flick: the root accelerates along the heading while the lift takes it off the paper
    for k in range(n_flick):
        t = (k + 1) / n_flick
        d = reach * L * t
        poses.append(Pose((d * math.cos(h), d * math.sin(h), _lerp(z_press, z_air, t)), tilt_deg, heading_deg))
    end = (reach * L * math.cos(h), reach * L * math.sin(h), z_air)
    poses += [Pose(end, tilt_deg, heading_deg)] * n_air
    return poses


def replay(brush, poses) -> list:
    """Step `brush` through `poses`; return the list of StepStats."""
    return [brush.step(p) for p in poses]


def mean_iterations(model: BrushModel, poses, warm_hessian: bool) -> float:
    """Mean SQP iterations per frame over `poses` with the carried or a fresh Hessian."""
    from .brush import Brush

    m = model.copy()
    m.warm_hessian = warm_hessian
    b = Brush(m)
    return float(np.mean([s.iterations for s in replay(b, poses)]))


def straight_stroke(model: BrushModel, start=(0.0, 0.0), length_mm: float = 60.0,
                    step_mm: float = 1.0, press: float = 0.2, tilt_deg: float = 15.0,
                    heading_deg: float = 0.0, azimuth_deg: float | None = None,
                    press_frames: int = 12, lift_frames: int = 6) -> list[Pose]:
    """Descend at `start` (mm) and press `press` L below first contact over `press_frames`,
    drag `length_mm` along `heading_deg` in steps of `step_mm` per frame, then lift while
    moving on. The handle leans toward the heading unless `azimuth_deg` says otherwise."""
    if not (step_mm > 0 and length_mm > 0):
        raise ValueError(f"straight_stroke: step_mm = {step_mm} and length_mm = {length_mm} must be > 0")
    L = model.tuft_length
    az = heading_deg if azimuth_deg is None else azimuth_deg
    contact_z = root_height(model, tilt_deg, 0.0)
    z_air, z_press = contact_z + HOVER * L, root_height(model, tilt_deg, press)
    h = math.radians(heading_deg)
    ux, uy = math.cos(h), math.sin(h)
    poses = [Pose((start[0], start[1], _lerp(z_air, z_press, (k + 1) / press_frames)), tilt_deg, az)
             for k in range(press_frames)]
    n_drag = max(1, int(math.ceil(length_mm / step_mm - 1e-9)))
    for k in range(n_drag):
        d = min(length_mm, step_mm * (k + 1))
        poses.append(Pose((start[0] + d * ux, start[1] + d * uy, z_press), tilt_deg, az))
    for k in range(lift_frames):
        d = length_mm + 0.05 * L * (k + 1)
        poses.append(Pose((start[0] + d * ux, start[1] + d * uy,
                           _lerp(z_press, z_air + HOVER * L, (k + 1) / lift_frames)), tilt_deg, az))
    return poses


def along_path(model: BrushModel, points, press, tilt_deg=15.0, azimuth_deg=None,
               step_mm: float = 0.5, approach_frames: int = 8, lift_frames: int = 6,
               hover: float = HOVER) -> list[Pose]:
    """Poses that carry the brush along a polyline on the paper.

    points: (k, 2) mm, k >= 2; press: depth below first contact as a fraction of L, a scalar
    or (k,) per point (0: the tip just touches; negative: above the paper); tilt_deg and
    azimuth_deg: scalars or (k,) (azimuth None: the handle leans along the local heading, so the
    tip trails). The path is resampled every `step_mm`; the brush descends from `hover` L above
    contact over `approach_frames` and rises as much over `lift_frames` at the end.
    """
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 2 or not np.all(np.isfinite(pts)):
        raise ValueError("along_path: points must be a finite (k, 2) array with k >= 2")
    if not step_mm > 0:
        raise ValueError(f"along_path: step_mm = {step_mm} must be > 0")
    k = len(pts)

    def per_point(v, name):
        a = np.broadcast_to(np.asarray(v, dtype=float), (k,)).copy()
        if not np.all(np.isfinite(a)):
            raise ValueError(f"along_path: {name} must be finite")
        return a

    press_k, tilt_k = per_point(press, "press"), per_point(tilt_deg, "tilt_deg")
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])                       # (k,) arc length, mm
    if s[-1] <= 0:
        raise ValueError("along_path: the path has zero length")
    headings = np.degrees(np.arctan2(np.diff(pts[:, 1]), np.diff(pts[:, 0])))
    headings = np.degrees(np.unwrap(np.radians(np.concatenate([headings, headings[-1:]]))))
    az_k = headings if azimuth_deg is None else per_point(azimuth_deg, "azimuth_deg")
    n = max(2, int(math.ceil(s[-1] / step_mm)) + 1)
    ss = np.linspace(0.0, s[-1], n)
    xs, ys = np.interp(ss, s, pts[:, 0]), np.interp(ss, s, pts[:, 1])
    pr, tl, az = np.interp(ss, s, press_k), np.interp(ss, s, tilt_k), np.interp(ss, s, az_k)
    poses = []
    z_first = (root_height(model, tl[0], -hover), root_height(model, tl[0], pr[0]))    # hover, pressed
    for j in range(approach_frames):
        t = (j + 1) / (approach_frames + 1)
        poses.append(Pose((xs[0], ys[0], _lerp(*z_first, t)), tl[0], az[0]))
    poses += [Pose((x, y, root_height(model, t, p)), t, a) for x, y, p, t, a in zip(xs, ys, pr, tl, az)]
    z_last = (root_height(model, tl[-1], pr[-1]), root_height(model, tl[-1], -hover))  # pressed, hover
    for j in range(lift_frames):
        t = (j + 1) / lift_frames
        poses.append(Pose((xs[-1], ys[-1], _lerp(*z_last, t)), tl[-1], az[-1]))
    return poses
