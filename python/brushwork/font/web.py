"""A font for the web: the font cut into unicode-range slices, each a WOFF2 of SLICE_CHARS
characters in the order the charset lists them (GB2312's 3,755 common characters of level 1
before the 3,008 rarer ones of level 2), a CSS file of @font-face rules, one per slice with its
`unicode-range`, and a page that sets a paragraph in the font. A browser fetches only the slices
whose ranges hold the characters of its text."""
from __future__ import annotations

import html
import io
import os
from dataclasses import dataclass, field
from pathlib import Path

from ..files import write_atomic

SLICE_CHARS = 64        # characters a slice: GB2312's 6,763 in 106 slices
DEMO_PX = 48            # the demo page's font size
MARGIN_PX = 16           # white around the line on the page and in the screenshot
DEMO_CHARS = 40         # characters of the demo paragraph (the first of the font's)


@dataclass
class WebFont:
    folder: str
    css: str                                        # the CSS file's path
    page: str                                       # the demo page's path
    slices: list = field(default_factory=list)      # (WOFF2 path, its characters) in order


def check_slice_chars(n: int) -> int:
    if int(n) < 1:
        raise ValueError(f"--slice-chars {n}: expected >= 1")
    return int(n)


def cut(chars: str, per: int) -> list:
    """chars in runs of `per`, in order: the characters of each slice."""
    return [chars[i:i + per] for i in range(0, len(chars), per)]


def unicode_range(chars: str) -> str:
    """The CSS unicode-range of chars: code points sorted, consecutive runs joined (U+4E00-4E02)."""
    cps = sorted({ord(c) for c in chars})
    runs: list = []
    for cp in cps:
        if runs and cp == runs[-1][1] + 1:
            runs[-1][1] = cp
        else:
            runs.append([cp, cp])
    return ", ".join(f"U+{a:X}" if a == b else f"U+{a:X}-{b:X}" for a, b in runs)


def _subset(data: bytes, chars: str):
    """The font in data cut down to chars (and .notdef), every table the subsetter keeps kept
    whole (BASE, vhea, vmtx, VORG, meta among them), as a WOFF2 TTFont."""
    from fontTools import subset
    from fontTools.ttLib import TTFont

    opts = subset.Options()
    opts.flavor = "woff2"
    opts.name_IDs, opts.name_languages, opts.layout_features = ["*"], ["*"], ["*"]
    opts.notdef_outline, opts.glyph_names = True, False
    opts.no_subset_tables += ["meta"]        # the script tags hold for every slice
    font = TTFont(io.BytesIO(data))
    sub = subset.Subsetter(opts)
    sub.populate(unicodes=[ord(c) for c in chars])
    sub.subset(font)
    font.flavor = "woff2"
    return font


def _css(family: str, slices: list) -> str:
    rules = [f"@font-face {{\n  font-family: \"{family}\";\n  src: url(\"{os.path.basename(path)}\") "
             f"format(\"woff2\");\n  font-display: swap;\n  unicode-range: {unicode_range(chars)};\n}}"
             for path, chars in slices]
    return "\n".join(rules) + "\n"


def page_html(family: str, css_name: str, text: str, px: int = DEMO_PX) -> str:
    """A page that loads css_name and sets text in family, px to the em, one line MARGIN_PX from
    the top-left corner (as browser.chromium_line sets it)."""
    return ("<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>" + html.escape(family) + "</title>\n"
            f"<link rel=\"stylesheet\" href=\"{css_name}\">\n<style>html,body{{margin:0;background:#fff}}\n"
            f"p{{font-family:\"{family}\";font-size:{px}px;line-height:{px}px;color:#000;white-space:nowrap;"
            f"margin:0;position:absolute;left:{MARGIN_PX}px;top:{MARGIN_PX}px}}</style></head>\n"
            f"<body><p id=\"text\">{html.escape(text)}</p></body></html>\n")


def write_web(font, chars: str, folder: str | os.PathLike, family: str, stem: str,
              per: int = SLICE_CHARS, first: str = "") -> WebFont:
    """The TTFont `font` (of the characters chars, in their order) as slices of `per` characters
    in folder after a slice of the characters `first` (the blanks, which a browser fetches for any
    text of the font: the line's metrics come from the first face that maps U+0020, CSS Fonts 4
    "first available font"): STEM.NNN.woff2, STEM.css
    (their @font-face rules, family `family`) and index.html (a paragraph of the first DEMO_CHARS
    characters set in it). Each file written atomically."""
    folder = os.fspath(folder)
    os.makedirs(folder, exist_ok=True)
    buf = io.BytesIO()
    font.save(buf)
    data = buf.getvalue()
    out = WebFont(folder, os.path.join(folder, f"{stem}.css"), os.path.join(folder, "index.html"))
    mapped = set(font.getBestCmap())
    chars = "".join(c for c in dict.fromkeys(chars) if ord(c) in mapped)
    blanks = "".join(c for c in first if ord(c) in mapped)
    parts = ([blanks] if blanks else []) + cut(chars, check_slice_chars(per))
    for k, part in enumerate(parts):
        path = os.path.join(folder, f"{stem}.{k:03d}.woff2")
        write_atomic(path, _subset(data, part).save, suffix=".woff2")
        out.slices.append((path, part))
    css = _css(family, out.slices)
    write_atomic(out.css, lambda tmp: Path(tmp).write_text(css, encoding="utf-8"), suffix=".css")
    doc = page_html(family, os.path.basename(out.css), chars[:DEMO_CHARS])
    write_atomic(out.page, lambda tmp: Path(tmp).write_text(doc, encoding="utf-8"), suffix=".html")
    return out
