"""Glyphs: characters as strokes in writing order, from our JSON format, KanjiVG or Make Me a Hanzi.

Stroke centrelines are in em units: the source's em box mapped to [0, 1] x [0, 1], x right, y up.
"""
from .jsonfmt import load_glyph, save_glyph
from .model import STROKE_TYPES, Glyph, GlyphError, Stroke
from .sources import load_source
from .strokes import infer_stroke_type, normalise_kind
from .svgpath import parse_svg_path

__all__ = ["Glyph", "GlyphError", "STROKE_TYPES", "Stroke", "infer_stroke_type", "load_glyph", "load_source",
           "normalise_kind", "parse_svg_path", "save_glyph"]
