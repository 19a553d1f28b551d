"""The brush view: an image of the brush over the paper, for previews (seed Figure 8)."""
from __future__ import annotations

import numpy as np

from . import _core

MODES = ("shaded", "outlined", "transparent")


class BrushView(_core.BrushView):
    """An offscreen `width_px` x `height_px` camera on the brush and the paper.

    ``render(brush, paper)`` returns (H, W, 4) uint8 RGBA, row 0 at the top. The camera looks at
    `target` (default: a third of the way down the tuft from its root) from `eye` (default:
    behind and above, at two tuft lengths); `fov_deg=0` makes it orthographic, showing
    `ortho_height_mm` of the scene.
    """

    def __init__(self, width_px: int = 640, height_px: int = 480):
        super().__init__(int(width_px), int(height_px))

    def render(self, brush, paper=None, mode: str = "shaded", shadow: bool = True, eye=None,
               target=None, fov_deg: float = 35.0, ortho_height_mm: float = 80.0,
               light=(-0.4, -0.5, 1.0)) -> np.ndarray:
        if mode not in MODES:
            raise ValueError(f"mode = {mode!r}: expected one of {MODES}")
        L = brush.model.tuft_length
        root = np.asarray(brush.skeleton()[0], float)
        o = _core.ViewOptions()
        o.mode, o.shadow = mode, bool(shadow)
        o.target = np.asarray(target if target is not None else (root[0], root[1], root[2] / 3.0), float)
        o.eye = np.asarray(eye if eye is not None else o.target + np.array([-0.8 * L, -1.6 * L, 1.6 * L]), float)
        o.fov_deg, o.ortho_height_mm = float(fov_deg), float(ortho_height_mm)
        o.light = np.asarray(light, float)
        return super().render(paper, brush, getattr(brush, "ink", None), o)
