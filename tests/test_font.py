"""`brushwork font`: fonts built from the brush's ink, read back by the clients that use fonts
(OpenType Sanitizer, fontTools, HarfBuzz, FreeType, Chromium), their command line and cache."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("fontTools")
pytest.importorskip("pathops")

from brushwork.font import Em, FontInfo, build_font  # noqa: E402
from brushwork.font.make import CACHE_DIR  # noqa: E402

CHARS = "永十人大"           # bundled glyphs: no KanjiVG or median lookups needed
SIMPLE = "十人大"


@pytest.fixture(scope="module")
def fonts(tmp_path_factory):
    """The same four characters as OTF, TTF, WOFF2 and UFO (the outlines made once, then cached)."""
    folder = tmp_path_factory.mktemp("fonts")
    out = {}
    for ext in (".otf", ".ttf", ".woff2", ".ufo"):
        out[ext] = (folder / f"b{ext}", build_font(CHARS, folder / f"b{ext}", jobs=1))
    return out


@pytest.fixture(scope="module")
def renders():
    """The brush's own 512 px render of each character, as `brushwork render CHAR --size 512 --ink
    geometry` draws it (the font's route for the opaque kai), with its exact loops and its
    placement in the em box."""
    from brushwork.bench.font import Written
    from brushwork.writing import text_paper
    from brushwork.glyphs import load_source

    glyphs = load_source("default", CHARS)
    return {c: Written(text_paper([glyphs[c]], 512, ink="geometry"), 512) for c in CHARS}


def test_fonts_are_made_once_then_cached(fonts):
    first = fonts[".otf"][1]
    assert sorted(first.made) == sorted(CHARS) and not first.cached and not first.failed
    for ext in (".ttf", ".woff2", ".ufo"):
        res = fonts[ext][1]
        assert not res.made and sorted(res.cached) == sorted(CHARS)


@pytest.mark.parametrize("ext", [".otf", ".ttf", ".woff2"])
def test_the_sanitizer_accepts_the_font(fonts, ext):
    pytest.importorskip("ots")
    from brushwork.font.check import sanitize

    assert sanitize(fonts[ext][0]) is None


@pytest.mark.parametrize("ext", [".otf", ".ttf", ".woff2"])
def test_font_tables_read_back(fonts, ext):
    from fontTools.ttLib import TTFont

    with TTFont(fonts[ext][0]) as font:
        _check_tables(font, ext)


def _check_tables(font, ext):
    for tag in ("cmap", "head", "hhea", "hmtx", "vhea", "vmtx", "OS/2", "name", "post", "maxp"):
        assert tag in font, tag
    assert ("glyf" if ext == ".ttf" else "CFF ") in font
    assert font.getGlyphOrder()[0] == ".notdef"
    assert set(font.getBestCmap()) == {ord(c) for c in CHARS + " \u00a0\u3000"}
    os2, upm = font["OS/2"], font["head"].unitsPerEm
    assert upm in (1000, 1024)
    assert os2.sTypoAscender - os2.sTypoDescender == upm
    assert os2.sTypoAscender == round(0.88 * upm) and os2.sTypoLineGap == 0
    # Google Fonts' CJK vertical metrics: hhea and win equal, a line of 1.1..1.5 em, bit 7 clear
    hhea = font["hhea"]
    assert hhea.ascent == os2.usWinAscent and -hhea.descent == os2.usWinDescent and hhea.lineGap == 0
    assert 1.1 * upm < hhea.ascent - hhea.descent <= 1.5 * upm and not os2.fsSelection & 0x80
    assert font["post"].formatType == 3.0
    assert font["meta"].data == {"dlng": "Hans", "slng": "Hans"}
    assert os2.ulCodePageRange1 & (1 << 18)                 # Chinese Simplified
    assert 59 in os2.getUnicodeRanges()                      # CJK Unified Ideographs
    names = {n.nameID: n.toUnicode() for n in font["name"].names}
    assert names[1] == "Brushwork" and names[5] == "Version 1.0" and names[13]
    for c in CHARS + "\u3000":
        name = font.getBestCmap()[ord(c)]
        assert font["hmtx"][name][0] == upm and font["vmtx"][name][0] == upm
    assert font["hmtx"]["space"][0] == upm // 4


def _glyph_boxes(font) -> dict:
    from fontTools.pens.boundsPen import BoundsPen

    glyphs, boxes = font.getGlyphSet(), {}
    for c in CHARS:
        pen = BoundsPen(glyphs)
        glyphs[font.getBestCmap()[ord(c)]].draw(pen)
        boxes[c] = pen.bounds
    return boxes


@pytest.mark.parametrize("ext", [".otf", ".ttf"])
def test_base_table_has_the_em_box_and_the_ink_face(fonts, ext):
    """BASE, across and down: the ideographic em box (ideo, idtp) is the typo descender and
    ascender across and the em's sides down; the character face (icfb, icft) is the median of
    the glyphs' ink boxes' edges, inside the em box; Han sits on ideo, Latin on romn."""
    from fontTools.ttLib import TTFont

    with TTFont(fonts[ext][0]) as font:
        base, boxes = font["BASE"].table, np.array(list(_glyph_boxes(font).values()))
        for axis, lo, hi, y in ((base.HorizAxis, -120, 880, 1), (base.VertAxis, 0, 1000, 0)):
            tags = axis.BaseTagList.BaselineTag
            assert tags == ["icfb", "icft", "ideo", "idtp", "romn"]
            scripts = {r.BaseScriptTag: r.BaseScript.BaseValues for r in axis.BaseScriptList.BaseScriptRecord}
            assert tags[scripts["hani"].DefaultIndex] == "ideo" and tags[scripts["latn"].DefaultIndex] == "romn"
            value = dict(zip(tags, (c.Coordinate for c in scripts["hani"].BaseCoord)))
            assert (value["ideo"], value["idtp"]) == (lo, hi)
            assert value["icfb"] == pytest.approx(np.median(boxes[:, y]), abs=1)
            assert value["icft"] == pytest.approx(np.median(boxes[:, y + 2]), abs=1)
            assert lo < value["icfb"] < value["icft"] < hi


def test_name_table_carries_the_licence_and_its_url(tmp_path):
    from fontTools.ttLib import TTFont

    info = FontInfo(licence="SIL Open Font License, Version 1.1", licence_url="https://openfontlicense.org",
                    copyright="Copyright 2026 The Brushwork Authors", vendor_url="https://example.org")
    build_font("十", tmp_path / "n.otf", info=info)
    with TTFont(tmp_path / "n.otf") as font:
        names = {n.nameID: n.toUnicode() for n in font["name"].names}
    assert (names[0], names[11], names[13], names[14]) == (info.copyright, info.vendor_url, info.licence,
                                                           info.licence_url)
    with pytest.raises(ValueError, match="--licence-url"):
        FontInfo(licence_url="openfontlicense.org").check()


@pytest.mark.parametrize("ext", [".otf", ".ttf"])
def test_no_segment_is_degenerate(fonts, ext):
    """No line or curve of a glyph ends where it starts (a point repeated), and no contour closes
    with a line back onto its first point."""
    from fontTools.pens.recordingPen import DecomposingRecordingPen
    from fontTools.ttLib import TTFont

    with TTFont(fonts[ext][0]) as font:
        glyphs = font.getGlyphSet()
        for c in CHARS:
            pen = DecomposingRecordingPen(glyphs)
            glyphs[font.getBestCmap()[ord(c)]].draw(pen)
            here = start = None
            for op, args in pen.value:
                if op == "moveTo":
                    here = start = args[0]
                elif args:
                    assert np.abs(np.subtract(args, here)).max() > 0, (c, op, args)
                    assert not (op == "lineTo" and tuple(args[0]) == tuple(start)), (c, args)
                    here = args[-1]


def test_ufo_reads_back(fonts):
    ufo_lib = pytest.importorskip("ufoLib2")
    ufo = ufo_lib.Font.open(fonts[".ufo"][0])
    assert ufo.info.unitsPerEm == 1000 and ufo.info.ascender - ufo.info.descender == 1000
    mapped = {u for g in ufo for u in g.unicodes}
    assert mapped == {ord(c) for c in CHARS + " \u00a0\u3000"}
    assert all(len(ufo[f"uni{ord(c):04X}"].contours) > 0 for c in CHARS)


@pytest.mark.parametrize("ext", [".otf", ".ttf"])
def test_every_code_point_shapes_to_its_own_glyph(fonts, ext):
    pytest.importorskip("uharfbuzz")
    from brushwork.font.check import shaped_glyphs

    assert shaped_glyphs(fonts[ext][0], CHARS) == [f"uni{ord(c):04X}" for c in CHARS]


@pytest.mark.parametrize("ext", [".otf", ".ttf"])
def test_freetype_draws_what_the_brush_drew(fonts, renders, ext):
    """At the default tolerance the outline keeps within 2 font units of the ink's edge (90th
    percentile) and FreeType's ink overlaps the brush's closely."""
    from brushwork.font.check import glyph_fidelity

    assert fonts[ext][1].ink == "geometry"
    for c in CHARS:
        fid = glyph_fidelity(fonts[ext][0], c, renders[c].rgb, Em(), renders[c].shift)
        assert fid["stray"] <= 2.0, (c, fid)
        assert fid["iou"] >= 0.96, (c, fid)


def test_a_tight_tolerance_reproduces_the_render(tmp_path, renders):
    """Fitted within 0.05 px on average (0.2 px at most), and tidied (near-flat curves and
    near-colinear lines straightened within half a font unit, 0.26 px here), FreeType's 512 px
    raster of each glyph matches the brush's 512 px render to IoU 0.988: what differs is single
    edge pixels whose coverage sits near one half."""
    from brushwork.font.check import glyph_fidelity

    path = tmp_path / "tight.otf"
    build_font(SIMPLE, path, tolerance=0.05)
    for c in SIMPLE:
        assert glyph_fidelity(path, c, renders[c].rgb, Em(), renders[c].shift)["iou"] >= 0.988, c


def test_outline_points_lie_on_the_em_square_the_render_spans(fonts, renders):
    """The ink's box in the render, moved as the font places it and mapped to font units, is the
    glyph's box in the font, within what the fit may stray from the ink's edge (MAX_RATIO
    tolerances: a thin spike cut short) and half a pixel of the mask's steps."""
    from fontTools.pens.boundsPen import BoundsPen
    from fontTools.ttLib import TTFont

    from brushwork.font.fit import MAX_RATIO
    from brushwork.font.outline import FIT_TOL_PX
    from brushwork.font.check import shifted
    from brushwork.font.trace import ink_coverage, ink_mask

    boxes = {}
    with TTFont(fonts[".ttf"][0]) as font:
        glyphs = font.getGlyphSet()
        for c in CHARS:
            pen = BoundsPen(glyphs)
            glyphs[f"uni{ord(c):04X}"].draw(pen)
            boxes[c] = pen.bounds
    em = Em()
    for c in CHARS:
        ys, xs = np.nonzero(ink_mask(shifted(ink_coverage(renders[c].rgb), renders[c].shift)))
        lo = em.to_font(np.array([xs.min(), ys.max() + 1.0]))
        hi = em.to_font(np.array([xs.max() + 1.0, ys.min()]))
        bound = (MAX_RATIO * FIT_TOL_PX + 0.5) * em.upm / em.size
        assert np.allclose(boxes[c], [*lo, *hi], atol=bound), (c, boxes[c], lo, hi)


def _cli(*args, cwd=None):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    return subprocess.run([sys.executable, "-m", "brushwork", "font", *args], capture_output=True, text=True,
                          env=env, cwd=cwd, timeout=300)


def test_cli_lists_missing_characters_and_builds_the_rest(tmp_path):
    out = tmp_path / "part.otf"
    res = _cli("--chars", "十\U0002A6A5", "-o", str(out), "--jobs", "1", "--no-progress")
    assert res.returncode == 2
    assert out.is_file()
    assert "missing from the font: \U0002A6A5" in res.stdout
    assert len(res.stderr.strip().splitlines()) == 1


@pytest.mark.parametrize("args, why", [
    (["--chars", "十", "-o", "{d}/f.png"], "cannot write a .png font"),
    (["--chars", "十", "-o", "{d}/no/f.otf"], "no such folder"),
    (["--chars", "十", "-o", "{d}/f.otf", "--version", "one"], "--version"),
    (["--chars", "十", "-o", "{d}/f.otf", "--executor", "mpi"], "--executor"),
    (["--chars", "十", "-o", "{d}/f.otf", "--tolerance", "0"], "--tolerance"),
    (["--charset", "{d}/none.txt", "-o", "{d}/f.otf"], "none.txt"),
    (["--chars", "十"], "--web"),
    (["--chars", "十", "--web", "{d}/f.web", "--slice-chars", "0"], "--slice-chars"),
    (["--chars", "十", "-o", "{d}/f.otf", "--licence-url", "openfontlicense.org"], "--licence-url"),
    (["--chars", "十", "-o", "{d}/f.ufo", "--variable"], "--variable"),
])
def test_cli_bad_input_is_one_line_and_no_file(tmp_path, args, why):
    res = _cli(*[a.format(d=tmp_path) for a in args])
    assert res.returncode == 2
    assert len(res.stderr.strip().splitlines()) == 1 and why in res.stderr
    assert not list(tmp_path.glob("f.*"))


def test_a_rebuild_makes_only_glyphs_missing_from_the_cache(tmp_path):
    first = build_font("十人", tmp_path / "a.otf")
    cached = sorted((tmp_path / CACHE_DIR).rglob("*.json"))
    assert len(cached) == 2 and sorted(first.made) == sorted("十人")
    cached[0].unlink()
    again = build_font("十人", tmp_path / "a.otf")
    assert len(again.made) == 1 and len(again.cached) == 1


@pytest.mark.parametrize("content", ["[]", "[[]]", "NaN", "[[[[NaN, 0], [1, 1], [2, 2], [3, 3]]]]",
                                     "[[[[1e300, 0], [1, 1], [2, 2], [3, 3]]]]", '[{"a": 1}]', "[[[1, 2, 3]]]",
                                     "[" * 100000, "{not json", ""])
def test_a_damaged_cache_entry_is_made_again(tmp_path, content):
    """A cache file that is not an outline (empty, not finite, beyond a font's coordinates, the
    wrong shape, nested too deeply, cut short) is made again, never drawn."""
    first = build_font("十", tmp_path / "a.otf")
    cached = sorted((tmp_path / CACHE_DIR).rglob("*.json"))
    good = cached[0].read_text(encoding="utf-8")
    cached[0].write_text(content, encoding="utf-8")
    again = build_font("十", tmp_path / "a.otf")
    assert first.made == ["十"] and again.made == ["十"] and not again.cached and not again.failed
    assert cached[0].read_text(encoding="utf-8") == good, "the entry made again is the one the brush draws"


def test_no_font_is_written_when_no_glyph_can_be_made(tmp_path):
    res = build_font("\U0002A6A5", tmp_path / "none.otf")
    assert res.failed and not res.points
    assert not (tmp_path / "none.otf").exists()


def test_font_info_is_checked():
    with pytest.raises(ValueError):
        FontInfo(version="1.0.0").check()
    with pytest.raises(ValueError):
        FontInfo(family="").check()


def test_ray_executor_gives_the_local_results(tmp_path):
    """One small Ray run on a local cluster: the font's outlines and the batch's PNGs are the
    same bytes as a local run's."""
    ray = pytest.importorskip("ray", reason="Ray is an optional extra (brushwork[ray])")
    from brushwork.batch import run_batch

    chars = "十人"
    (tmp_path / "ray").mkdir()
    try:
        build_font(chars, tmp_path / "ray" / "f.otf", jobs=2, executor="ray")
        run_batch(chars, tmp_path / "ray_png", jobs=2, size=128, executor="ray", progress=False)
    finally:
        ray.shutdown()
    (tmp_path / "local").mkdir()
    build_font(chars, tmp_path / "local" / "f.otf", jobs=1)
    run_batch(chars, tmp_path / "local_png", jobs=1, size=128, progress=False)
    for a in sorted((tmp_path / "ray" / CACHE_DIR).rglob("*.json")):
        b = tmp_path / "local" / a.relative_to(tmp_path / "ray")
        assert json.loads(a.read_text()) == json.loads(b.read_text())
    for c in chars:
        name = f"U+{ord(c):04X}.png"
        assert (tmp_path / "ray_png" / name).read_bytes() == (tmp_path / "local_png" / name).read_bytes()


def test_chromium_sets_the_woff2_as_freetype_does(fonts):
    """Headless Chromium renders a line in the WOFF2 through @font-face; its screenshot matches
    FreeType's rendering of the same line."""
    pytest.importorskip("selenium")
    from brushwork.font.browser import MARGIN_PX, chromium_line, find_chromium, freetype_line
    from brushwork.font.check import iou
    from brushwork.font.trace import ink_coverage, ink_mask

    browser, driver = find_chromium()
    if not browser or not driver:
        pytest.skip("no chromium and chromedriver on PATH (Debian: apt-get install chromium chromium-driver)")
    px = 128
    shot = ink_coverage(chromium_line(fonts[".woff2"][0], CHARS, px))
    line = shot[MARGIN_PX:MARGIN_PX + px, MARGIN_PX:MARGIN_PX + len(CHARS) * px]
    assert iou(ink_mask(line), freetype_line(fonts[".woff2"][0], CHARS, px) >= 0.5) >= 0.97


def _glyph_area(path, char):
    from fontTools.pens.areaPen import AreaPen
    from fontTools.ttLib import TTFont

    with TTFont(path) as font:
        glyphs = font.getGlyphSet()
        pen = AreaPen(glyphs)
        glyphs[font.getBestCmap()[ord(char)]].draw(pen)
    return pen.value


@pytest.mark.parametrize("how", ["raises", "loses ink"])
def test_a_glyph_skia_cannot_simplify_keeps_its_traced_contours(monkeypatch, tmp_path, how):
    """When skia-pathops gives up on a glyph or returns other ink, the font is still written,
    with that glyph's contours as traced (apart, outer ones counter-clockwise for CFF): the same
    ink, within the share of it that build accepts a union to change."""
    import pathops

    from brushwork.font.build import SIMPLIFY_AREA_TOL

    build_font("十", tmp_path / "a.otf")

    def fail(*args, **kwargs):
        if how == "raises":
            raise pathops.PathOpsError("operation did not succeed")
        return pathops.Path()

    monkeypatch.setattr(pathops, "simplify", fail)
    build_font("十", tmp_path / "b.otf")
    a, b = _glyph_area(tmp_path / "a.otf", "十"), _glyph_area(tmp_path / "b.otf", "十")
    assert a > 0 and b == pytest.approx(a, rel=SIMPLIFY_AREA_TOL)


def _circle(r, n, grain=0.0):
    """(n, 2) px: a closed circle of radius r about (50, 50), every fifth point pushed out by
    `grain` px (the pixel-sized bumps of the ink's edge)."""
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    rr = r + grain * (np.arange(n) % 5 == 0)
    return np.stack([50 + rr * np.cos(a), 50 + rr * np.sin(a)], axis=1)


def test_the_edge_grain_costs_no_curves():
    """A circle whose edge has bumps of 0.6 px, fitted within 0.5 px on average, takes as few
    curves as the smooth circle, and none strays more than MAX_RATIO tolerances."""
    from brushwork.font.fit import MAX_RATIO, _bezier, fit_closed

    smooth = fit_closed(_circle(20, 252), 0.5, 0.5)
    grainy_p = _circle(20, 252, grain=0.6)
    grainy = fit_closed(grainy_p, 0.5, 0.5)
    assert len(grainy) <= len(smooth) + 1
    drawn = np.concatenate([_bezier(c, np.linspace(0, 1, 200)) for c in grainy])
    dist = np.min(np.linalg.norm(grainy_p[:, None, :] - drawn[None, :, :], axis=2), axis=1)
    assert dist.mean() <= 0.5 and dist.max() <= MAX_RATIO * 0.5


def test_a_tolerance_bounds_the_mean_distance_of_each_curve():
    """A wavy contour fitted at two tolerances: each curve lies within its tolerance of its points
    on average, and the tighter fit takes more curves."""
    from brushwork.font.fit import _bezier, fit_closed

    a = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    wavy = np.stack([50 + (30 + 3 * np.sin(7 * a)) * np.cos(a), 50 + (30 + 3 * np.sin(7 * a)) * np.sin(a)], axis=1)
    counts = {}
    for tol in (0.05, 1.0):
        curves = fit_closed(wavy, tol, 0.5)
        drawn = np.concatenate([_bezier(c, np.linspace(0, 1, 200)) for c in curves])
        dist = np.min(np.linalg.norm(wavy[:, None, :] - drawn[None, :, :], axis=2), axis=1)
        assert dist.mean() <= tol
        counts[tol] = len(curves)
    assert counts[0.05] > counts[1.0]


def test_pinholes_under_a_pixel_are_dropped_and_larger_holes_kept():
    from brushwork.font.trace import trace

    cov = np.zeros((40, 40), np.float32)
    cov[5:35, 5:35] = 1.0
    cov[12, 12] = 0.0                      # a pinhole of one pixel
    cov[20:24, 20:24] = 0.0                # a hole of 4 x 4 pixels
    areas = sorted(0.5 * float(np.dot(p[:, 0], np.roll(p[:, 1], -1)) - np.dot(np.roll(p[:, 0], -1), p[:, 1]))
                   for p in trace(cov))
    assert len(areas) == 2
    assert areas[0] == pytest.approx(-16.0, rel=0.25) and areas[1] == pytest.approx(900.0, rel=0.02)


def test_the_ceiling_fill_covers_pixels_by_area():
    from brushwork.bench.font import _area_fill

    square = np.array([[2.0, 2.0], [6.5, 2.0], [6.5, 6.0], [2.0, 6.0]])
    cov = _area_fill([square], 10)
    assert cov[3, 3] == 1.0 and cov[0, 0] == 0.0
    assert cov[3, 6] == pytest.approx(0.5, abs=0.07)      # the column the edge halves
    assert cov.sum() == pytest.approx(4.5 * 4.0, rel=0.03)


def test_a_curve_that_loops_between_its_points_does_not_fit():
    """Points that lie on a curve at their parameters do not make it fit when the curve loops
    between them: its length gives it away."""
    from brushwork.font.fit import _bezier, _worst

    p = np.array([[0.0, 0.0], [5.0, 0.0], [10.0, 0.0]])
    u = np.array([0.0, 0.5, 1.0])
    straight = np.array([[0.0, 0.0], [10 / 3, 0.0], [20 / 3, 0.0], [10.0, 0.0]])
    looped = np.array([[0.0, 0.0], [30.0, 12.0], [-20.0, -12.0], [10.0, 0.0]])
    assert _worst(straight, p, u, 0.5)[0] <= 1.0
    assert np.allclose(_bezier(looped, u), p)          # on every point at its parameter
    assert _worst(looped, p, u, 0.5)[0] == np.inf


def test_the_glyph_cache_is_keyed_by_the_brush(monkeypatch):
    """Cached outlines are found again only for the same brush: a preset whose parameters differ
    (another brushwork's simulation) gets a cache folder of its own."""
    import brushwork
    from brushwork.font import make
    from brushwork.writing import Style

    kai = Style.load("kai")
    key = make._cache_key(kai, 0, 512, 0.5)
    assert make._cache_key(kai, 0, 512, 0.5) == key
    preset = brushwork.BrushModel.preset

    def stiffer(name):
        m = preset(name)
        m.bend_stiffness *= 2.0
        return m

    monkeypatch.setattr(brushwork.BrushModel, "preset", staticmethod(stiffer))
    assert make._cache_key(kai, 0, 512, 0.5) != key


@pytest.fixture(scope="module")
def web(tmp_path_factory):
    """CHARS for the web in slices of one character each after a slice of the blanks."""
    folder = tmp_path_factory.mktemp("web")
    res = build_font(CHARS, None, web=folder, slice_chars=1)
    assert res.web is not None and not res.failed
    return res.web


def test_web_slices_split_the_font_by_unicode_range(web):
    """One WOFF2 a slice, in the charset's order, each mapping its characters alone (and .notdef),
    accepted by the Sanitizer, with the BASE and vertical tables kept; the CSS holds one
    @font-face rule a slice whose unicode-range is that slice's; the page links the CSS."""
    from fontTools.ttLib import TTFont

    from brushwork.font.web import unicode_range

    pytest.importorskip("ots")
    from brushwork.font.check import sanitize

    assert [chars for _, chars in web.slices] == [" \u00a0\u3000", *CHARS]
    from pathlib import Path

    css = Path(web.css).read_text(encoding="utf-8")
    assert css.count("@font-face") == len(web.slices)
    for path, chars in web.slices:
        with TTFont(path) as font:
            assert font.flavor == "woff2" and set(font.getBestCmap()) == {ord(c) for c in chars}
            assert {"BASE", "vhea", "vmtx", "VORG", "meta"} <= set(font.keys())
        assert f'url("{os.path.basename(path)}") format("woff2");\n  font-display: swap;\n  unicode-range: ' \
               f'{unicode_range(chars)};' in css
        assert sanitize(path) is None
    assert os.path.basename(web.css) in Path(web.page).read_text(encoding="utf-8")
    assert unicode_range("一丁七万丈三") == "U+4E00-4E01, U+4E03, U+4E07-4E09"


def test_chromium_fetches_only_the_slices_a_page_needs(web, tmp_path):
    """A page of two of the characters, served over HTTP: Chromium fetches the two slices that
    hold them and no other but the blanks' (the line's metrics come from the face that maps the
    space), and sets them as FreeType draws them from the slices."""
    pytest.importorskip("selenium")
    import functools
    import http.server
    import threading

    from brushwork.font.browser import MARGIN_PX, chromium_shot, find_chromium, freetype_line
    from brushwork.font.check import iou
    from brushwork.font.trace import ink_coverage, ink_mask
    from brushwork.font.web import page_html

    if not all(find_chromium()):
        pytest.skip("no chromium and chromedriver on PATH (Debian: apt-get install chromium chromium-driver)")
    text, px = CHARS[1] + CHARS[3], 128
    with open(os.path.join(web.folder, "two.html"), "w", encoding="utf-8") as f:
        f.write(page_html("Brushwork", os.path.basename(web.css), text, px))
    handler = functools.partial(http.server.SimpleHTTPRequestHandler, directory=web.folder)
    handler.log_message = lambda *a: None
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        url = f"http://127.0.0.1:{server.server_address[1]}/two.html"
        shot, fetched = chromium_shot(url, len(text) * px + 2 * MARGIN_PX, px + 2 * MARGIN_PX,
                                      "return performance.getEntriesByType('resource').map(e => e.name)")
    finally:
        server.shutdown()
        server.server_close()
    needed = {os.path.basename(p) for p, chars in web.slices if set(chars) & set(text)}
    assert len(needed) == 2
    got = {n.rsplit("/", 1)[-1] for n in fetched if n.endswith(".woff2")}
    assert needed <= got <= needed | {os.path.basename(web.slices[0][0])}
    line = ink_coverage(shot)[MARGIN_PX:MARGIN_PX + px, MARGIN_PX:MARGIN_PX + len(text) * px]
    drawn = np.concatenate([freetype_line(p, c, px) for c in text for p, chars in web.slices if c in chars], axis=1)
    assert iou(ink_mask(line), drawn >= 0.5) >= 0.97


def test_a_cubic_cut_in_two_is_joined_again_and_others_are_not():
    from brushwork.font.tidy import _split, rejoin

    c = np.array([[0.0, 0.0], [30.0, 80.0], [90.0, 90.0], [120.0, 10.0]])
    a, b = _split(c, 0.3)
    assert len(rejoin([a, b])) == 1 and np.allclose(rejoin([a, b])[0], c)
    bent = b.copy()
    bent[1] += [0.0, 5.0]                     # the handle turned: not the other part of c
    assert len(rejoin([a, bent])) == 2


def test_extremes_are_on_curve():
    """A curve that bulges past its ends is split at its extreme, which then lies at the new ends
    with level handles; one that bulges under EXTREME_UNITS has its handles pulled in."""
    from brushwork.font.tidy import EXTREME_UNITS, _point, on_curve_extremes

    arch = np.array([[0.0, 0.0], [10.0, 60.0], [90.0, 60.0], [100.0, 0.0]])
    parts = on_curve_extremes(arch)
    assert len(parts) == 2 and parts[0][3, 1] == pytest.approx(45.0) and parts[0][2, 1] == parts[1][1, 1] == parts[0][3, 1]
    flat = np.array([[0.0, 0.0], [30.0, 0.6], [70.0, 0.6], [100.0, 0.0]])
    (kept,) = on_curve_extremes(flat)
    assert max(_point(kept, t)[1] for t in np.linspace(0, 1, 101)) <= 1e-9 < 0.45 <= EXTREME_UNITS


def test_a_long_handle_past_an_end_is_not_pulled_in():
    """A curve whose handle reaches far past its end's span (a rejoined S-shaped edge of a stroke,
    its extreme right at an end) keeps its shape: pulling the handle in would move the curve 25
    units off the ink. A handle a little past is still pulled in."""
    from brushwork.font.tidy import CLAMP_UNITS, _point, on_curve_extremes

    long = np.array([[766.8, 36.3], [583.8, 32.2], [727.4, 242.8], [641.3, 323.7]])
    parts = on_curve_extremes(long)
    drawn = np.concatenate([[_point(c, t) for t in np.linspace(0, 1, 33)] for c in parts])
    truth = np.array([_point(long, t) for t in np.linspace(0, 1, 401)])
    assert np.sqrt(((drawn[:, None] - truth[None]) ** 2).sum(-1)).min(1).max() <= CLAMP_UNITS
    short = np.array([[0.0, 0.0], [30.0, -0.5], [70.0, 10.0], [100.0, 20.0]])
    (kept,) = on_curve_extremes(short)
    assert kept[1, 1] == 0.0


def test_a_small_bulge_whose_handle_cannot_be_pulled_in_is_split_at_its_extreme():
    """A curve bulging 0.85 units past its end (under EXTREME_UNITS) whose handle, pulled in, would
    move it 2.9 units (over CLAMP_UNITS) is split at its extreme: two curves that keep its shape
    (within half a unit), each within its ends' span along x."""
    from brushwork.font.tidy import _point, on_curve_extremes

    curve = np.array([[448.0, 198.0], [447.0, 150.0], [454.5, 89.0], [438.0, 45.0]])
    parts = on_curve_extremes(curve)
    assert len(parts) == 2
    for c in parts:
        x = np.array([_point(c, t)[0] for t in np.linspace(0, 1, 65)])
        assert x.min() >= min(c[0, 0], c[3, 0]) - 1e-9 and x.max() <= max(c[0, 0], c[3, 0]) + 1e-9
    drawn = np.concatenate([[_point(c, t) for t in np.linspace(0, 1, 65)] for c in parts])
    truth = np.array([_point(curve, t) for t in np.linspace(0, 1, 401)])
    assert np.sqrt(((drawn[:, None] - truth[None]) ** 2).sum(-1)).min(1).max() < 0.5     # within rounding


def test_no_curve_of_the_otf_bulges_past_its_ends(fonts):
    """Every curve of every glyph keeps within its end points' span along x and y (its extremes
    on-curve), within half a unit of the rounding to whole units."""
    from fontTools.pens.recordingPen import DecomposingRecordingPen
    from fontTools.ttLib import TTFont

    u = np.linspace(0.0, 1.0, 65)[:, None]
    curves = 0
    with TTFont(fonts[".otf"][0]) as font:
        glyphs = font.getGlyphSet()
        for c in CHARS:
            pen = DecomposingRecordingPen(glyphs)
            glyphs[font.getBestCmap()[ord(c)]].draw(pen)
            here = None
            for op, args in pen.value:
                if op == "curveTo":
                    p = np.array([here, *args], dtype=float)
                    drawn = ((1 - u) ** 3 * p[0] + 3 * (1 - u) ** 2 * u * p[1] + 3 * (1 - u) * u * u * p[2]
                             + u ** 3 * p[3])
                    lo, hi = np.minimum(p[0], p[3]) - 0.5, np.maximum(p[0], p[3]) + 0.5
                    assert ((drawn >= lo) & (drawn <= hi)).all(), (c, p)
                    curves += 1
                if args:
                    here = args[-1]
    assert curves > 10 * len(CHARS)


def test_the_ufo_compiles_with_ufo2ft(fonts, tmp_path):
    """The UFO opens with ufoLib2 and ufo2ft compiles it to an OTF the Sanitizer accepts."""
    ufo_lib = pytest.importorskip("ufoLib2")
    ufo2ft = pytest.importorskip("ufo2ft")
    pytest.importorskip("ots")
    from brushwork.font.check import sanitize

    otf = ufo2ft.compileOTF(ufo_lib.Font.open(fonts[".ufo"][0]))
    otf.save(tmp_path / "from_ufo.otf")
    assert sanitize(tmp_path / "from_ufo.otf") is None
    assert {ord(c) for c in CHARS} <= set(otf.getBestCmap())


@pytest.fixture(scope="module")
def variable(tmp_path_factory):
    """SIMPLE as a variable font, CFF2 and gvar (the masters written once, then cached)."""
    folder = tmp_path_factory.mktemp("variable")
    out = {}
    for ext in (".otf", ".ttf", ".woff2"):
        res = build_font(SIMPLE, folder / f"v{ext}", variable=True)
        assert not res.failed
        out[ext] = folder / f"v{ext}"
    return out


@pytest.mark.parametrize("ext", [".otf", ".ttf", ".woff2"])
def test_variable_font_has_a_weight_axis_of_compatible_masters(variable, ext):
    """CFF2 in the OTF and its WOFF2, gvar in the TTF with every glyph flagged as overlapping; a
    wght axis from 300 to 700 whose default is the style as it is (400); the Sanitizer accepts it;
    each stroke is a contour of its own (overlaps kept)."""
    pytest.importorskip("ots")
    from fontTools.ttLib import TTFont

    from brushwork.font.check import sanitize
    from brushwork.glyphs import load_source

    assert sanitize(variable[ext]) is None
    strokes = {c: len(g.strokes) for c, g in load_source("default", SIMPLE).items()}
    with TTFont(variable[ext]) as font:
        (axis,) = font["fvar"].axes
        assert (axis.axisTag, axis.minValue, axis.defaultValue, axis.maxValue) == ("wght", 300, 400, 700)
        assert ("glyf" if ext == ".ttf" else "CFF2") in font and ("gvar" in font) == (ext == ".ttf")
        for c in SIMPLE:
            name = font.getBestCmap()[ord(c)]
            if ext == ".ttf":
                glyph = font["glyf"][name]
                assert glyph.numberOfContours == strokes[c] and glyph.flags[0] & 0x40
            else:
                from fontTools.pens.recordingPen import RecordingPen

                pen = RecordingPen()
                font.getGlyphSet()[name].draw(pen)
                assert sum(op == "closePath" for op, _ in pen.value) == strokes[c]


@pytest.mark.parametrize("ext", [".otf", ".ttf"])
def test_variable_instances_draw_the_brush_at_their_press(variable, ext):
    """FreeType's raster of the instances at the axis's two ends and its middle (300, 500, 700)
    against the brush writing each character at the press they stand for: IoU >= 0.965 (the
    outlines are fitted within 0.5 px on average, a rim that is 3% of the light master's 12-18 px
    strokes; `brushwork bench font` finds 0.967 at worst for the regular); HarfBuzz shapes every
    code point to its own glyph at each."""
    pytest.importorskip("uharfbuzz")
    from brushwork.writing import text_paper
    from brushwork.font.check import freetype_coverage, iou, shaped_glyphs, shifted
    from brushwork.font.outline import placement
    from brushwork.font.trace import ink_coverage, ink_mask
    from brushwork.font.variable import master_style, press_factor, stroke_edges
    from brushwork.glyphs import load_source
    from brushwork.writing import Style

    glyphs, kai = load_source("default", SIMPLE), Style.load("kai")
    # the font centres every master as it centres the regular one's strokes
    shifts = {c: placement([e for e in stroke_edges(glyphs[c], 512, kai, 0, "geometry") if e is not None], 512)
              for c in SIMPLE}
    for w in (300, 500, 700):
        assert shaped_glyphs(variable[ext], SIMPLE, wght=w) == [f"uni{ord(c):04X}" for c in SIMPLE]
        for c in SIMPLE:
            paper = text_paper([glyphs[c]], 512, master_style(kai, press_factor(w)), ink="geometry")
            ink = ink_mask(shifted(ink_coverage(paper.image()), shifts[c]))
            assert iou(ink, freetype_coverage(variable[ext], c, Em(), wght=w) >= 0.5) >= 0.965, (w, c)


def test_a_hair_out_and_back_is_dropped():
    """Two segments that go out and come back enclosing under a unit of width are no ink: tidy
    drops them and the contour goes on from where they left it."""
    from fontTools.pens.recordingPen import RecordingPen

    from brushwork.font.tidy import tidy

    rec = RecordingPen()
    rec.moveTo((0, 0))
    rec.lineTo((100, 0))
    rec.curveTo((103, 0.2), (109, 0.2), (113, 0.3))       # a hair 13 units long
    rec.curveTo((109, 0.1), (104, 0.1), (100.2, 0.1))      # ... and back
    rec.lineTo((100, 100))
    rec.lineTo((0, 100))
    rec.closePath()
    ops = [(op, args) for op, args in tidy(rec).value]
    assert [op for op, _ in ops] == ["moveTo", "lineTo", "lineTo", "lineTo", "closePath"]
    assert ops[2][1] == ((100.0, 100.0),)


def test_a_contour_that_is_a_hair_or_a_speck_is_dropped():
    from fontTools.pens.recordingPen import RecordingPen

    from brushwork.font.tidy import tidy

    rec = RecordingPen()
    for shape in (((0, 0), (100, 0), (100, 100), (0, 100)), ((200, 0), (213, 0.4), (200, 0.7)),
                  ((300, 0), (303, 0), (303, 3), (300, 3))):
        rec.moveTo(shape[0])
        for p in shape[1:]:
            rec.lineTo(p)
        rec.closePath()
    assert [op for op, _ in tidy(rec).value] == ["moveTo", "lineTo", "lineTo", "lineTo", "closePath"]


def test_the_fit_cuts_at_the_extremes_with_level_handles():
    """A tilted ellipse is cut at its four x and y extremes: no curve bulges past its ends along x
    or y by more than a tenth of a pixel, and the handles at each extreme are level or plumb."""
    from brushwork.font.fit import _bezier, fit_closed

    a = np.linspace(0, 2 * np.pi, 700, endpoint=False)
    x, y = 60 * np.cos(a), 25 * np.sin(a)
    t = np.radians(20)
    ellipse = np.stack([100 + x * np.cos(t) - y * np.sin(t), 100 + x * np.sin(t) + y * np.cos(t)], axis=1)
    curves = fit_closed(ellipse, 0.25, 0.5)
    u = np.linspace(0, 1, 101)[:, None]
    for c in curves:
        drawn = _bezier(c, u[:, 0])
        lo, hi = np.minimum(c[0], c[3]) - 0.1, np.maximum(c[0], c[3]) + 0.1
        assert ((drawn >= lo) & (drawn <= hi)).all(), c
    tops = [c for c in curves if abs(c[0, 1] - ellipse[:, 1].max()) < 0.5]
    assert tops and all(abs(c[1, 1] - c[0, 1]) < 1e-9 for c in tops)


EXTREMES = "狐宰"      # of bench font's 60 characters, the widest ink and the tallest


def _font_box(path, char) -> tuple:
    from fontTools.pens.boundsPen import BoundsPen
    from fontTools.ttLib import TTFont

    with TTFont(path) as font:
        glyphs = font.getGlyphSet()
        pen = BoundsPen(glyphs)
        glyphs[font.getBestCmap()[ord(char)]].draw(pen)
        return pen.bounds


def test_the_ink_is_centred_in_the_em_and_the_extremes_are_whole(tmp_path):
    """The widest and the tallest glyph of a set (of bench font's 60 characters, 3.7 mm from the
    paper's left edge and 3.6 mm from its top): each glyph's ink box centred in the em box (side bearings equal, as much room above the middle as
    below, within the whole pixel placement moves by and the fit's stray), inside the em, and as
    wide and tall as the brush's ink (the geometry's own loops, which the render clips) to within
    the fit's stray: nothing cut off."""
    from brushwork.font.fit import MAX_RATIO
    from brushwork.font.outline import FIT_TOL_PX
    from brushwork.glyphs import load_source
    from brushwork.writing import text_paper

    path = tmp_path / "x.otf"
    assert not build_font(EXTREMES, path, jobs=1).failed
    em, glyphs = Em(), load_source("default", EXTREMES)
    unit = em.upm / em.size                                # font units a px
    stray = MAX_RATIO * FIT_TOL_PX * unit
    middle = (em.upm / 2, (em.ascender + (em.ascender - em.upm)) / 2)
    for c in EXTREMES:
        paper = text_paper([glyphs[c]], em.size, ink="geometry")
        loops = np.concatenate(paper.outlines()) * (em.upm / paper.width_mm)
        x0, y0, x1, y1 = _font_box(path, c)
        assert (x1 - x0, y1 - y0) == pytest.approx(tuple(np.ptp(loops, axis=0)), abs=2 * stray), c
        assert ((x0 + x1) / 2, (y0 + y1) / 2) == pytest.approx(middle, abs=unit / 2 + stray), c
        assert x0 > 0 and x1 < em.upm and y0 > em.ascender - em.upm and y1 < em.ascender, c


def test_exact_loops_are_fitted_with_few_curves_their_corners_kept():
    """A disc and a square as a VectorPaper's loops give them (mm, outer counter-clockwise): the
    disc in four curves meeting at its extremes, enclosing pi r^2; the square's four corners are
    points of its outline, and its area is kept."""
    from brushwork.font.build import clean_outline, _area
    from brushwork.font.outline import fit_edges, loop_edges

    em = Em(512)
    a = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
    disc = np.stack([50 + 30 * np.cos(a), 50 + 30 * np.sin(a)], axis=1)
    square = np.array([[20.0, 20.0], [80.0, 20.0], [80.0, 80.0], [20.0, 80.0]])
    units2 = (em.upm / 100.0) ** 2
    (c,) = fit_edges(loop_edges([disc], 100.0, em.size), em)
    assert len(c) == 4
    assert abs(_area(clean_outline([c]))) == pytest.approx(np.pi * 30 ** 2 * units2, rel=0.005)
    (s,) = fit_edges(loop_edges([square], 100.0, em.size), em)
    ends = {tuple(np.round(p, 3)) for p in s[:, 0]}
    want = {tuple(np.round(em.to_font(np.array([x, 100.0 - y]) * 5.12), 3)) for x, y in square}
    assert want <= ends
    assert abs(_area(clean_outline([s]))) == pytest.approx(60 * 60 * units2, rel=0.002)


def test_gl_ink_is_traced_and_cached_apart(tmp_path):
    """`--ink gl` builds the font from the GL render's traced edge: another cache folder, the same
    character's glyph within the traced route's fidelity of the geometry route's."""
    pytest.importorskip("ots")
    from brushwork.font.check import sanitize

    geo = build_font("十", tmp_path / "g.otf", jobs=1)
    gl = build_font("十", tmp_path / "t.otf", jobs=1, ink="gl")
    assert (geo.ink, gl.ink) == ("geometry", "gl") and gl.made == ["十"]
    assert len(list((tmp_path / CACHE_DIR).iterdir())) == 2
    assert sanitize(tmp_path / "t.otf") is None
    assert _glyph_area(tmp_path / "t.otf", "十") == pytest.approx(_glyph_area(tmp_path / "g.otf", "十"), rel=0.03)


def test_a_flat_curve_is_stored_as_a_line_and_a_bent_one_is_not():
    """A curve whose handles lie on its chord becomes a line (one point, not three); one whose
    handles stand off it stays a curve; a line back to the start is left to closePath."""
    from fontTools.pens.recordingPen import RecordingPen

    from brushwork.font.tidy import tidy

    rec = RecordingPen()
    rec.moveTo((0, 0))
    rec.curveTo((30, 0.2), (60, -0.2), (90, 0))        # flat: a line
    rec.curveTo((100, 30), (100, 60), (90, 90))        # bent: a curve (cut at its x extreme)
    rec.curveTo((60, 90.1), (30, 89.9), (0, 90))       # flat
    rec.curveTo((0, 60.2), (0.1, 29.9), (0, 0))        # flat, back to the start
    rec.closePath()
    ops = [op for op, _ in tidy(rec).value]
    assert ops == ["moveTo", "lineTo", "curveTo", "curveTo", "lineTo", "closePath"]


def test_lines_that_go_on_in_one_direction_are_one_line():
    """Two lines in a row along one direction (within half a unit) are stored as one; a line that
    turns is kept."""
    from fontTools.pens.recordingPen import RecordingPen

    from brushwork.font.tidy import tidy

    rec = RecordingPen()
    rec.moveTo((0, 0))
    rec.lineTo((40, 0.3))
    rec.lineTo((90, 0))            # on in the same direction: merged
    rec.lineTo((90, 90))           # turns: kept
    rec.lineTo((0, 90))
    rec.closePath()
    assert [(op, args[-1] if args else None) for op, args in tidy(rec).value] == [
        ("moveTo", (0.0, 0.0)), ("lineTo", (90.0, 0.0)), ("lineTo", (90.0, 90.0)), ("lineTo", (0.0, 90.0)),
        ("closePath", None)]


def test_a_master_curve_whose_handles_round_onto_its_ends_still_merges():
    """A weight master in which one stroke's curve has its handles on its ends (a line, if its
    charstring were specialized) merges with the others curve for curve into a CFF2 font."""
    from fontTools.pens.recordingPen import RecordingPen

    from brushwork.font import FontInfo
    from brushwork.font.variable import MASTERS, make_variable

    def box(r, flat=False):
        c = np.array([[[500 - r, 380], [500 - r, 380 - r], [500 - r, 380 - r], [500, 380 - r]],
                      [[500, 380 - r], [500 + r, 380 - r], [500 + r, 380 - r], [500 + r, 380]],
                      [[500 + r, 380], [500 + r, 380 + r], [500 + r, 380 + r], [500, 380 + r]],
                      [[500, 380 + r], [500 - r, 380 + r], [500 - r, 380 + r], [500 - r, 380]]], dtype=float)
        if flat:
            c[1, 1], c[1, 2] = c[1, 0], c[1, 3]       # handles on the ends
        return [c]

    masters = {w: {"十": box(100 + w / 10, flat=(w == 500))} for w in MASTERS}
    vf = make_variable(masters, FontInfo(), cff=True)
    pen = RecordingPen()
    vf.getGlyphSet()["uni5341"].draw(pen)
    assert [op for op, _ in pen.value].count("curveTo") == 4
