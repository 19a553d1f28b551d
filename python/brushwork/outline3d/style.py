"""How an outline is drawn: the outline style's fields, one table of them (type, unit, range,
default, meaning) in the writing styles' StyleField form, which checks a style file and
documents it.

A style (JSON under outline3d/styles/, or a file) names the brush preset, how many mm the
image's longer side spans on the paper (so the brush's size against the drawing), tilt, step,
the press depth of a line of weight 1 (fraction of the tuft length L below first contact), the
width of each kind of line against that one (silhouettes heavier than creases), how much nearer
lines are widened and lines running behind a nearer one thinned, the calligraphic entry (a
press `entry_weight` times the line's over `entry_mm`) and exit (a taper to `exit_weight` times it
over `exit_mm`, lifting while moving), the ink (mm^2 per dip; `dip_mm` of drawn line between
dips, 0: before every chain), how hidden lines are drawn under --hidden faint, and the chains'
minimum length (of the image diagonal) and smoothing.
"""
from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from ..writing.style import FIELD_BY_NAME as WRITING, StyleField, read_style, style_dataclass

OUTLINE_STYLE_DIR = Path(__file__).with_name("styles")
KIND_WEIGHTS = {"silhouette": 1.0, "boundary": 0.8, "crease": 0.6, "suggestive": 0.4}

_F = StyleField
# (the fields a writing style has too are its table's rows)
FIELDS: tuple[StyleField, ...] = (
    WRITING["name"],
    replace(WRITING["description"], doc="what the line looks like"),
    replace(WRITING["preset"], default="small"),
    _F("paper_mm", "float", "mm", 10.0, 5000.0, 200.0, "what the image's longer side spans on the paper"),
    WRITING["tilt_deg"],
    WRITING["step_mm"],
    _F("press", "float", "L", 0.0, 0.45, 0.125, "press depth of a line of weight 1, fraction of the tuft length",
       lo_open=True),
    _F("weight", "map", "-", 0.0, 3.0, KIND_WEIGHTS, "each kind's line width against a line of weight 1"),
    _F("depth_weight", "float", "-", 0.0, 1.5, 0.0,
       "the nearest line's width times 1 + this / 2, the farthest's times 1 - this / 2"),
    _F("occlusion_thinning", "float", "-", 0.0, 0.9, 0.35,
       "a line's width falls by up to this share where it runs behind a nearer line"),
    _F("entry_mm", "float", "mm", 0.0, 100.0, 10.0, "length of the entry, the tip touching down while moving"),
    _F("entry_weight", "float", "-", 0.0, 3.0, 1.0, "width at the entry's deepest, times the line's"),
    _F("exit_mm", "float", "mm", 0.0, 100.0, 6.0, "length of the exit's taper"),
    _F("exit_weight", "float", "-", 0.0, 3.0, 0.8, "width at the line's end, times the line's"),
    _F("ink_mm2", "float", "mm^2", 0.0, 1e7, 20000.0, "ink the brush is dipped with, paper at full density",
       lo_open=True),
    _F("dip_mm", "float", "mm", 0.0, 1e6, 0.0, "drawn line between dips (0: a dip before every line)"),
    _F("hidden_alpha", "float", "-", 0.0, 1.0, 0.25, "opacity of hidden lines (--hidden faint)"),
    _F("hidden_weight", "float", "-", 0.0, 3.0, 0.7, "width of hidden lines against visible ones"),
    _F("min_length", "float", "diagonal", 0.0, 0.5, 0.012, "shorter chains are not drawn"),
    _F("smooth_passes", "int", "passes", 0, 200, 20, "Laplacian smoothing of each chain, half way per pass"),
    replace(WRITING["scene"], default={}),
)


class _OutlineStyleMethods:
    @classmethod
    def load(cls, spec: str) -> "OutlineStyle":
        """A bundled style by name (baimiao, xieyi) or a JSON file; StyleError (a ValueError)
        naming the file, the field and the value."""
        return cls(**read_style(spec, OUTLINE_STYLE_DIR, FIELDS))

    @staticmethod
    def names() -> list[str]:
        return sorted(p.stem for p in OUTLINE_STYLE_DIR.glob("*.json"))


OutlineStyle = style_dataclass("OutlineStyle", FIELDS, (_OutlineStyleMethods,))
OutlineStyle.__module__ = __name__
OutlineStyle.__doc__ = "How an outline is drawn: the fields of FIELDS. Loaded by OutlineStyle.load."
