"""Make Me a Hanzi: graphics.txt (one JSON object a line) or hanzi-writer-data (<char>.json files).

Medians are stroke centrelines in a 1024-unit box, y up, its top edge at y = 900: the em box is
(0, -124, 1024, 900). The filled outlines are kept on each Stroke (source units) for scoring.
"""
from __future__ import annotations

import json
from pathlib import Path
from typing import Iterator

from .model import Glyph, GlyphError, Stroke, check_points
from .strokes import infer_stroke_type
from .svgpath import parse_svg_path

EM_BOX = (0.0, -124.0, 1024.0, 900.0)


def glyph_from_mmah(doc, char: str | None, where: str, outlines: bool = True) -> Glyph:
    """One character's {"strokes": [outline d, ...], "medians": [[[x, y], ...], ...]} -> Glyph.
    char: the character (None: doc["character"]); where: the file (and line) named in errors;
    outlines: False for medians alone (no "strokes"; the glyph's strokes then carry no outline)."""
    char, medians, shapes = _fields(doc, char, where, outlines)
    frame = Glyph(char, ord(char), [], "", EM_BOX, False)
    strokes = []
    for i, (outline, median) in enumerate(zip(shapes, medians)):
        pts = frame.to_em(check_points(where, f"medians[{i}]", median))
        if outline is not None:
            try:
                parse_svg_path(outline)
            except GlyphError as e:
                raise GlyphError(where, f"strokes[{i}]: {e}") from None
        strokes.append(Stroke(pts, infer_stroke_type(pts), outline=outline))
    frame.strokes = strokes
    return frame


def _fields(doc, char: str | None, where: str, outlines: bool) -> tuple[str, list, list]:
    """(character, medians, outlines: one SVG path or None a stroke) of a checked document."""
    if not isinstance(doc, dict):
        raise GlyphError(where, f"expected a JSON object, got {type(doc).__name__}")
    char = doc.get("character") if char is None else char
    if not isinstance(char, str) or len(char) != 1:
        raise GlyphError(where, f"character: expected one character, got {char!r:.20}")
    medians = doc.get("medians")
    shapes = doc.get("strokes") if outlines else [None] * (len(medians) if isinstance(medians, list) else 0)
    for key, val in (("strokes", shapes), ("medians", medians)):
        if not isinstance(val, list):
            raise GlyphError(where, f"{key}: missing or not a list")
    if not medians:
        raise GlyphError(where, "no strokes")
    if len(shapes) != len(medians):
        raise GlyphError(where, f"{len(shapes)} outlines (strokes) but {len(medians)} medians")
    return char, medians, shapes


def read_graphics(path: Path, wanted: set[str] | None) -> Iterator[tuple[str | None, Glyph | GlyphError]]:
    """(char, Glyph or the GlyphError of a bad line) for the lines of a graphics.txt file."""
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise GlyphError(path, f"cannot read: {e}") from None
    if '"character"' not in text:
        raise GlyphError(path, 'not a Make Me a Hanzi graphics.txt: no line holds {"character": C, "strokes": '
                               '[...], "medians": [...]}')
    for n, line in enumerate(text.splitlines(), 1):
        if not line.strip() or (wanted is not None and not any(c in line for c in wanted)):
            continue
        where = f"{path}: line {n}"
        try:
            doc = json.loads(line)
        except json.JSONDecodeError as e:
            yield None, GlyphError(where, f"malformed JSON: {e.msg} at column {e.colno}")
            continue
        except RecursionError:
            yield None, GlyphError(where, "malformed JSON: nested too deeply")
            continue
        char = doc.get("character") if isinstance(doc, dict) else None
        if wanted is not None and char not in wanted:
            continue
        try:
            glyph = glyph_from_mmah(doc, None, where)
            glyph.source = f"mmah:{path}"
            yield glyph.char, glyph
        except GlyphError as e:
            yield char, e


def read_char_file(path: Path, char: str) -> Glyph:
    """A hanzi-writer-data file <char>.json -> Glyph."""
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError) as e:
        raise GlyphError(path, f"cannot read: {e}") from None
    except json.JSONDecodeError as e:
        raise GlyphError(path, f"malformed JSON: {e.msg} at line {e.lineno} column {e.colno}") from None
    except RecursionError:
        raise GlyphError(path, "malformed JSON: nested too deeply") from None
    glyph = glyph_from_mmah(doc, char, str(path))
    glyph.source = f"mmah:{path}"
    return glyph
