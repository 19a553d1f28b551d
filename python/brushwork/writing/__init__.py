"""Writing glyphs with the brush: the style (style.py), what a stroke aims at (targets.py), the
driver that closes the loops on the footprint (driver.py) and a line of glyphs on a paper
(layout.py)."""
from .driver import Writer
from .layout import (MAX_SIDE, check_samples, check_seed, check_size, render_glyph, text_paper, writing_paper,
                     writing_stats)
from .style import FAMILIES, FIELDS, Style, StyleError, family, style_table

__all__ = ["FAMILIES", "FIELDS", "MAX_SIDE", "Style", "StyleError", "Writer", "check_samples", "check_seed",
           "check_size", "family", "render_glyph", "style_table", "text_paper", "writing_paper", "writing_stats"]
