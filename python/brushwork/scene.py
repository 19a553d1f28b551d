"""What a scene uses (DESIGN "scene.py").

A `Scene` names the rendering features a picture needs. What it leaves off is not computed on the
CPU and not compiled into the footprint shader: a plain black stroke pays for none of the split,
dry, grain, soaked-tip, colour-ramp or depletion machinery (see `brushwork bench render`).
"""
from __future__ import annotations

from . import _core

#: the scene's table (name, unit, kind, default, range, shader define, doc), written once in the core
SLOTS = tuple(_core.scene_slots())

#: feature switches, in the order the seed introduces them
FEATURES = tuple(row["name"] for row in SLOTS if row["kind"] == "bool")

#: the features only the GL footprint pass draws (a scene without them is opaque: its ink is geometry)
TEXTURED = ("split_map", "dry_map", "grain", "soaked_tip", "color_ramp")

#: tuning fields: name -> (unit, meaning)
PARAMETERS = {row["name"]: (row["unit"], row["doc"]) for row in SLOTS if row["kind"] != "bool"}


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
