"""The friendly face of the C++ brush: `Brush` and `Pose` (see DESIGN.md's promised names)."""
from __future__ import annotations

from . import _core

Pose = _core.Pose


class Brush(_core.Brush):
    """One tuft of the Chu-Tai brush (a spine of n joints with lateral nodes and a swept surface).

    ``step(pose)`` solves one frame and returns `StepStats`; ``skeleton()`` is the (n+1, 3) spine,
    root first, in mm; ``footprint()`` a list of (k, 2) polygons on the paper (mm, outer loops
    counter-clockwise, holes clockwise); ``footprint_area()`` their area in mm^2; ``reset()``
    straightens the brush and forgets plasticity.
    """

    def __init__(self, model: _core.BrushModel | str = "medium"):
        if isinstance(model, str):
            model = _core.BrushModel.preset(model)
        super().__init__(model)

    def lateral_nodes(self):
        """(n+1, 2, 3) lateral node positions in mm: [:, 0] on the +u side, [:, 1] on the -u side."""
        return super().lateral_nodes().reshape(-1, 2, 3)

    def __repr__(self) -> str:
        m = self.model
        return f"Brush(n_segments={m.n_segments}, tuft_length={m.tuft_length} mm)"
