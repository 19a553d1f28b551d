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
    """The brush's own 512 px render of each character, as `brushwork render CHAR --size 512` draws it."""
    from brushwork.writing import text_paper
    from brushwork.glyphs import load_source

    glyphs = load_source("default", CHARS)
    return {c: text_paper([glyphs[c]], 512).image() for c in CHARS}


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
    assert os2.sTypoAscender == round(0.88 * upm) and os2.fsSelection & 0x80
    assert os2.ulCodePageRange1 & (1 << 18)                 # Chinese Simplified
    assert 59 in os2.getUnicodeRanges()                      # CJK Unified Ideographs
    names = {n.nameID: n.toUnicode() for n in font["name"].names}
    assert names[1] == "Brushwork" and names[5] == "Version 1.0" and names[13]
    for c in CHARS + "\u3000":
        name = font.getBestCmap()[ord(c)]
        assert font["hmtx"][name][0] == upm and font["vmtx"][name][0] == upm
    assert font["hmtx"]["space"][0] == upm // 4


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

    for c in CHARS:
        fid = glyph_fidelity(fonts[ext][0], c, renders[c], Em())
        assert fid["stray"] <= 2.0, (c, fid)
        assert fid["iou"] >= 0.96, (c, fid)


def test_a_tight_tolerance_reproduces_the_render(tmp_path, renders):
    """Fitted within 0.05 px on average (0.2 px at most), FreeType's 512 px raster of each glyph
    matches the brush's 512 px render to IoU 0.99."""
    from brushwork.font.check import glyph_fidelity

    path = tmp_path / "tight.otf"
    build_font(SIMPLE, path, tolerance=0.05)
    for c in SIMPLE:
        assert glyph_fidelity(path, c, renders[c], Em())["iou"] >= 0.99, c


def test_outline_points_lie_on_the_em_square_the_render_spans(fonts, renders):
    """The ink's box in the render, mapped to font units, is the glyph's box in the font, within
    what the fit may stray from the ink's edge (MAX_RATIO tolerances: a thin spike cut short)
    and half a pixel of the mask's steps."""
    from fontTools.pens.boundsPen import BoundsPen
    from fontTools.ttLib import TTFont

    from brushwork.font.fit import MAX_RATIO
    from brushwork.font.outline import FIT_TOL_PX
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
        ys, xs = np.nonzero(ink_mask(ink_coverage(renders[c])))
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
    for tol in (0.1, 1.0):
        curves = fit_closed(wavy, tol, 0.5)
        drawn = np.concatenate([_bezier(c, np.linspace(0, 1, 200)) for c in curves])
        dist = np.min(np.linalg.norm(wavy[:, None, :] - drawn[None, :, :], axis=2), axis=1)
        assert dist.mean() <= tol
        counts[tol] = len(curves)
    assert counts[0.1] > counts[1.0]


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
