"""The friendly face of the C++ brush: `Brush` and `Pose` (see DESIGN.md's promised names)."""
from __future__ import annotations

import math

import numpy as np

from . import _core

Pose = _core.Pose


def lerp_angle(a: float, b: float, t: float) -> float:
    """From angle a toward b (deg), a fraction t of the way, the short way round."""
    return a + ((b - a + 180.0) % 360.0 - 180.0) * t


def between(a: Pose, b: Pose, t: float) -> Pose:
    """The pose a fraction t of the way from a to b: position and tilt straight, the azimuth and the
    twist the short way round."""
    pa, pb = np.asarray(a.position, dtype=float), np.asarray(b.position, dtype=float)
    return Pose(tuple(pa + (pb - pa) * t), a.tilt_deg + (b.tilt_deg - a.tilt_deg) * t,
                lerp_angle(a.azimuth_deg, b.azimuth_deg, t), lerp_angle(a.twist_deg, b.twist_deg, t))


def solver_tally() -> dict:
    """An empty tally of solved frames (see tally_step)."""
    return {"steps": 0, "steps_at_q_max": 0, "iterations": 0, "substeps": 0, "max_penetration_mm": 0.0}


def tally_step(tally: dict, stats: _core.StepStats) -> None:
    """Add one step's `StepStats` to `tally`: steps, steps whose solve stopped at the iteration cap
    q_max unconverged (a split frame's iterations add up over its sub-steps, so a count of
    iterations alone says nothing), SQP iterations, sub-steps, the deepest penetration of the
    shrunk sections (mm)."""
    tally["steps"] += 1
    tally["steps_at_q_max"] += int(stats.status == "iteration cap")
    tally["iterations"] += stats.iterations
    tally["substeps"] += stats.substeps
    tally["max_penetration_mm"] = max(tally["max_penetration_mm"], stats.max_penetration)


class Brush(_core.Brush):
    """One tuft of the Chu-Tai brush (a spine of n joints with lateral nodes and a swept surface).

    ``step(pose)`` solves one frame and returns `StepStats`; ``skeleton()`` is the (n+1, 3) spine,
    root first, in mm; ``footprint()`` a list of (k, 2) polygons on the paper (mm, outer loops
    counter-clockwise, holes clockwise); ``footprint_area()`` their area in mm^2; ``reset()``
    straightens the brush and forgets plasticity.  ``state()`` copies everything that moves (an
    opaque `BrushState`, with ``copy()``, the ink included) and ``set_state(state)`` puts it back
    (ValueError for a state of a brush of another shape): the brush then replays bit for bit.
    """

    def __init__(self, model: _core.BrushModel | str = "medium"):
        if isinstance(model, str):
            model = _core.BrushModel.preset(model)
        super().__init__(model)

    @property
    def ink(self) -> _core.Ink:
        """The ink on this brush, part of its state: a live view, full on first use (see
        `load_ink`)."""
        ink = self._ink()
        if ink.load.size == 0:
            self._set_ink(_core.Ink(self, self.default_ink_mm2()))
            ink = self._ink()
        return ink

    @ink.setter
    def ink(self, value: _core.Ink) -> None:
        self._set_ink(value)

    def load_ink(self, total_mm2: float | None = None, ramp=None, excess: float = 1.0) -> _core.Ink:
        """Dip the brush: full ink (`total_mm2` of paper at full density; default 2 pi r^2 L
        mm^2, about what the tuft's volume holds), wetness 1, `excess` soaked-tip moisture,
        and an optional colour `ramp` ((K, 4) straight RGBA from root to tip)."""
        m = self.model
        total = total_mm2 if total_mm2 is not None else self.default_ink_mm2()
        ink = _core.Ink(self, float(total))
        if ramp is not None:
            ink.ramp = [tuple(float(c) for c in rgba) for rgba in ramp]
        ink.excess = float(excess)
        self._set_ink(ink)
        self.wetness = np.ones(m.n_segments + 1)
        return self._ink()

    def copy(self) -> "Brush":
        """An independent brush in exactly this state (the next step() of both agrees bit for
        bit), ink included."""
        twin = type(self)(self.model)
        twin.copy_state_from(self)
        return twin

    def default_ink_mm2(self) -> float:
        """Ink a dipped tuft holds, in mm^2 of paper at full density: 2 pi r^2 L."""
        m = self.model
        return 2.0 * math.pi * m.belly_radius ** 2 * m.tuft_length

    def tufts(self) -> list[np.ndarray]:
        """The spine of every tuft, the main tuft first, then each sprouted child tuft (seed
        "Simulation with multiple tufts"): a list of (n_j+1, 3) arrays in mm, root first;
        ``tufts_active`` counts the children."""
        return self._tuft_skeletons()

    def lateral_nodes(self):
        """(n+1, 2, 3) lateral node positions in mm: [:, 0] on the +u side, [:, 1] on the -u side."""
        return super().lateral_nodes().reshape(-1, 2, 3)

    def __repr__(self) -> str:
        m = self.model
        return f"Brush(n_segments={m.n_segments}, tuft_length={m.tuft_length} mm)"
