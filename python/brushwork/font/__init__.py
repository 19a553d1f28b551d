"""Fonts from the brush: every character written by the brush, its ink traced and fitted with
curves, built into an OpenType (CFF), TrueType, WOFF2 or UFO font (`brushwork font`)."""
from .build import FORMATS, FontInfo, make_font, write_font
from .make import FontResult, build_font
from .outline import ASCENDER, DESCENDER, UPM, Em, outline_from_image, render_outline

__all__ = ["ASCENDER", "DESCENDER", "FORMATS", "UPM", "Em", "FontInfo", "FontResult", "build_font", "make_font",
           "outline_from_image", "render_outline", "write_font"]
