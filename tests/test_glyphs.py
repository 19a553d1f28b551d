"""Glyph trajectories: our JSON format, the Make Me a Hanzi and KanjiVG importers, SVG paths,
stroke-type inference, and a clear GlyphError ("FILE: problem") for every kind of bad input."""
import json
import math
import re
import shutil
from importlib import metadata
from pathlib import Path

import numpy as np
import pytest

from brushwork.glyphs import (STROKE_TYPES, Glyph, GlyphError, Stroke, infer_stroke_type, load_glyph, load_source,
                              parse_svg_path, save_glyph)
from brushwork.glyphs.jsonfmt import schema

ROOT = Path(__file__).resolve().parent.parent
GLYPHS = ROOT / "glyphs"
DATA = Path(__file__).resolve().parent / "data"
GRAPHICS = DATA / "mmah" / "graphics.txt"
KANJIVG = DATA / "kanjivg"


def glyph_doc(**over):
    doc = {"format": "brushwork-glyph", "version": 1, "char": "十", "codepoint": 0x5341, "em_box": [0, 0, 100, 100],
           "y_down": True, "strokes": [{"kind": "㇐", "points": [[10, 40], [90, 40]]},
                                       {"kind": "㇑", "points": [[50, 10], [50, 90]]}]}
    doc.update(over)
    return doc


def write(tmp_path, doc, name="U+5341.json"):
    path = tmp_path / name
    path.write_text(doc if isinstance(doc, str) else json.dumps(doc, ensure_ascii=False), encoding="utf-8")
    return path


def test_stroke_types_are_the_cjk_strokes_block():
    assert sorted(STROKE_TYPES) == [chr(c) for c in range(0x31C0, 0x31E4)]
    assert STROKE_TYPES["㇐"] == "horizontal (heng)"


def test_examples_load_and_follow_the_schema():
    files = sorted(GLYPHS.glob("U+*.json"))
    chars = "".join(load_glyph(f).char for f in files)
    assert set("一十人大永和九年") <= set(chars)
    assert json.loads((GLYPHS / "schema.json").read_text()) == schema()   # the shipped copy is the same
    assert (GLYPHS / "ARPHICPL.TXT").is_file()
    jsonschema = pytest.importorskip("jsonschema")
    validator = jsonschema.Draft202012Validator(schema())
    jsonschema.Draft202012Validator.check_schema(schema())
    for f in files:
        assert not list(validator.iter_errors(json.loads(f.read_text()))), f.name
    # and the schema rejects what the hand checks reject
    bad = glyph_doc(strokes=[{"kind": "㇐", "d": "M 0 0 L 1 1", "pressure": [1, 1]}])
    assert list(validator.iter_errors(bad))


def test_yong_example_matches_the_mmah_data():
    ours = load_glyph(GLYPHS / "U+6C38.json")
    mmah = load_source(f"mmah:{GRAPHICS}", "永")["永"]
    assert [s.kind for s in ours.strokes] == ["㇔", "㇆", "㇇", "㇒", "㇏"]
    for a, b in zip(ours.strokes, mmah.strokes):
        np.testing.assert_allclose(a.points, b.points, atol=1e-9)
        assert a.outline == b.outline


def test_save_load_round_trip(tmp_path):
    k = 4
    pts = np.array([[0.1, 0.5], [0.4, 0.52], [0.7, 0.51], [0.9, 0.5]])
    strokes = [Stroke(pts, "㇐", pressure=np.linspace(0.2, 0.8, k), tilt_deg=np.full(k, 15.0),
                      speed=np.array([0.5, 1.0, 1.5, 0.7])),
               Stroke(np.array([[0.5, 0.9], [0.5, 0.1]]), "㇑", outline="M 1 2 L 3 4 Z")]
    for box, y_down in (((0, -124, 1024, 900), False), ((0, 0, 109, 109), True)):
        g = Glyph("十", 0x5341, strokes, "test", box, y_down, {"source": "unit test"})
        path = tmp_path / "U+5341.json"
        save_glyph(g, path)
        back = load_glyph(path)
        assert (back.char, back.em_box, back.source_y_down) == ("十", tuple(map(float, box)), y_down)
        assert back.source == f"glyphs:{path}" and back.metadata == {"source": "unit test"}
        for a, b in zip(strokes, back.strokes):
            np.testing.assert_allclose(b.points, a.points, atol=1e-6)
            assert b.kind == a.kind and b.outline == a.outline
            for name in ("pressure", "tilt_deg", "speed"):
                want, got = getattr(a, name), getattr(b, name)
                assert (want is None) == (got is None)
                if want is not None:
                    np.testing.assert_allclose(got, want, atol=1e-6)
        assert [p.name for p in tmp_path.iterdir()] == ["U+5341.json"]   # no temporary file left


def test_d_paths_and_missing_kinds(tmp_path):
    doc = glyph_doc(strokes=[{"d": "M 10 40 h 80"}, {"kind": "㇑", "d": "M50,10 C50,40 50,60 50,90"}])
    g = load_glyph(write(tmp_path, doc))
    assert [s.kind for s in g.strokes] == ["㇐", "㇑"]          # the first one inferred
    np.testing.assert_allclose(g.strokes[0].points, [[0.1, 0.6], [0.9, 0.6]])
    np.testing.assert_allclose(g.strokes[1].points[[0, -1]], [[0.5, 0.9], [0.5, 0.1]])


def test_mmah_mapping_puts_points_where_the_readme_says():
    g = load_source(f"mmah:{GRAPHICS}", "永")["永"]
    assert g.em_box == (0.0, -124.0, 1024.0, 900.0) and not g.source_y_down
    first = json.loads(GRAPHICS.read_text(encoding="utf-8").splitlines()[-1])   # 永 is the last line
    assert first["character"] == "永"
    x, y = first["medians"][0][0]                                    # [428, 824]
    u, v = g.strokes[0].points[0]
    assert (u, v) == pytest.approx((x / 1024, (y + 124) / 1024))
    n = 512                                                          # the data's SVG recipe at N px
    assert (u * n, (1 - v) * n) == pytest.approx((x * n / 1024, (900 - y) * n / 1024))
    np.testing.assert_allclose(g.from_em(g.strokes[0].points), first["medians"][0])
    assert g.strokes[0].outline == first["strokes"][0]
    np.testing.assert_allclose(g.to_em([[0, 900], [1024, -124]]), [[0, 1], [1, 0]])


def test_mmah_source_kinds_and_hanzi_writer_folder(tmp_path):
    glyphs = load_source(f"mmah:{GRAPHICS}")
    assert set(glyphs) == set("永和它凡明")
    kinds = {c: "".join(s.kind for s in g.strokes) for c, g in glyphs.items()}
    assert kinds["永"] == "㇔㇆㇇㇒㇏"
    assert kinds["和"] == "㇒㇐㇑㇒㇔㇑㇕㇐"
    assert kinds["明"] == "㇑㇕㇐㇐㇓㇆㇐㇐"
    assert kinds["它"] == "㇔㇑㇖㇒㇟"
    for line in GRAPHICS.read_text(encoding="utf-8").splitlines():   # hanzi-writer-data: <char>.json
        doc = json.loads(line)
        write(tmp_path, {"strokes": doc["strokes"], "medians": doc["medians"], "radStrokes": [0]},
              f"{doc['character']}.json")
    folder = load_source(f"mmah:{tmp_path}", "和永")
    assert list(folder) == ["和", "永"]
    np.testing.assert_allclose(folder["永"].strokes[1].points, glyphs["永"].strokes[1].points)
    assert set(load_source(f"mmah:{tmp_path}")) == set("永和它凡明")


def test_parse_svg_path_commands():
    (square,) = parse_svg_path("M0,0 L10,0 l0,10 h-10 V5 z")
    np.testing.assert_allclose(square, [[0, 0], [10, 0], [10, 10], [0, 10], [0, 5], [0, 0]])
    (implicit,) = parse_svg_path("m1 1 2 0 0 2")                     # implicit relative lineto
    np.testing.assert_allclose(implicit, [[1, 1], [3, 1], [3, 3]])
    (c,) = parse_svg_path("M0 0C0 10 10 10 10 0")
    assert c[0].tolist() == [0, 0] and c[-1].tolist() == [10, 0] and len(c) > 8
    assert np.abs(c[:, 1].max() - 7.5) < 0.05                          # the cubic's peak
    (rc,) = parse_svg_path("M0 0c0 10 10 10 10 0s10 -10 10 0")       # relative, smooth continuation
    assert rc[-1].tolist() == [20, 0] and rc[:, 1].min() == pytest.approx(-7.5, abs=0.05)
    (q,) = parse_svg_path("M0 0Q5 10 10 0T20 0")
    assert q[:, 1].max() == pytest.approx(5, abs=0.05) and q[:, 1].min() == pytest.approx(-5, abs=0.05)
    two = parse_svg_path("M0 0L1 1ZM5 5 6 6")
    assert len(two) == 2 and two[0][-1].tolist() == [0, 0]
    (packed,) = parse_svg_path("M45.5,13.25c5.12-2.4.5.5,10.75,9")   # numbers run together, as KanjiVG writes
    assert packed[-1] == pytest.approx([56.25, 22.25])
    assert parse_svg_path("") == []


@pytest.mark.parametrize("d, problem", [
    ("L 1 2", "must start with M"),
    ("M 1", "M needs a multiple of 2 numbers, got 1"),
    ("M 1 2 C 3 4 5", "C needs a multiple of 6"),
    ("M 1 2 X 3 4", "unexpected character 'X'"),
    ("M 1 2 L nan 3", "unexpected character 'n'"),
    ("M 0 0 A 5 5 0 0 1 10 10", "arc commands"),
    ("M 0 0 L 1e999 0", "beyond the limit"),
        ("M 0 0 L 1e300 0", "beyond the limit"),
])
def test_parse_svg_path_rejects_malformed_data(d, problem):
    with pytest.raises(GlyphError, match="svg path: .*" + problem):
        parse_svg_path(d)


def test_kanjivg_file_variant_and_inference():
    g = load_source(f"kanjivg:{KANJIVG}", "人")["人"]
    assert g.source == f"kanjivg:{KANJIVG / '04eba.svg'}" and g.source_y_down and g.em_box == (0, 0, 109, 109)
    assert [s.kind for s in g.strokes] == ["㇒", "㇏"]                # "㇏a" normalised
    np.testing.assert_allclose(g.strokes[0].points[0], [54.5 / 109, 1 - 10 / 109])
    np.testing.assert_allclose(g.strokes[1].points[-1], [95 / 109, 1 - 88 / 109])
    kai = load_source(f"kanjivg:{KANJIVG}#Kaisho", "人")["人"]
    assert kai.source.endswith("04eba-Kaisho.svg")
    assert [s.kind for s in kai.strokes] == ["㇒", "㇏"]              # "㇒/㇓" -> ㇒; the second inferred
    assert load_source(f"kanjivg:{KANJIVG}", "人", variant="Gyosho")["人"].source.endswith("04eba.svg")
    assert list(load_source(f"kanjivg:{KANJIVG}")) == ["人"]


@pytest.mark.skipif(not any(d.metadata["Name"] == "kanjivg" for d in metadata.distributions()),
                    reason="the optional kanjivg package is not installed")
def test_kanjivg_package():
    g = load_source("kanjivg", "永")["永"]
    assert len(g.strokes) == 5 and g.strokes[0].kind == "㇔"


def em_line(*pts):
    """A polyline through em points, densified (2 mm-ish steps) like a flattened curve."""
    pts = np.array(pts, float)
    return np.concatenate([np.linspace(a, b, 8, endpoint=False) for a, b in zip(pts[:-1], pts[1:])] + [pts[-1:]])


@pytest.mark.parametrize("kind, pts", [
    ("㇐", [(0.1, 0.5), (0.9, 0.53)]),
    ("㇑", [(0.5, 0.9), (0.5, 0.1)]),
    ("㇒", [(0.7, 0.8), (0.2, 0.3)]),
    ("㇏", [(0.3, 0.8), (0.8, 0.3)]),
    ("㇔", [(0.45, 0.6), (0.52, 0.53)]),
    ("㇀", [(0.2, 0.3), (0.45, 0.5)]),
    ("㇕", [(0.2, 0.8), (0.8, 0.8), (0.78, 0.2)]),
    ("㇆", [(0.2, 0.8), (0.8, 0.8), (0.78, 0.15), (0.68, 0.2)]),
    ("㇖", [(0.1, 0.7), (0.85, 0.72), (0.78, 0.64)]),
    ("㇇", [(0.2, 0.8), (0.6, 0.8), (0.25, 0.35)]),
    ("㇗", [(0.3, 0.8), (0.3, 0.3), (0.8, 0.3)]),
    ("㇚", [(0.5, 0.9), (0.5, 0.15), (0.4, 0.2)]),
    ("㇙", [(0.4, 0.8), (0.4, 0.3), (0.5, 0.4)]),
    ("㇟", [(0.3, 0.8), (0.3, 0.2), (0.85, 0.2), (0.86, 0.3)]),
    ("㇈", [(0.2, 0.8), (0.6, 0.8), (0.6, 0.3), (0.9, 0.25), (0.92, 0.35)]),
    ("㇉", [(0.3, 0.8), (0.3, 0.6), (0.7, 0.6), (0.68, 0.15), (0.58, 0.2)]),
    ("㇜", [(0.4, 0.8), (0.2, 0.5), (0.6, 0.55)]),
    ("㇛", [(0.5, 0.8), (0.3, 0.5), (0.6, 0.3)]),
])
def test_infer_stroke_type_from_shapes(kind, pts):
    assert infer_stroke_type(em_line(*pts)) == kind
    # an entry tick (the brush's press before the stroke) does not change the type
    p = em_line(*pts)
    d = p[1] - p[0]
    entry = p[0] - 0.03 * np.array([d[1], -d[0]]) / np.hypot(*d) - 0.01 * d / np.hypot(*d)
    if kind not in ("㇔", "㇀"):
        assert infer_stroke_type(np.vstack([entry, p])) == kind


def test_example_kinds_agree_with_inference():
    """The hand-made examples name their kinds; the inference finds the same ones (九's first is its ㇓ form)."""
    for f in sorted(GLYPHS.glob("U+*.json")):
        g = load_glyph(f)
        got = [infer_stroke_type(s.points) for s in g.strokes]
        want = [s.kind for s in g.strokes]
        assert [{"㇓": "㇒"}.get(k, k) for k in got] == want, f.name


# -- bad input: every case names the file and the problem ------------------------------------------

@pytest.mark.parametrize("doc, problem", [
    ("{\"format\": ", "malformed JSON: Expecting value at line 1 column 12"),
    (glyph_doc(strokes=[{"kind": "㇐", "points": [[0, 0], [1, 1], [float("nan"), 2]]}]), "strokes[0].points[2]: NaN"),
    (glyph_doc(strokes=[{"kind": "㇐", "points": []}]), "strokes[0].points: empty stroke"),
    (glyph_doc(strokes=[{"kind": "㇐", "points": [[3, 3], [3, 3]]}]), "strokes[0].points: empty stroke"),
    (glyph_doc(strokes=[{"kind": "㇐", "d": "M 0 0 L 5"}]), "strokes[0].d: svg path: L needs a multiple of 2"),
    (glyph_doc(strokes=[{"kind": "㇐", "d": "M 3 3"}]), "strokes[0].d: empty stroke"),
    (glyph_doc(strokes=[{"kind": "㇐", "points": [[0, 0], [1, 1]], "pressure": [0.5]}]),
     "strokes[0].pressure: expected a list of 2 numbers"),
    (glyph_doc(strokes=[{"kind": "㇐", "d": "M0 0 L1 1", "speed": [1, 1]}]), "strokes[0].speed: only allowed with 'points'"),
    (glyph_doc(strokes=[{"kind": "X", "points": [[0, 0], [1, 1]]}]), "strokes[0].kind: 'X' is not a CJK stroke"),
    (glyph_doc(strokes=[{"kind": "㇐", "points": [[0, 0], [1, 1]], "width": 3}]), "strokes[0]: unknown field 'width'"),
    (glyph_doc(strokes=[{"kind": "㇐", "points": [[0, 0], [1, 1]], "outline": "M 0 0 Q 1"}]),
     "strokes[0].outline: svg path: Q needs"),
    (glyph_doc(strokes=[]), "strokes: expected a non-empty list"),
    (glyph_doc(codepoint=1), "codepoint: 1 is not ord"),
    (glyph_doc(em_box=[0, 0, 0, 100]), "em_box: needs x1 > x0"),
    (glyph_doc(version=2), "version: this brushwork reads version 1"),
    (glyph_doc(format="svg"), "format: expected 'brushwork-glyph'"),
])
def test_bad_glyph_files(tmp_path, doc, problem):
    path = write(tmp_path, doc)
    with pytest.raises(GlyphError) as err:
        load_glyph(path)
    assert str(err.value).startswith(f"{path}: ") and problem in str(err.value), str(err.value)
    assert isinstance(err.value, ValueError)


def test_bad_mmah_input(tmp_path):
    lines = GRAPHICS.read_text(encoding="utf-8").splitlines()
    doc = json.loads(lines[0])
    nan = dict(doc, medians=[[[1, 2], [float("nan"), 3]]] + doc["medians"][1:])
    empty = dict(doc, medians=[[[5, 5]]] + doc["medians"][1:])
    outline = dict(doc, strokes=["M 1 2 L 3 4 K"] + doc["strokes"][1:])
    for bad, problem in ((nan, "medians[0][1]: NaN"), (empty, "medians[0]: empty stroke"),
                         (outline, "strokes[0]: svg path: unexpected character 'K'")):
        path = write(tmp_path, json.dumps(bad, ensure_ascii=False) + "\n", "graphics.txt")
        with pytest.raises(GlyphError, match=f"^{path}: line 1: " + problem.replace("[", r"\[").replace("]", r"\]")):
            load_source(f"mmah:{path}")
    path = write(tmp_path, lines[1] + "\n{\"character\": \"凡\", oops\n", "graphics.txt")
    with pytest.raises(GlyphError, match=f"^{path}: line 2: malformed JSON"):
        load_source(f"mmah:{path}")
    errors = []                                   # collected instead: the good glyph still loads
    got = load_source(f"mmah:{path}", errors=errors)
    assert len(got) == 1 and len(errors) == 1 and "line 2" in str(errors[0])
    write(tmp_path, "{not json", "永.json")
    with pytest.raises(GlyphError, match=f"^{tmp_path / '永.json'}: malformed JSON"):
        load_source(f"mmah:{tmp_path}", "永")


def test_unknown_characters_and_sources(tmp_path):
    with pytest.raises(GlyphError, match=f"^{GRAPHICS}: no glyph for 'X' \\(U\\+0058\\)"):
        load_source(f"mmah:{GRAPHICS}", "永X")
    with pytest.raises(GlyphError, match=f"^{GLYPHS}: no glyph for '龍'"):
        load_source(f"glyphs:{GLYPHS}", "永龍")
    with pytest.raises(GlyphError, match=f"^{KANJIVG}: no glyph for '永'"):
        load_source(f"kanjivg:{KANJIVG}", "永")
    errors = []
    assert list(load_source(f"glyphs:{GLYPHS}", "永龍", errors=errors)) == ["永"] and len(errors) == 1
    with pytest.raises(GlyphError, match="^fontforge: unknown source"):
        load_source("fontforge")
    with pytest.raises(GlyphError, match="no such file or folder"):
        load_source(f"mmah:{tmp_path / 'nothing.txt'}")
    shutil.copy(GLYPHS / "U+6C38.json", tmp_path / "U+548C.json")   # 永 in 和's file
    with pytest.raises(GlyphError, match="holds '永', but its name says '和'"):
        load_source(f"glyphs:{tmp_path}", "和")


def test_a_chain_of_sources_takes_each_character_from_the_first_that_has_it(tmp_path):
    chain = f"kanjivg:{KANJIVG}+mmah:{GRAPHICS}"
    got = load_source(chain, "人永")
    assert list(got) == ["人", "永"]
    assert got["人"].source.startswith("kanjivg:") and got["永"].source == f"mmah:{GRAPHICS}"
    # in order: the same character from an earlier source wins
    mine = tmp_path / "mine+more"                   # a '+' inside a path stays in the path
    mine.mkdir()
    shutil.copy(GLYPHS / "U+6C38.json", mine / "U+6C38.json")
    both = load_source(f"glyphs:{mine}+mmah:{GRAPHICS}", "永和")
    assert both["永"].source.startswith("glyphs:") and both["和"].source.startswith("mmah:")
    # every glyph of every source, when no characters are asked for
    assert set(load_source(chain)) == set(load_source(f"mmah:{GRAPHICS}")) | {"人"}
    # a character in none of them: one error naming the chain and each source
    with pytest.raises(GlyphError, match="^" + re.escape(f"{chain}: no glyph for 'X' (U+0058) in any of kanjivg:{KANJIVG}, mmah:")):
        load_source(chain, "人X")
    errors = []
    assert list(load_source(chain, "X永", errors=errors)) == ["永"] and len(errors) == 1
    # a file a source has but cannot read is reported, not replaced by the next source's glyph
    (mine / "U+6C38.json").write_text("{not json", encoding="utf-8")
    errors = []
    assert list(load_source(f"glyphs:{mine}+mmah:{GRAPHICS}", "永和", errors=errors)) == ["和"]
    assert len(errors) == 1 and "malformed JSON" in str(errors[0])
    with pytest.raises(GlyphError, match="no such file or folder"):
        load_source(f"mmah:{GRAPHICS}+fontforge", "永")   # no source kind after '+': part of the path
    with pytest.raises(GlyphError, match="^fontforge: unknown source"):
        load_source(f"fontforge+mmah:{GRAPHICS}", "永")


def test_bad_kanjivg_files(tmp_path):
    (tmp_path / "04eba.svg").write_text("<svg><path d='M 1 2 L'/></svg", encoding="utf-8")
    with pytest.raises(GlyphError, match=f"^{tmp_path / '04eba.svg'}: malformed SVG"):
        load_source(f"kanjivg:{tmp_path}", "人")
    (tmp_path / "04eba.svg").write_text("<svg><path id='s1' d='M 1 2 L 5'/></svg>", encoding="utf-8")
    with pytest.raises(GlyphError, match=r"04eba.svg: stroke 1 \(s1\): svg path: L needs"):
        load_source(f"kanjivg:{tmp_path}", "人")
    (tmp_path / "04eba.svg").write_text("<svg><path d='M 1 2 L 1 2'/></svg>", encoding="utf-8")
    with pytest.raises(GlyphError, match="04eba.svg: stroke 1: .*empty stroke"):
        load_source(f"kanjivg:{tmp_path}", "人")


def test_stroke_and_glyph_check_their_arrays():
    with pytest.raises(GlyphError, match="points: empty stroke"):
        Stroke(np.zeros((1, 2)), "㇐")
    with pytest.raises(GlyphError, match="kind"):
        Stroke(np.eye(2), "a")
    with pytest.raises(GlyphError, match="pressure: shape"):
        Stroke(np.eye(2), "㇐", pressure=np.ones(3))
    with pytest.raises(GlyphError, match=r"points\[1\]: not finite"):
        Stroke(np.array([[0, 0], [math.inf, 1]]), "㇐")
    g = Glyph("永", 0x6C38, [], "x", (0, 0, 109, 109), True)
    xy = np.array([[10.0, 20.0], [109, 0]])
    np.testing.assert_allclose(g.from_em(g.to_em(xy)), xy)
    np.testing.assert_allclose(g.to_em(xy)[1], [1, 1])


def test_pieces_counts_a_broken_stroke_and_a_stray_dot():
    from brushwork.glyphs.score import pieces

    ref = np.zeros((512, 512), bool)
    ref[100:120, 50:450] = True                       # one horizontal stroke
    assert pieces(ref, ref) == (0, 0)
    broken = ref.copy()
    broken[:, 250:254] = False                        # a gap across it: two pieces
    assert pieces(broken, ref) == (1, 0)
    dotted = ref.copy()
    dotted[300:304, 300:304] = True                   # a stray 16 px dot: a speck too
    assert pieces(dotted, ref) == (1, 1)
    dust = ref.copy()
    dust[300, 300] = True                             # one stray pixel: fringe, not counted
    assert pieces(dust, ref) == (0, 0)
    assert pieces(np.zeros_like(ref), ref) == (0, 0)  # no ink: nothing extra
    with pytest.raises(ValueError, match="shapes differ"):
        pieces(ref[:10], ref)


def _disc(radius_px, wave_px=0.0, waves=40, size=512):
    """(size, size) bool: a disc whose radius wavers by wave_px, `waves` times round."""
    import cv2

    th = np.linspace(0.0, 2.0 * math.pi, 1440, endpoint=False)
    r = radius_px + wave_px * np.sin(waves * th)
    pts = np.stack([size / 2 + r * np.cos(th), size / 2 + r * np.sin(th)], axis=1)
    mask = np.zeros((size, size), np.uint8)
    cv2.fillPoly(mask, [np.round(pts * 16).astype(np.int32)], 1, shift=4)
    return mask.astype(bool)


def test_edge_figures_tell_a_smooth_edge_from_a_wavering_one():
    from brushwork.glyphs.score import edge_figures

    smooth, smooth_len = edge_figures(_disc(150.0))
    assert smooth < 0.3                                   # the pixel staircase and the smoothing's shrink
    assert smooth_len == pytest.approx(2 * math.pi * 150.0, rel=0.07)
    rough, rough_len = edge_figures(_disc(150.0, wave_px=2.0))
    assert rough > smooth + 0.4 and rough_len > smooth_len * 1.05
    # a waver slower than the Gaussian is shape, not roughness
    slow, _ = edge_figures(_disc(150.0, wave_px=2.0, waves=3))
    assert slow < smooth + 0.1
    # holes count: a ring has two contours, its length both circles
    ring = _disc(150.0) & ~_disc(100.0)
    assert edge_figures(ring)[1] == pytest.approx(smooth_len + edge_figures(_disc(100.0))[1], rel=0.01)
    assert edge_figures(np.zeros((64, 64), bool)) == (0.0, 0.0)


def test_a_sliver_footprint_keeps_its_centre_on_the_ink():
    # an outer loop and a hole that nearly cancel (a footprint of 1e-4 mm^2 net) have an area
    # centroid far off the ink; the driver would aim the root there (one threw it 200 mm)
    from brushwork.writing.targets import _centroid_and_width

    outer = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])          # counter-clockwise
    e, dx = 0.99995, 2e-3
    hole = (np.array([[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]]) - 0.5) * e + 0.5 + [dx, 0.0]
    centre, width, behind, ahead = _centroid_and_width([outer, hole], 0.0)
    assert np.all(centre >= 0.0) and np.all(centre <= 1.0)
    assert width == pytest.approx(1.0) and behind >= 0.0 and ahead >= 0.0
    # an ordinary footprint keeps its area centroid
    tri = np.array([[0.0, 0.0], [3.0, 0.0], [0.0, 3.0]])
    np.testing.assert_allclose(_centroid_and_width([tri], 0.0)[0], [1.0, 1.0])


def _doc(strokes, em_box=(0, 0, 1, 1)):
    return {"format": "brushwork-glyph", "version": 1, "char": "一", "codepoint": 0x4E00, "em_box": list(em_box),
            "y_down": False, "strokes": strokes}


@pytest.mark.parametrize("doc, words", [
    (_doc([{"points": [[0, 0], [1e300, -1e300]]}]), "strokes[0].points[1]: 1e+300 is beyond the limit"),
    (_doc([{"points": [[0, 0], [1, 1]]}], em_box=(-1e300, 0, 1, 1)), "em_box[0]: -1e+300 is beyond the limit"),
    (_doc([{"points": [[i / 20000, 0.5] for i in range(20001)]}]), "strokes[0].points: 20001 points, more than 10000"),
    (_doc([{"points": [[0, 0], [1, 1]]}] * 101), "strokes: 101 strokes, more than 100"),
    (_doc([{"points": [[0, 0], [3, 0.5]]}]), "strokes[0].points: a point lies more than 1 em outside"),
    (_doc([{"points": [[0, 0], [1, 1]] * 20}]), "strokes[0].points: the centreline is .* em long, more than 20"),
    (_doc([{"d": "M 0 0 " + "L 1 1 L 0 0 " * 30000}]), "strokes[0].d: svg path: 360006 characters, more than 200000"),
])
def test_glyph_limits_are_checked_as_the_file_is_read(tmp_path, doc, words):
    from brushwork.glyphs.model import MAX_POINTS, MAX_STROKES

    path = tmp_path / "U+4E00.json"
    path.write_text(json.dumps(doc), encoding="utf-8")
    with pytest.raises(GlyphError, match=re.escape(str(path)) + ": " + words.replace("[", r"\[").replace("]", r"\]").replace("+", r"\+")):
        load_glyph(path)
    described = json.dumps(schema())
    assert f"{MAX_POINTS}" in described and f"{MAX_STROKES}" in described


def test_the_two_glyph_schemas_are_the_same():
    root = Path(__file__).resolve().parents[1]
    assert (root / "glyphs" / "schema.json").read_text() == (root / "python" / "brushwork" / "glyphs" / "schema.json").read_text()
