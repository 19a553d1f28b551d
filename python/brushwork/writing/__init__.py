"""Writing glyphs with the brush: the style (style.py), what a stroke aims at (targets.py) and
the driver that closes the loops on the footprint (driver.py)."""
from .driver import Writer, check_samples, check_size, render_glyph, writing_paper
from .style import FAMILIES, FIELDS, Style, StyleError, family, style_table

__all__ = ["FAMILIES", "FIELDS", "Style", "StyleError", "Writer", "check_samples", "check_size", "family",
           "render_glyph", "style_table", "writing_paper"]
