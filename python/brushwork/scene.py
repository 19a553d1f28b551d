"""What a scene uses (DESIGN "scene.py").

A `Scene` names the rendering features a picture needs. What it leaves off is not computed on the
CPU and not compiled into the footprint shader: a plain black stroke pays for none of the split,
dry, grain, soaked-tip, colour-ramp or depletion machinery (see `brushwork bench render`).
"""
from __future__ import annotations

from . import _core

#: feature switches, in the order the seed introduces them
FEATURES = ("split_map", "dry_map", "grain", "soaked_tip", "color_ramp", "depletion")

#: the features only the GL footprint pass draws (a scene without them is opaque: its ink is geometry)
TEXTURED = ("split_map", "dry_map", "grain", "soaked_tip", "color_ramp")

#: tuning fields: name -> (unit, meaning)
PARAMETERS = {
    "dry_onset": ("-", "wetness below which the dry map opens streaks"),
    "dry_pressure": ("-", "how much node pressure closes dry streaks again"),
    "grain_onset": ("-", "wetness below which paper grain shows"),
    "grain_pressure": ("-", "how much pressure presses ink into the grain's valleys"),
    "grain_mm": ("mm", "size of the paper grain's features"),
    "streak_mm": ("mm", "width of a bristle streak across the stroke (split and dry fields)"),
    "dry_speed": ("-", "dryness added per mm the footprint travels per frame"),
    "soak_expand": ("-", "radial growth of a soaked tip at full excess moisture"),
    "soak_shift": ("-", "split map scaled toward the tip at full excess moisture"),
    "soak_drain_mm": ("mm", "travel in contact over which excess moisture falls by 1/e"),
    "capillary": ("-", "depletion: per frame, each node's wetness moves this far toward the tuft's mean"),
    "seed": ("-", "seed of the procedural split, dry and grain fields"),
    "mesh_rings": ("-", "rings per spine segment of the swept surface, at most"),
    "mesh_around": ("-", "vertices around one ring, at most"),
    "mesh_mm": ("mm", "the render mesh is this fine (segment and belly circumference over it), up to the two caps, at every output size from 3 px to mesh_mm up; 0: the caps"),
    "samples": ("-", "multisampling of the stroke layer: 1, 2, 4 (default) or 8; 1 is ~2.5x faster on a software renderer"),
}


class Scene(_core.SceneFeatures):
    """Rendering features and their settings; every feature is off unless named.

    >>> Scene(split_map=True, dry_map=True)           # doctest: +SKIP
    >>> Scene.full()                                   # everything the renderer has
    """

    def __init__(self, **settings):
        super().__init__()
        for name, value in settings.items():
            if name not in FEATURES and name not in PARAMETERS:
                known = ", ".join(FEATURES + tuple(PARAMETERS))
                raise ValueError(f"Scene: unknown setting {name!r}; known: {known}")
            setattr(self, name, value)
        self.validate()

    @classmethod
    def minimal(cls) -> "Scene":
        """Ink from the footprint only: no maps, constant ink level."""
        return cls()

    @classmethod
    def full(cls, **settings) -> "Scene":
        """Every feature on (split, dry, grain, soaked tip, colour ramp, depletion)."""
        return cls(**{name: True for name in FEATURES}, **settings)

    def opaque(self) -> bool:
        """No split, dry or grain map, soaked tip or colour ramp: the ink is a region of the paper."""
        return not any(getattr(self, name) for name in TEXTURED)

    def features(self) -> list[str]:
        """The names of the features switched on."""
        return [name for name in FEATURES if getattr(self, name)]

    def __repr__(self) -> str:
        on = ", ".join(f"{name}=True" for name in self.features())
        return f"Scene({on})"
