"""Fonts from outlines: OpenType with CFF (.otf) or TrueType glyf (.ttf) outlines, WOFF2 (.woff2,
the CFF font compressed with Brotli) through fontTools' FontBuilder, and UFO (.ufo) through
ufoLib2. Every glyph's contours are unioned by skia-pathops (overlaps removed, winding made
consistent) and tidied (tidy.py: the curves skia cut joined again, extremes on-curve, no degenerate
segment), wound counter-clockwise for CFF and UFO and clockwise for glyf, whose quadratics
cu2qu makes from the cubics within QUAD_ERR font units. An OTF's CFF is subroutinised (cffsubr)."""
from __future__ import annotations

import os
import shutil
import tempfile
from dataclasses import dataclass

import numpy as np

from ..files import check_writable, os_error_text, write_atomic
from .outline import ASCENDER, DESCENDER, UPM
from .tidy import tidy

FORMATS = (".otf", ".ttf", ".woff2", ".ufo")
QUAD_ERR = 1.0            # font units: the farthest a glyf quadratic strays from its cubic
SIMPLIFY_AREA_TOL = 0.002  # the most skia's union may change a glyph's ink area by, as a fraction of it
NOTDEF_MARGIN = 0.1       # of the em: the .notdef box's inset
# the blank glyphs every font carries: char -> (glyph name, advance in ems)
SPACES = {" ": ("space", 0.25), "\u00a0": ("uni00A0", 0.25), "\u3000": ("uni3000", 1.0)}
# OS/2 ulCodePageRange1 bits of the CJK code pages, by the Python codec of each
CODEPAGE_BITS = {"cp932": 17, "gb2312": 18, "cp949": 19, "big5": 20}
# the meta table's script of each, first match wins
META_SCRIPTS = {"gb2312": "Hans", "big5": "Hant", "cp932": "Jpan", "cp949": "Kore"}
LINE_PAD = 0.1            # em: the line's room above the em box's top and below its bottom (hhea, win)


@dataclass
class FontInfo:
    family: str = "Brushwork"
    style: str = "Regular"
    version: str = "1.0"
    licence: str = ("Outlines written by brushwork's simulated brush from stroke centrelines; the "
                    "licence of the stroke data applies (bundled data: Arphic Public License).")
    licence_url: str = ""        # name ID 14, omitted when empty
    copyright: str = ""          # name ID 0, omitted when empty
    vendor_url: str = ""         # name ID 11, omitted when empty
    upm: int = UPM
    ascender: int = ASCENDER
    descender: int = DESCENDER

    def check(self) -> "FontInfo":
        """This info when it can name a font; ValueError in one line otherwise."""
        parts = self.version.split(".")
        # head.fontRevision is a signed 16.16 fixed-point number
        if len(parts) != 2 or not all(p.isdigit() for p in parts) or int(parts[0]) > 32767:
            raise ValueError(f"--version {self.version!r}: expected MAJOR.MINOR, e.g. 1.0")
        if not self.family.strip() or len(self.family) > 63 or not self.family.isprintable():
            raise ValueError(f"--family {self.family!r}: expected 1..63 printable characters")
        for option, url in (("--licence-url", self.licence_url), ("--vendor-url", self.vendor_url)):
            if url and (not url.startswith(("http://", "https://")) or not url.isprintable() or " " in url):
                raise ValueError(f"{option} {url!r}: expected an http:// or https:// URL")
        return self

    @property
    def ps_name(self) -> str:
        keep = "".join(c for c in f"{self.family}-{self.style}" if c.isascii() and c.isalnum() or c == "-")
        return keep[:63] or "Brushwork-Regular"


def check_font_path(path: str | os.PathLike) -> str:
    """The format suffix of `path` when brushwork writes it and its folder is writable."""
    suffix = os.path.splitext(os.fspath(path))[1].lower()
    if suffix not in FORMATS:
        raise ValueError(f"{os.fspath(path)}: cannot write a {suffix or 'suffix-less'} font; "
                         f"name one of {' '.join(FORMATS)}")
    if suffix == ".ufo":
        folder = os.path.dirname(os.path.abspath(os.fspath(path)))
        if not os.path.isdir(folder) or not os.access(folder, os.W_OK):
            raise PermissionError(f"cannot write {os.fspath(path)}: folder {folder} is missing or not writable")
    else:
        check_writable(path)
    return suffix


def glyph_name(char: str) -> str:
    """The AGL name of char: uniXXXX, or uXXXXX beyond the BMP."""
    cp = ord(char)
    return f"uni{cp:04X}" if cp <= 0xFFFF else f"u{cp:05X}"


def _draw_contours(contours: list, pen) -> None:
    """Each contour (m, 4, 2) of cubics onto a segment pen."""
    for c in contours:
        if len(c) == 0:
            continue
        pen.moveTo(tuple(c[0, 0]))
        for cubic in c:
            pen.curveTo(tuple(cubic[1]), tuple(cubic[2]), tuple(cubic[3]))
        pen.closePath()


def _area(path) -> float:
    """The signed area a pen-drawable path encloses (positive counter-clockwise, y up)."""
    from fontTools.pens.areaPen import AreaPen

    pen = AreaPen()
    path.draw(pen)
    return pen.value


def _simplified(contours: list):
    """The contours through skia-pathops' simplify (overlaps removed, winding fixed), or, where
    skia gives up on one or returns other ink (it can, on near-degenerate curves), on the
    contours with their points rounded to whole units, or else the contours as traced: the edges
    of one ink mask, apart by construction and wound outer one way, holes the other."""
    import pathops

    traced = pathops.Path()
    _draw_contours(contours, traced.getPen())
    ink = abs(_area(traced))
    for rounding in (None, 0):
        path = pathops.Path()
        _draw_contours(contours if rounding is None else [np.round(c, rounding) for c in contours],
                       path.getPen())
        try:
            path = pathops.simplify(path, fix_winding=True, keep_starting_points=True)
        except pathops.PathOpsError:
            continue
        if abs(abs(_area(path)) - ink) <= SIMPLIFY_AREA_TOL * max(ink, 1.0):
            return path
    return traced


def clean_outline(contours: list):
    """The contours unioned by skia-pathops: a RecordingPen of non-overlapping contours wound
    counter-clockwise around ink (y up), clockwise around holes."""
    from fontTools.pens.areaPen import AreaPen
    from fontTools.pens.recordingPen import RecordingPen
    from fontTools.pens.reverseContourPen import ReverseContourPen

    rec = RecordingPen()
    _simplified(contours).draw(rec)
    rec = tidy(rec)
    area = AreaPen()
    rec.replay(area)
    if area.value < 0:          # skia winds outer contours clockwise: turn them the PostScript way
        turned = RecordingPen()
        rec.replay(ReverseContourPen(turned))
        rec = turned
    return rec


def notdef(upm: int, ascender: int, descender: int):
    """The .notdef glyph: a box with a box-shaped hole, counter-clockwise outside (a RecordingPen)."""
    from fontTools.pens.recordingPen import RecordingPen

    m, w = int(upm * NOTDEF_MARGIN), int(upm * NOTDEF_MARGIN / 2)
    x0, x1, y0, y1 = m, upm - m, descender + m, ascender - m
    rec = RecordingPen()
    for (a, b, c, d), ccw in (((x0, y0, x1, y1), True), ((x0 + w, y0 + w, x1 - w, y1 - w), False)):
        pts = [(a, b), (c, b), (c, d), (a, d)]
        pts = pts if ccw else pts[::-1]
        rec.moveTo(pts[0])
        for p in pts[1:]:
            rec.lineTo(p)
        rec.closePath()
    return rec


def _bounds(rec) -> tuple:
    """(xMin, yMin, xMax, yMax) of a RecordingPen's outline, zeros when it is empty."""
    from fontTools.pens.boundsPen import BoundsPen

    pen = BoundsPen(None)
    rec.replay(pen)
    return pen.bounds or (0, 0, 0, 0)


def _charstring(rec, width: int, specialize: bool = True):
    """The Type 2 charstring of a RecordingPen's outline; unspecialized, every curve stays an
    rrcurveto (a curve whose handles round onto its ends would otherwise be written as a line, and
    a variable font's masters would no longer match point for point)."""
    from fontTools.pens.t2CharStringPen import T2CharStringPen

    pen = T2CharStringPen(width, None)
    rec.replay(pen)
    return pen.getCharString(optimize=specialize)


def _grid_pen(out):
    """A pen that passes its segments on to `out` with their points rounded to whole font units,
    leaving out any that the rounding collapses onto the point it starts from (glyf stores
    integers: a short quadratic or line cu2qu made would otherwise repeat a point)."""
    from fontTools.misc.roundTools import otRound
    from fontTools.pens.filterPen import FilterPen

    class GridPen(FilterPen):
        here = None

        def _kept(self, pts):
            pts = [(otRound(x), otRound(y)) for x, y in pts]
            if all(p == self.here for p in pts):
                return None
            self.here = pts[-1]
            return pts

        def moveTo(self, pt):
            self.here = (otRound(pt[0]), otRound(pt[1]))
            super().moveTo(self.here)

        def lineTo(self, pt):
            pts = self._kept([pt])
            if pts:
                super().lineTo(pts[0])

        def qCurveTo(self, *points):
            pts = self._kept(points)
            if pts:
                super().qCurveTo(*pts)

    return GridPen(out)


def _tt_glyph(rec):
    from fontTools.pens.cu2quPen import Cu2QuPen
    from fontTools.pens.ttGlyphPen import TTGlyphPen

    pen = TTGlyphPen(None)
    # cu2qu turns the PostScript winding into TrueType's (clockwise outer contours) as it goes
    rec.replay(Cu2QuPen(_grid_pen(pen), QUAD_ERR, reverse_direction=True))
    return pen.glyph()


def _glyf_bounds(glyf, name: str) -> tuple:
    g = glyf[name]
    g.recalcBounds(glyf)
    return (g.xMin, g.yMin, g.xMax, g.yMax) if g.numberOfContours else (0, 0, 0, 0)


def _timestamp() -> int:
    """head's created and modified: SOURCE_DATE_EPOCH when set (reproducible builds), else now."""
    from fontTools.misc.timeTools import epoch_diff, timestampNow

    epoch = os.environ.get("SOURCE_DATE_EPOCH", "")
    return int(epoch) - epoch_diff if epoch.isdigit() else timestampNow()


def _names(info: FontInfo) -> dict:
    """The name table's strings: the empty optional ones (copyright, URLs) left out."""
    names = {"copyright": info.copyright, "familyName": info.family, "styleName": info.style,
             "uniqueFontIdentifier": f"{info.version};BRSH;{info.ps_name}", "fullName": f"{info.family} {info.style}",
             "version": f"Version {info.version}", "psName": info.ps_name, "vendorURL": info.vendor_url,
             "licenseDescription": info.licence, "licenseInfoURL": info.licence_url}
    return {k: v for k, v in names.items() if v}


def line_metrics(info: FontInfo, bounds: list) -> tuple:
    """(ascent, descent >= 0) font units of hhea and OS/2's win metrics, as Google Fonts' CJK
    vertical metrics have them: the em box (the typo ascender and descender) with LINE_PAD em
    above and below, a line 1 + 2 LINE_PAD em high (1.1..1.5 em) that keeps the em box at its
    middle, widened where a glyph (bounds (xMin, yMin, xMax, yMax)) reaches past it."""
    pad = LINE_PAD * info.upm
    top = max([info.ascender + pad] + [b[3] for b in bounds])
    bottom = min([info.descender - pad] + [b[1] for b in bounds])
    return int(np.ceil(top)), int(np.ceil(-bottom))


def _os2(fb, info: FontInfo, bounds: list, chars: str) -> None:
    """OS/2 version 4: typo metrics of the em box with no line gap, win metrics as line_metrics
    (fsSelection bit 7 clear, as Google Fonts' CJK schema wants: the win and hhea metrics, equal,
    set the line), and the Unicode-range and code-page bits of the characters mapped."""
    ascent, descent = line_metrics(info, bounds)
    # PANOSE: Latin text family, monospaced proportion (every ideograph is one em wide)
    from fontTools.ttLib.tables.O_S_2f_2 import Panose

    panose = Panose()
    panose.bFamilyType, panose.bProportion = 2, 9
    fb.setupOS2(version=4, panose=panose, sTypoAscender=info.ascender, sTypoDescender=info.descender, sTypoLineGap=0,
                usWinAscent=ascent, usWinDescent=descent, fsSelection=0x40, achVendID="BRSH", fsType=0)
    os2 = fb.font["OS/2"]
    os2.recalcAvgCharWidth(fb.font)
    os2.recalcUnicodeRanges(fb.font)
    os2.ulCodePageRange1, os2.ulCodePageRange2 = code_pages(chars), 0


def _meta(font, chars: str) -> None:
    """A meta table naming the script the font is designed for and supports (dlng, slng): the
    CJK code page most of its characters are in, else Hani."""
    from fontTools.ttLib import newTable

    bits = code_pages(chars)
    tag = next((t for codec, t in META_SCRIPTS.items() if bits >> CODEPAGE_BITS[codec] & 1), "Hani")
    meta = newTable("meta")
    meta.data = {"dlng": tag, "slng": tag}
    font["meta"] = meta


def _encodes(char: str, codec: str) -> bool:
    try:
        char.encode(codec)
        return True
    except UnicodeEncodeError:
        return False


def code_pages(chars: str) -> int:
    """ulCodePageRange1 for a font of chars: bit 0 (Latin 1) when it has ASCII letters, and each
    CJK code page's bit when at least half its other characters are in that code page."""
    wide = [c for c in chars if ord(c) > 0x7F]
    bits = int(any(c.isascii() and c.isalpha() for c in chars))
    for codec, bit in CODEPAGE_BITS.items():
        if wide and 2 * sum(_encodes(c, codec) for c in wide) >= len(wide):
            bits |= 1 << bit
    return bits


# BASE: the scripts set on the ideographic baseline (the em box's bottom) and those on the Roman one
BASE_SCRIPTS = (("DFLT", "ideo"), ("cyrl", "romn"), ("grek", "romn"), ("hang", "ideo"), ("hani", "ideo"),
                ("kana", "ideo"), ("latn", "romn"))


def face_extent(boxes: list, axis: int) -> tuple:
    """(low, high) font units: the ideographic character face along axis (0 x, 1 y), the median
    of the glyphs' ink boxes' low and high edges (boxes (xMin, yMin, xMax, yMax)) over the set."""
    lows = [b[axis] for b in boxes]
    highs = [b[axis + 2] for b in boxes]
    return int(round(float(np.median(lows)))), int(round(float(np.median(highs))))


def base_feature(info: FontInfo, boxes: list) -> str:
    """The BASE table as feature syntax: for horizontal and vertical writing the ideographic em
    box (ideo, idtp: the typo descender and ascender across, the em's left and right edges down),
    the ideographic character face (icfb, icft: the ink's extent over the set, face_extent) and
    the Roman baseline (romn: y 0 across, the descender's depth from the left edge down)."""
    if not boxes:
        boxes = [(0, info.descender, info.upm, info.ascender)]
    axes = {"HorizAxis": (*face_extent(boxes, 1), info.descender, info.ascender, 0),
            "VertAxis": (*face_extent(boxes, 0), 0, info.upm, -info.descender)}
    lines = ["table BASE {"]
    for axis, values in axes.items():
        coords = " ".join(map(str, values))
        scripts = ",\n    ".join(f"{tag} {default} {coords}" for tag, default in BASE_SCRIPTS)
        lines += [f"  {axis}.BaseTagList icfb icft ideo idtp romn;", f"  {axis}.BaseScriptList {scripts};"]
    return "\n".join(lines + ["} BASE;"])


def _smart_dropout(font) -> None:
    """An unhinted TrueType font's prep program turning smart dropout control on at every size
    (SCANCTRL 511, SCANTYPE 4), and a gasp table asking for grey-scale smoothing throughout."""
    from fontTools.ttLib import newTable
    from fontTools.ttLib.tables import ttProgram

    prep = newTable("prep")
    prep.program = ttProgram.Program()
    prep.program.fromAssembly(["PUSHW[ ]", "511", "SCANCTRL[ ]", "PUSHB[ ]", "4", "SCANTYPE[ ]"])
    font["prep"] = prep
    gasp = newTable("gasp")
    gasp.gaspRange = {0xFFFF: 0x000F}
    font["gasp"] = gasp


def _glyphs(outlines: dict, info: FontInfo, draw=None) -> tuple:
    """(glyph names, their RecordingPens, their advances, code point -> name): .notdef, the
    spaces, then the outlines' glyphs in code-point order, each drawn by draw(char, contours)
    (default: clean_outline of the contours)."""
    from fontTools.pens.recordingPen import RecordingPen

    chars = sorted(outlines, key=ord)
    spaces = [(c, n, round(w * info.upm)) for c, (n, w) in SPACES.items() if c not in outlines]
    names = [".notdef"] + [n for _, n, _ in spaces] + [glyph_name(c) for c in chars]
    recs = [notdef(info.upm, info.ascender, info.descender)] + [RecordingPen() for _ in spaces] + \
        [draw(c, outlines[c]) if draw else clean_outline(outlines[c]) for c in chars]
    advances = [info.upm] + [w for _, _, w in spaces] + [info.upm] * len(chars)
    cmap = {ord(c): n for c, n, _ in spaces} | {ord(c): glyph_name(c) for c in chars}
    return names, recs, advances, cmap


def make_font(outlines: dict, info: FontInfo, cff: bool = True, draw=None, specialize: bool = True):
    """A fontTools TTFont of the outlines ({char: contours in font units}), each glyph one em wide
    and one em tall (vertical metrics set for vertical CJK text), with CFF outlines or, when cff is
    False, glyf quadratics (cu2qu makes those of cubics); with .notdef and the SPACES. draw(char,
    contours) -> RecordingPen draws a glyph (default: clean_outline, overlaps removed)."""
    from fontTools.fontBuilder import FontBuilder

    names, recs, advances, cmap = _glyphs(outlines, info, draw)
    bounds = tight = [_bounds(r) for r in recs]
    fb = FontBuilder(info.upm, isTTF=not cff)
    fb.setupGlyphOrder(names)
    fb.setupCharacterMap(cmap)
    if cff:
        fb.setupCFF(info.ps_name, {"FullName": f"{info.family} {info.style}", "FamilyName": info.family,
                                   "Weight": info.style, "version": info.version},
                    {n: _charstring(r, w, specialize) for n, r, w in zip(names, recs, advances)}, {})
    else:
        fb.setupGlyf({n: _tt_glyph(r) for n, r in zip(names, recs)})
        # TrueType places a glyph by its left side bearing: take it from the quadratics' own box
        bounds = [_glyf_bounds(fb.font["glyf"], n) for n in names]
        _smart_dropout(fb.font)
    fb.setupHorizontalMetrics({n: (w, int(np.floor(b[0]))) for n, w, b in zip(names, advances, bounds)})
    ascent, descent = line_metrics(info, bounds)
    fb.setupHorizontalHeader(ascent=ascent, descent=-descent, lineGap=0)
    # vertical: one em advance down; a glyph's top side bearing from the em box's top (the ascender)
    fb.setupVerticalHeader(ascent=info.upm // 2, descent=-(info.upm - info.upm // 2))
    fb.setupVerticalMetrics({n: (info.upm, int(np.floor(info.ascender - b[3]))) for n, b in zip(names, bounds)})
    if cff:
        fb.setupVerticalOrigins({}, info.ascender)
    fb.setupNameTable(_names(info), mac=False)
    _os2(fb, info, bounds, "".join(outlines))
    ink = [b for n, b in zip(names, tight) if n in set(cmap.values()) and b[2] > b[0]]
    fb.addOpenTypeFeatures(base_feature(info, ink))
    _meta(fb.font, "".join(outlines))
    fb.setupPost(keepGlyphNames=False)
    stamp = _timestamp()
    fb.setupHead(unitsPerEm=info.upm, fontRevision=float(info.version), created=stamp, modified=stamp)
    fb.setupMaxp()
    return fb.font


def _write_ufo(outlines: dict, info: FontInfo, path: str) -> None:
    """A UFO 3 folder at path, made beside it and moved into place (an older one replaced)."""
    import ufoLib2

    ufo = ufoLib2.Font()
    fi = ufo.info
    fi.familyName, fi.styleName, fi.unitsPerEm = info.family, info.style, info.upm
    fi.ascender, fi.descender = info.ascender, info.descender
    fi.openTypeOS2TypoAscender, fi.openTypeOS2TypoDescender, fi.openTypeOS2TypoLineGap = info.ascender, info.descender, 0
    major, minor = info.version.split(".")
    fi.versionMajor, fi.versionMinor = int(major), int(minor)
    fi.openTypeNameLicense = info.licence
    fi.postscriptFontName = info.ps_name
    names, recs, advances, cmap = _glyphs(outlines, info)
    code = {n: cp for cp, n in cmap.items()}
    for name, rec, advance in zip(names, recs, advances):
        g = ufo.newGlyph(name)
        g.width, g.height = advance, info.upm
        g.unicodes = [code[name]] if name in code else []
        rec.replay(g.getPen())
    folder = os.path.dirname(os.path.abspath(path))
    tmp = tempfile.mkdtemp(prefix=".tmp-", suffix=".ufo", dir=folder)
    old = None
    try:
        ufo.save(tmp, overwrite=True)
        if os.path.exists(path):
            old = tempfile.mkdtemp(prefix=".old-", suffix=".ufo", dir=folder)
            os.replace(path, os.path.join(old, "ufo"))
        os.replace(tmp, path)
    except OSError as err:
        raise OSError(err.errno, os_error_text(err, path)) from None
    finally:
        for left in (tmp, old):
            if left and os.path.exists(left):
                shutil.rmtree(left)


def write_font(outlines: dict, path: str | os.PathLike, info: FontInfo | None = None) -> str:
    """The outlines ({char: contours}) as a font at path, in the format its suffix names (.otf
    .ttf .woff2 .ufo), written atomically. Returns the path."""
    info = (info or FontInfo()).check()
    path = os.fspath(path)
    suffix = check_font_path(path)
    if suffix == ".ufo":
        _write_ufo(outlines, info, path)
        return path
    font = make_font(outlines, info, cff=suffix != ".ttf")
    if suffix == ".woff2":
        font.flavor = "woff2"
    elif suffix == ".otf":
        subroutinize(font)
    write_atomic(path, font.save, suffix=suffix)
    return path


def subroutinize(font) -> None:
    """font's CFF charstrings with their shared runs moved into subroutines (cffsubr, AFDKO's tx):
    an OTF about 5% smaller. A WOFF2 is left without: Brotli packs the plain charstrings tighter."""
    import cffsubr

    cffsubr.subroutinize(font)
