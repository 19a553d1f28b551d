"""brushwork's own glyph format: one JSON document per character (glyphs/README.md, glyphs/schema.json).

Files are checked by hand here, with messages like "FILE: strokes[3].points[2]: NaN", and also
against the JSON Schema when the optional `jsonschema` package is installed.
"""
from __future__ import annotations

import json
import os
import tempfile
from functools import lru_cache
from pathlib import Path

import numpy as np

from .model import (EM_REACH, MAX_COORD, MAX_POINTS, MAX_STROKE_EM, MAX_STROKES, STROKE_TYPES, Glyph, GlyphError,
                    Stroke, check_number, check_points)
from .strokes import infer_stroke_type
from .svgpath import MAX_CHARS, MAX_FLAT_POINTS, parse_svg_path

FORMAT, VERSION = "brushwork-glyph", 1
_TOP_KEYS = {"format", "version", "char", "codepoint", "em_box", "y_down", "source", "strokes"}
_STROKE_KEYS = {"kind", "points", "d", "pressure", "tilt_deg", "speed", "outline"}
_PER_POINT = ("pressure", "tilt_deg", "speed")
MAX_FILE_BYTES = 32 << 20     # a glyph file at its limits (MAX_STROKES x MAX_POINTS) is under 32 MiB


def limits_text() -> str:
    """The limits a glyph file is checked against as it is read, in words (the README quotes them)."""
    return (f"{MAX_FILE_BYTES >> 20} MiB a file, {MAX_STROKES} strokes, {MAX_POINTS:,} points a stroke, "
            f"{MAX_CHARS:,} characters of path data ({MAX_FLAT_POINTS:,} points flattened), finite "
            f"coordinates within ±{MAX_COORD:,.0f}, a centreline within {EM_REACH:g} em of the em box "
            f"and at most {MAX_STROKE_EM:g} em long")


@lru_cache(maxsize=1)
def schema() -> dict:
    """The JSON Schema (draft 2020-12) of the format, as shipped in the package."""
    return json.loads((Path(__file__).with_name("schema.json")).read_text(encoding="utf-8"))


def _is_num(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _numbers(where: str, name: str, value, k: int) -> np.ndarray:
    if not isinstance(value, list) or len(value) != k:
        raise GlyphError(where, f"{name}: expected a list of {k} numbers (one per point)")
    for i, v in enumerate(value):
        check_number(where, f"{name}[{i}]", v)
    return np.array(value, dtype=np.float64)


def _svg_centreline(where: str, at: str, s: dict) -> np.ndarray:
    """The centreline of a stroke given as SVG path data `d` (one subpath), in file units."""
    for name in _PER_POINT:
        if name in s:
            raise GlyphError(where, f"{at}.{name}: only allowed with 'points', not 'd'")
    polylines = _svg(where, f"{at}.d", s["d"])
    if len(polylines) != 1:
        raise GlyphError(where, f"{at}.d: {len(polylines)} subpaths, expected one centreline")
    return check_points(where, f"{at}.d", polylines[0].tolist())


def _svg(where: str, at: str, d) -> list:
    try:
        return parse_svg_path(d)
    except GlyphError as e:
        raise GlyphError(where, f"{at}: {e}") from None


def _per_point(where: str, at: str, s: dict, k: int) -> dict:
    """The stroke's per-point arrays (pressure, tilt_deg, speed), each (k,), checked."""
    extras = {name: _numbers(where, f"{at}.{name}", s[name], k) for name in _PER_POINT if name in s}
    if "pressure" in extras and not np.all((extras["pressure"] >= 0) & (extras["pressure"] <= 1)):
        raise GlyphError(where, f"{at}.pressure: values must lie in [0, 1]")
    if "speed" in extras and np.any(extras["speed"] < 0):
        raise GlyphError(where, f"{at}.speed: values must not be negative")
    return extras


def _stroke_kind(where: str, at: str, s: dict, pts: np.ndarray) -> str:
    kind = s.get("kind")
    if kind is None:
        return infer_stroke_type(pts)
    if not isinstance(kind, str) or kind not in STROKE_TYPES:
        raise GlyphError(where, f"{at}.kind: {kind!r:.20} is not a CJK stroke (U+31C0..U+31E3)")
    return kind


def _stroke(where: str, i: int, s, glyph: Glyph) -> Stroke:
    at = f"strokes[{i}]"
    if not isinstance(s, dict):
        raise GlyphError(where, f"{at}: expected an object")
    extra = sorted(set(s) - _STROKE_KEYS)
    if extra:
        raise GlyphError(where, f"{at}: unknown field {extra[0]!r}")
    if ("points" in s) == ("d" in s):
        raise GlyphError(where, f"{at}: needs exactly one of 'points' or 'd'")
    src = _svg_centreline(where, at, s) if "d" in s else check_points(where, f"{at}.points", s["points"])
    extras = _per_point(where, at, s, len(src))
    outline = s.get("outline")
    if outline is not None:
        _svg(where, f"{at}.outline", outline)
    pts = glyph.to_em(src)
    try:
        return Stroke(pts, _stroke_kind(where, at, s, pts), outline=outline, **extras)
    except GlyphError as e:                 # a limit of the stroke in em units: name the file and stroke
        raise GlyphError(where, f"{at}.{e.problem}") from None


def _check_head(doc: dict, where: str) -> None:
    """The fields above the strokes: format, version, char and codepoint."""
    missing = [k for k in ("format", "version", "char", "codepoint", "em_box", "y_down", "strokes") if k not in doc]
    if missing:
        raise GlyphError(where, f"missing field {missing[0]!r}")
    extra = sorted(set(doc) - _TOP_KEYS)
    if extra:
        raise GlyphError(where, f"unknown field {extra[0]!r}")
    if doc["format"] != FORMAT:
        raise GlyphError(where, f"format: expected {FORMAT!r}, got {doc['format']!r:.40}")
    if doc["version"] != VERSION or isinstance(doc["version"], bool):
        raise GlyphError(where, f"version: this brushwork reads version {VERSION}, got {doc['version']!r:.20}")
    char, cp = doc["char"], doc["codepoint"]
    if not isinstance(char, str) or len(char) != 1:
        raise GlyphError(where, f"char: expected one character, got {char!r:.20}")
    if not _is_num(cp) or cp != ord(char):
        raise GlyphError(where, f"codepoint: {cp!r:.20} is not ord({char!r}) = {ord(char)}")


def _check_frame(doc: dict, where: str) -> np.ndarray:
    """em_box (4,) in file units, y_down, source and the strokes list's length."""
    box = doc["em_box"]
    if not isinstance(box, list) or len(box) != 4:
        raise GlyphError(where, "em_box: expected [x0, y0, x1, y1]")
    box = _numbers(where, "em_box", box, 4)
    if not (box[2] > box[0] and box[3] > box[1]):
        raise GlyphError(where, "em_box: needs x1 > x0 and y1 > y0")
    if not isinstance(doc["y_down"], bool):
        raise GlyphError(where, "y_down: expected true or false")
    if "source" in doc and not isinstance(doc["source"], str):
        raise GlyphError(where, "source: expected a string")
    strokes = doc["strokes"]
    if not isinstance(strokes, list) or not strokes:
        raise GlyphError(where, "strokes: expected a non-empty list")
    if len(strokes) > MAX_STROKES:
        raise GlyphError(where, f"strokes: {len(strokes)} strokes, more than {MAX_STROKES}")
    return box


def glyph_from_dict(doc, where: str) -> Glyph:
    """A parsed JSON document -> Glyph; GlyphError(where, problem) at the first problem."""
    if not isinstance(doc, dict):
        raise GlyphError(where, f"expected a JSON object, got {type(doc).__name__}")
    _check_head(doc, where)
    box = _check_frame(doc, where)
    glyph = Glyph(doc["char"], int(doc["codepoint"]), [], f"glyphs:{where}", tuple(box), doc["y_down"],
                  {"source": doc["source"]} if "source" in doc else {})
    glyph.strokes = [_stroke(where, i, s, glyph) for i, s in enumerate(doc["strokes"])]
    _check_schema(doc, where)
    return glyph


def _check_schema(doc: dict, where: str) -> None:
    """The schema's verdict too, when jsonschema is installed (the checks above should agree)."""
    try:
        import jsonschema
    except ImportError:
        return
    err = jsonschema.exceptions.best_match(jsonschema.Draft202012Validator(schema()).iter_errors(doc))
    if err is not None:
        loc = "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in err.absolute_path).lstrip(".")
        raise GlyphError(where, f"{loc or 'document'}: {err.message} (schema)")


def load_glyph(path) -> Glyph:
    """Read one glyph file of our format; GlyphError "PATH: problem" for anything wrong in it."""
    path = Path(path)
    try:
        if path.stat().st_size > MAX_FILE_BYTES:
            raise GlyphError(path, f"larger than {MAX_FILE_BYTES} bytes: not a glyph file")
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise GlyphError(path, "cannot read: not UTF-8 text") from None
    except OSError as e:
        raise GlyphError(path, f"cannot read: {(e.strerror or type(e).__name__).lower()}") from None
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as e:
        raise GlyphError(path, f"malformed JSON: {e.msg} at line {e.lineno} column {e.colno}") from None
    except RecursionError:
        raise GlyphError(path, "malformed JSON: nested too deeply") from None
    return glyph_from_dict(doc, str(path))


def _num(v: float):
    """A coordinate for the file: 6 decimals, integers written as integers."""
    r = round(float(v), 6) + 0.0
    return int(r) if r.is_integer() else r


def glyph_to_dict(glyph: Glyph) -> dict:
    """Glyph -> a document of our format, points in the glyph's own source units and em box."""
    strokes = []
    for s in glyph.strokes:
        d = {"kind": s.kind, "points": [[_num(x), _num(y)] for x, y in glyph.from_em(s.points)]}
        for name in _PER_POINT:
            if getattr(s, name) is not None:
                d[name] = [_num(v) for v in getattr(s, name)]
        if s.outline is not None:
            d["outline"] = s.outline
        strokes.append(d)
    doc = {"format": FORMAT, "version": VERSION, "char": glyph.char, "codepoint": glyph.codepoint,
           "em_box": [_num(v) for v in glyph.em_box], "y_down": bool(glyph.source_y_down)}
    if glyph.metadata.get("source"):
        doc["source"] = str(glyph.metadata["source"])
    doc["strokes"] = strokes
    return doc


def dumps(doc: dict) -> str:
    """A document as JSON text: one line per field and per stroke."""
    dump = lambda v: json.dumps(v, ensure_ascii=False, allow_nan=False)  # noqa: E731
    head = [f"  {dump(k)}: {dump(v)}" for k, v in doc.items() if k != "strokes"]
    strokes = ",\n".join(f"    {dump(s)}" for s in doc["strokes"])
    return "{\n" + ",\n".join(head + [f'  "strokes": [\n{strokes}\n  ]']) + "\n}\n"


def save_glyph(glyph: Glyph, path) -> None:
    """Write glyph to path in our format, atomically (a temporary file, then os.replace)."""
    path = Path(path)
    text = dumps(glyph_to_dict(glyph))
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise
