"""KanjiVG: one SVG file per character (<5-hex-digit code>[-Variant].svg), a stroke a <path> whose `d`
is the centreline (cubic Beziers) in a 109-unit box, y down, with its type in `kvg:type`.

The `kanjivg` package on PyPI ships only the data: the SVG files in a top-level `kanji/` folder
of site-packages, no Python API. KanjiVG is CC BY-SA 3.0 (Ulrich Apel, https://kanjivg.tagaini.net).
"""
from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from ..extras import install_hint
from .model import Glyph, GlyphError, Stroke
from .strokes import infer_stroke_type, normalise_kind
from .svgpath import parse_svg_path

EM_BOX = (0.0, 0.0, 109.0, 109.0)


def package_dir() -> Path:
    """The `kanji/` folder of the installed kanjivg package; GlyphError saying how to get it if absent."""
    from importlib import metadata
    try:
        folder = Path(metadata.distribution("kanjivg").locate_file("kanji"))
    except metadata.PackageNotFoundError:
        folder = None
    if folder is None or not folder.is_dir():
        raise GlyphError("kanjivg", f"the kanjivg package is not installed ({install_hint('kanjivg')}), "
                                    "or pass kanjivg:DIR with a folder of KanjiVG SVG files")
    return folder


def file_for(folder: Path, char: str, variant: str | None) -> Path | None:
    """The SVG for char in folder: the variant (e.g. "Kaisho") when it exists, else the plain file."""
    stem = f"{ord(char):05x}"
    for name in ([f"{stem}-{variant}.svg"] if variant else []) + [f"{stem}.svg"]:
        if (folder / name).is_file():
            return folder / name
    return None


def _attr(elem, local: str) -> str | None:
    """An attribute by local name in any namespace (KanjiVG's kvg: URI differs between files)."""
    for key, val in elem.attrib.items():
        if key == local or key.endswith("}" + local) or key == "kvg:" + local:
            return val
    return None


def read_svg(path: Path, source: str = "kanjivg") -> Glyph:
    """A KanjiVG SVG file -> Glyph (strokes in document order, types from kvg:type or inferred)."""
    path = Path(path)
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as e:
        raise GlyphError(path, f"malformed SVG: {e}") from None
    except OSError as e:
        raise GlyphError(path, f"cannot read: {e}") from None
    try:
        char = chr(int(path.stem.split("-")[0], 16))
    except (ValueError, OverflowError):
        raise GlyphError(path, "file name is not a KanjiVG code (like 06c38.svg or 06c38-Kaisho.svg)") from None
    frame = Glyph(char, ord(char), [], f"{source}:{path}", EM_BOX, True)
    paths = [e for e in root.iter() if e.tag.rsplit("}", 1)[-1] == "path"]
    if not paths:
        raise GlyphError(path, "no strokes (no <path> elements)")
    for i, elem in enumerate(paths):
        name = f"stroke {i + 1} ({elem.get('id')})" if elem.get("id") else f"stroke {i + 1}"
        try:
            polylines = parse_svg_path(elem.get("d", ""))
        except GlyphError as e:
            raise GlyphError(path, f"{name}: {e}") from None
        if len(polylines) != 1:
            raise GlyphError(path, f"{name}: {len(polylines)} subpaths, expected one centreline")
        try:
            pts = frame.to_em(polylines[0])
            kind = normalise_kind(_attr(elem, "type")) or infer_stroke_type(pts)
            frame.strokes.append(Stroke(pts, kind))
        except GlyphError as e:
            raise GlyphError(path, f"{name}: {e.problem}") from None
    return frame
