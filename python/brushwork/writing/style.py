"""How a hand writes: the style's fields, ONE table of them (type, unit, range, default, meaning)
that both checks a style file and prints its documentation (`brushwork params --style`).

A style is data (`styles/<name>.json`): the brush preset, the em size, the nominal stroke width,
the tilt, the speed, the width profile of each stroke family and the ink.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field, make_dataclass
from pathlib import Path

import numpy as np

STYLE_DIR = Path(__file__).resolve().parent.parent / "styles"

# stroke type -> width-profile family (the kinds are CJK Strokes characters, glyphs.STROKE_TYPES)
FAMILIES = {
    "tapered": "㇒㇓㇢㇛㇜㇇㇋",        # left-falling: thin out and lift
    "flared": "㇏㇝",                  # right-falling: press, flare, lift
    "rising": "㇀㇙㇊",                # rising: start pressed, flick up thin
    "dot": "㇔",
    "hook": "㇚㇁㇂㇃㇆㇈㇉㇌㇖㇟㇠㇡",   # a hook's flick at the end
}
PROFILE_FAMILIES = ("plain",) + tuple(FAMILIES)
PROFILE_POINTS = 256      # most [s, factor] points in one family's width profile


def family(kind: str) -> str:
    """The width-profile family of a stroke type ("plain" for the rest: ㇐ ㇑ ㇕ ㇗ ...)."""
    for name, kinds in FAMILIES.items():
        if kind in kinds:
            return name
    return "plain"


@dataclass(frozen=True)
class StyleField:
    """One field of a style file. kind: str, float, int, float? (a number or null), pair (two
    floats), map (an object of the default's keys, each a number), scene (a Scene's settings) or
    profiles; lo..hi bound a number (lo excluded when lo_open); default None with required: the
    file must give it."""
    name: str
    kind: str
    unit: str
    lo: float | None
    hi: float | None
    default: object
    doc: str
    lo_open: bool = False
    required: bool = False

    def range_text(self) -> str:
        if self.lo is None:
            return {"scene": "Scene settings", "profiles": "s 0..1, factor 0..5",
                    "brush": "BrushModel fields"}.get(self.kind, "-")
        lo = f"> {self.lo:g}" if self.lo_open else f"{self.lo:g}"
        return f"{lo} .. {self.hi:g}" if self.lo_open else f"{lo}..{self.hi:g}"


_F = StyleField
FIELDS: tuple[StyleField, ...] = (
    _F("name", "str", "-", None, None, None, "the style's name", required=True),
    _F("description", "str", "-", None, None, "", "what the hand looks like"),
    _F("preset", "str", "-", None, None, "medium", "the brush: a BrushModel preset (`brushwork params`)"),
    _F("brush", "brush", "-", None, None, {},
       "the preset's model parameters this style sets otherwise, e.g. {\"spread_reach\": 1} (`brushwork params`)"),
    _F("em_mm", "float", "mm", 1.0, 1000.0, 100.0, "physical size of the em box on the paper"),
    _F("width_em", "float", "em", 0.0, 0.5, 0.06, "nominal stroke width", lo_open=True),
    _F("tilt_deg", "float", "deg", 0.0, 60.0, 15.0, "handle against the paper's normal, leaning along the travel"),
    _F("step_mm", "float", "mm", 0.1, 20.0, 1.0, "travel per frame"),
    _F("press_start", "float", "L", 0.0, 0.45, 0.2, "first guess of the press depth, fraction of the tuft length"),
    _F("position_gain", "float", "-", 0.0, 2.0, 0.8, "fraction of the footprint's position error corrected per frame"),
    _F("across_gain", "float", "-", 0.0, 2.0, 0.8, "the same, across the stroke"),
    _F("width_gain", "float", "L", 0.0, 1.0, 0.06, "press change per unit of relative width error"),
    _F("press_feedforward", "float", "L", 0.0, 2.0, 0.0,
       "press change per unit change of the profile's width / nominal"),
    _F("entry_frames", "int", "frames", 1, 100, 5, "frames pressing down at a stroke's start"),
    _F("exit_frames", "int", "frames", 0, 100, 4, "frames lifting at its end"),
    _F("air_frames", "int", "frames", 0, 100, 0, "frames hovering over a stroke's start, aiming the tip"),
    _F("hover", "float", "L", 0.0, 1.0, 0.12, "height above first contact between strokes"),
    _F("ink_mm2", "float", "mm^2", 0.0, 1e6, 6000.0, "ink the brush is dipped with, paper at full density"),
    _F("scene", "scene", "-", None, None, {"depletion": True}, "rendering features (Scene settings)"),
    _F("jitter", "float", "-", 0.0, 0.5, 0.03, "seeded relative variation of stroke width and pressure"),
    _F("corner_press", "float", "-", 0.5, 3.0, 1.2, "width factor at a corner of the centreline (折)"),
    _F("density_gain", "float", "1/stroke", 0.0, 1.0, 0.0,
       "width factor 1 - g (n - density_strokes) for a character of n strokes"),
    _F("density_strokes", "float", "strokes", 0.0, 100.0, 9.3, "stroke count whose width factor is 1"),
    _F("direction_gain", "float", "-", -0.9, 0.9, 0.0,
       "plain strokes and hooks: width factor 1 + g (2 |sin heading| - 1), verticals broader"),
    _F("end_reach_em", "float?", "em", -0.5, 0.5, None,
       "how far the footprint may reach past a median's end (null: half the stroke's width)"),
    _F("start_reach_em", "float?", "em", -0.5, 0.5, None, "the same before its start (null: as end_reach_em)"),
    _F("join_reach_em", "float?", "em", -0.5, 0.5, None,
       "the same at an end that lies on another stroke (within width_em of its centreline; null: no different)"),
    _F("taper_from", "float?", "median", 0.0, 1.0, None,
       "出锋 exits (撇, 提, 捺, hooks): from this fraction of the median on the press only eases (null: off)"),
    _F("taper_collapse", "float", "width", 0.0, 1.0, 0.5,
       "... and the travel ends once the footprint is narrower than this fraction of the width, or its area "
       "under this fraction of the last frame's (earlier, a footprint shrinking under this fraction of its last "
       "width is pressed again)"),
    _F("flick_press", "float?", "L", -0.2, 0.5, None,
       "a hook's flick 钩 (the median past its last turn of more than 57 deg) written open-loop, "
       "the press eased in a straight line from the corner's to this 0.06 em past the median's end "
       "(null: the loops write it)"),
    _F("plan_passes", "int", "passes", 0, 8, 0,
       "rehearsals of each stroke replaying a corrected plan of poses (0: the frame-by-frame loops alone)"),
    _F("plan_sigma_mm", "float", "mm", 0.0, 50.0, 3.0, "Gaussian along the stroke that low-passes the plan"),
    _F("plan_position_gain", "float", "-", 0.0, 2.0, 0.7, "fraction of the footprint's position error corrected a pass"),
    _F("plan_press_gain", "float", "L", 0.0, 1.0, 0.1, "press change a pass per unit of relative width error"),
    _F("offset_em", "pair", "em", -0.5, 0.5, (0.0, 0.0), "(x, y) added to every centreline point"),
    _F("hand", "file?", "-", None, None, None,
       "a learned hand (brushwork learn): its file, beside the style's; strokes are then written from its plans"),
    _F("profiles", "profiles", "-", None, None, None,
       "family (plain tapered flared rising dot hook) -> [[s 0..1, width factor], ...]", required=True),
)
FIELD_BY_NAME = {f.name: f for f in FIELDS}


class StyleError(ValueError):
    """A bad style file: "FILE: field = value: expected ..."."""


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _check_number(f: StyleField, v, name: str = "") -> str | None:
    """Why the number `v` does not fit field f, or None."""
    if not _is_number(v) or (f.kind == "int" and not isinstance(v, int)):
        return "an integer" if f.kind == "int" else "a number"
    if not math.isfinite(v) or v < f.lo or v > f.hi or (f.lo_open and v <= f.lo):
        return f"{f.range_text()} {f.unit}".rstrip(" -")
    return None


def _check_profiles(value) -> str | None:
    if not isinstance(value, dict):
        return "an object: family -> [[s, factor], ...]"
    missing = [n for n in PROFILE_FAMILIES if n not in value]
    extra = sorted(set(value) - set(PROFILE_FAMILIES))
    if missing or extra:
        return f"the families {', '.join(PROFILE_FAMILIES)}" + (f" (unknown: {', '.join(extra)})" if extra else "")
    for name in PROFILE_FAMILIES:
        why = _check_profile(value[name])
        if why:
            return f"{name}: {why}"
    return None


def _check_profile(rows) -> str | None:
    ok = (isinstance(rows, list) and 2 <= len(rows) <= PROFILE_POINTS
          and all(isinstance(r, list) and len(r) == 2 and all(map(_is_number, r)) for r in rows))
    if not ok:
        return f"expected 2..{PROFILE_POINTS} [s, factor] pairs of numbers"
    a = np.array(rows, dtype=float)
    if not (np.all(np.isfinite(a)) and np.all(np.diff(a[:, 0]) >= 0) and a[0, 0] >= 0 and a[-1, 0] <= 1):
        return "s must rise from 0..1"
    if a[:, 1].min() < 0 or a[:, 1].max() > 5:
        return "factors must lie in 0..5"
    return None


def _check_scene(value) -> str | None:
    from ..scene import Scene

    if not isinstance(value, dict):
        return "an object of Scene settings"
    try:
        Scene(**value)
    except (TypeError, ValueError) as err:
        return f"Scene settings ({str(err).splitlines()[0]})"
    return None


def brush_model(preset: str, changes: dict):
    """The BrushModel of `preset` with the fields of `changes` set; ValueError naming a field
    that is not one, or a value out of its range."""
    from .._core import BrushModel

    model = BrushModel.preset(preset)
    names = {p["name"] for p in model.parameters()}
    for name, value in changes.items():
        if name not in names:
            raise ValueError(f"{name}: not a BrushModel field")
        if not _is_number(value) and not isinstance(value, bool):
            raise ValueError(f"{name}: a number")
        setattr(model, name, value)
    model.validate()
    return model


def _check_brush(value) -> str | None:
    if not isinstance(value, dict):
        return "an object of BrushModel fields"
    try:
        brush_model("medium", value)
    except (TypeError, ValueError) as err:
        return f"BrushModel fields ({str(err).splitlines()[0]})"
    return None


def _check_str(f: StyleField, value) -> str | None:
    if not isinstance(value, str):
        return "a string"
    if f.name == "preset":
        from .._core import BrushModel

        if value not in BrushModel.presets():
            return f"one of {', '.join(BrushModel.presets())}"
    return None


def _check_pair(f: StyleField, value) -> str | None:
    if not isinstance(value, list) or len(value) != 2:
        return "[x, y]"
    return next((w for w in (_check_number(f, v) for v in value) if w), None)


def _check_map(f: StyleField, value) -> str | None:
    if not isinstance(value, dict) or set(value) != set(f.default):
        return "an object of " + ", ".join(f.default)
    return next((f"{k}: {w}" for k, w in ((k, _check_number(f, v)) for k, v in value.items()) if w), None)


def _check_file(f: StyleField, value) -> str | None:
    return None if isinstance(value, str) and value else "a file name or null"


def _why(f: StyleField, value) -> str | None:
    """Why `value` does not fit field f (what is expected), or None when it does."""
    if f.kind in ("float?", "file?") and value is None:
        return None
    checks = {"str": _check_str, "pair": _check_pair, "map": _check_map, "file?": _check_file,
              "scene": lambda _, v: _check_scene(v), "profiles": lambda _, v: _check_profiles(v),
              "brush": lambda _, v: _check_brush(v)}
    return checks.get(f.kind, _check_number)(f, value)


def check_style(doc, where: str, fields: tuple = FIELDS) -> dict:
    """A parsed style file -> the dataclass's keyword arguments; StyleError naming the file,
    the field and the value at the first problem."""
    if not isinstance(doc, dict):
        raise StyleError(f"{where}: expected a JSON object of style fields")
    by_name = {f.name: f for f in fields}
    unknown = sorted(set(doc) - set(by_name))
    if unknown:
        raise StyleError(f"{where}: unknown field(s) {', '.join(unknown)} (`brushwork params --style` lists them)")
    for f in fields:
        if f.name not in doc:
            if f.required:
                raise StyleError(f"{where}: missing field {f.name}")
            continue
        why = _why(f, doc[f.name])
        if why:
            raise StyleError(f"{where}: {f.name} = {json.dumps(doc[f.name])[:40]}: expected {why}")
    return {k: tuple(v) if by_name[k].kind == "pair" else v for k, v in doc.items()}


def read_style(name_or_path: str, directory: Path, fields: tuple = FIELDS) -> dict:
    """The checked fields of a style: by name (a file of `directory`) or from a JSON file
    (a name with a suffix); StyleError for a bad one."""
    path = Path(name_or_path)
    if not path.suffix:
        path = directory / f"{name_or_path}.json"
        if not path.is_file():
            known = ", ".join(sorted(p.stem for p in directory.glob("*.json")))
            raise StyleError(f"unknown style {name_or_path!r} (known: {known})")
    return check_style(_read_json(path), str(path), fields)


def style_table(fields: tuple = FIELDS) -> str:
    """The style fields as a Markdown table: field, unit, range, default, meaning."""
    rows = ["| field | unit | range | default | meaning |", "|---|---|---|---|---|"]
    for f in fields:
        default = "required" if f.required else json.dumps(list(f.default) if f.kind == "pair" else f.default,
                                                            ensure_ascii=False)
        cells = (f"`{f.name}`", f.unit, f.range_text(), default, f.doc)
        rows.append("| " + " | ".join(c.replace("|", "&#124;") for c in cells) + " |")
    return "\n".join(rows)


class _StyleMethods:
    @classmethod
    def load(cls, name_or_path: str) -> "Style":
        """A style by name (kai, xing) or from a JSON file; StyleError for a bad one."""
        return cls(**read_style(name_or_path, STYLE_DIR))

    def hand_path(self) -> Path:
        """The hand file: `hand` as given when absolute, else beside the style files."""
        path = Path(self.hand)
        return path if path.is_absolute() else STYLE_DIR / path

    def model(self):
        """The brush this style writes with: its preset's BrushModel with `brush`'s fields set."""
        return brush_model(self.preset, self.brush)

    def density(self, strokes: int) -> float:
        """Width factor of a character of `strokes` strokes (density_gain), within 0.7..1.3."""
        return float(np.clip(1.0 - self.density_gain * (strokes - self.density_strokes), 0.7, 1.3))

    @staticmethod
    def names() -> list[str]:
        return sorted(p.stem for p in STYLE_DIR.glob("*.json"))


MAX_STYLE_BYTES = 1 << 20      # a style file is a few kB; more is not one


def _read_json(path: Path):
    """The parsed JSON of a style file; StyleError with a plain sentence when it cannot be read."""
    if not path.is_file():
        raise StyleError(f"style file not found: {path}" if not path.exists() else f"{path}: not a file")
    try:
        if path.stat().st_size > MAX_STYLE_BYTES:
            raise StyleError(f"{path}: larger than {MAX_STYLE_BYTES} bytes: not a style file")
        return json.loads(path.read_text(encoding="utf-8"))
    except PermissionError:
        raise StyleError(f"cannot read the style file {path}: permission denied") from None
    except UnicodeDecodeError:
        raise StyleError(f"{path}: not UTF-8 text") from None
    except (json.JSONDecodeError, RecursionError) as err:
        raise StyleError(f"{path}: not a style file (malformed JSON: {getattr(err, 'msg', err)})") from None


def _dataclass_field(f: StyleField):
    if isinstance(f.default, (dict, list)):
        return field(default_factory=lambda d=f.default: json.loads(json.dumps(d)))
    return field(default=f.default)


_TYPES = {"file?": "str | None", "str": str, "float": float, "int": int, "float?": "float | None", "pair": tuple, "map": dict,
          "scene": dict, "profiles": dict, "brush": dict}


def style_dataclass(name: str, fields: tuple, bases: tuple) -> type:
    """The dataclass of a style table, its fields in the table's order (required ones first,
    as a dataclass needs)."""
    return make_dataclass(
        name,
        [(f.name, _TYPES[f.kind]) for f in fields if f.required]
        + [(f.name, _TYPES[f.kind], _dataclass_field(f)) for f in fields if not f.required],
        bases=bases)


Style = style_dataclass("Style", FIELDS, (_StyleMethods,))
Style.__module__ = __name__
Style.__doc__ = "How a hand writes: the fields of FIELDS (`brushwork params --style`). Loaded by Style.load."
