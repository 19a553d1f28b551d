"""The default source (bundled glyph files, bundled medians, KanjiVG), the medians reader and the
named charsets."""
import gzip
import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from brushwork.glyphs import GlyphError, STROKE_TYPES, load_source
from brushwork.glyphs import charsets, medians
from brushwork.glyphs import sources as glyph_sources

DATA = Path(__file__).resolve().parent / "data"
GRAPHICS = DATA / "mmah" / "graphics.txt"
KANJIVG = DATA / "kanjivg"
NOWHERE = "\U00020000"       # a CJK Extension B character: in no bundled source


def _same_strokes(a, b) -> bool:
    return len(a.strokes) == len(b.strokes) and all(
        np.array_equal(s.points, t.points) and s.kind == t.kind for s, t in zip(a.strokes, b.strokes))


def test_gb2312_charsets():
    every, one, two = charsets.gb2312(), charsets.gb2312(1), charsets.gb2312(2)
    assert (len(every), len(one), len(two)) == (6763, 3755, 3008)
    assert every == one + two and len(set(every)) == 6763
    codes = [c.encode("gb2312") for c in every]
    assert codes == sorted(codes) and every[0] == "啊" and every[-1] == "齄"
    assert all(0xB0 <= b[0] <= 0xF7 and 0xA1 <= b[1] <= 0xFE for b in codes)
    assert charsets.named("GB2312-1") == one and charsets.named("gb2312-3") is None
    assert charsets.read_charset("gb2312") == every and charsets.read_charset("gb2312-1") == one


def test_a_charset_file_named_like_a_builtin_wins(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    Path("gb2312").write_text("永 和\n", encoding="utf-8")
    assert charsets.read_charset("gb2312") == "永和"


def test_default_source_has_all_of_gb2312():
    errors: list = []
    got = load_source("default", charsets.gb2312(), errors=errors)
    assert errors == [] and len(got) == 6763
    assert list(got) == list(charsets.gb2312())
    assert all(g.strokes and all(s.kind in STROKE_TYPES for s in g.strokes) for g in got.values())


def test_default_source_order(monkeypatch, tmp_path):
    # the bundled glyph files first, the bundled medians for the rest of GB2312
    got = load_source("default", "永国")
    assert got["永"].source.startswith("glyphs:") and got["国"].source.startswith("medians:")
    # KanjiVG (a stand-in folder) comes after the medians: it gives only what they lack
    kvg = tmp_path / "kanji"
    shutil.copytree(KANJIVG, kvg)
    shutil.copy(KANJIVG / "04eba.svg", kvg / f"{ord(NOWHERE):05x}.svg")
    shutil.copy(KANJIVG / "04eba.svg", kvg / f"{ord('国'):05x}.svg")
    monkeypatch.setattr(glyph_sources, "_kanjivg_installed", lambda: True)
    monkeypatch.setattr(glyph_sources.kanjivg, "package_dir", lambda: kvg)
    got = load_source("default", "国" + NOWHERE)
    assert got["国"].source.startswith("medians:") and got[NOWHERE].source.startswith("kanjivg:")
    errors: list = []
    assert set(load_source("default", "永𠀁", errors=errors)) == {"永"}
    assert [str(e) for e in errors] == ["default: no glyph for '𠀁' (U+20001) among the bundled glyphs and "
                                        "medians or in KanjiVG"]
    # without KanjiVG, a miss says how to get it
    monkeypatch.setattr(glyph_sources, "_kanjivg_installed", lambda: False)
    with pytest.raises(GlyphError, match=r"^default: no glyph .*pip install '\.\[kanjivg\]'"):
        load_source("default", NOWHERE)


def test_bundled_medians_draw_as_mmah_does():
    # the same medians give the same strokes and inferred types through either reader
    mmah = load_source(f"mmah:{GRAPHICS}")
    bundled = load_source("medians", "".join(mmah))
    assert len(mmah) == 5
    for char, glyph in mmah.items():
        assert bundled[char].em_box == glyph.em_box and _same_strokes(bundled[char], glyph), char
        assert all(s.outline is None for s in bundled[char].strokes)
    folder = medians.bundled_path().parent
    assert (folder / "ARPHICPL.TXT").is_file() and (folder / "README.md").is_file()


def _write_medians(path: Path, lines: list[str], gz: bool) -> Path:
    data = ("\n".join(lines) + "\n").encode("utf-8")
    path.write_bytes(gzip.compress(data) if gz else data)
    return path


@pytest.mark.parametrize("gz", [True, False])
def test_medians_file(tmp_path, gz):
    heng = json.dumps({"character": "一", "medians": [[[100, 400], [900, 420]]]}, ensure_ascii=False)
    escaped = json.dumps({"character": "丨", "medians": [[[500, 800], [510, 0]]]})     # \\u4e28
    path = _write_medians(tmp_path / "m.jsonl", [heng, escaped, '{"character": "乙", "medians": [[[1, 2]]]}',
                                                 '{"medians": []}'], gz)
    got = load_source(f"medians:{path}", "丨一")
    assert list(got) == ["丨", "一"] and got["一"].strokes[0].kind == "㇐" and got["丨"].strokes[0].kind == "㇑"
    np.testing.assert_allclose(got["一"].strokes[0].points[0], [100 / 1024, 524 / 1024])
    with pytest.raises(GlyphError, match=r"m.jsonl: line 3: medians\[0\]: empty stroke"):
        load_source(f"medians:{path}", "乙")
    with pytest.raises(GlyphError, match=r"m.jsonl: no glyph for '二'"):
        load_source(f"medians:{path}", "二")
    errors: list = []
    assert set(load_source(f"medians:{path}", errors=errors)) == {"一", "丨"}
    assert sorted(str(e).split(": ")[1] for e in errors) == ["line 3", "line 4"]


def test_bad_medians_source(tmp_path):
    with pytest.raises(GlyphError, match="no such file"):
        load_source(f"medians:{tmp_path / 'none.jsonl.gz'}", "一")
    broken = tmp_path / "broken.jsonl.gz"
    broken.write_bytes(gzip.compress(b'{"character": "x"}')[:12])
    with pytest.raises(GlyphError, match="broken.jsonl.gz: cannot read"):
        load_source(f"medians:{broken}", "一")
    with pytest.raises(GlyphError, match="unknown source"):
        load_source("median", "一")


@pytest.mark.parametrize("text", ['{"a": 1}\n', "hello world\n", ""])
@pytest.mark.parametrize("kind, says", [("medians", "not a medians file"),
                                        ("mmah", "not a Make Me a Hanzi graphics.txt")])
def test_a_file_of_another_kind_is_named_so(tmp_path, text, kind, says):
    path = tmp_path / "other.json"
    path.write_text(text, encoding="utf-8")
    for spec in (f"{kind}:{path}", f"{kind}:{path}+default"):
        with pytest.raises(GlyphError, match=f"^{path}: {says}"):
            load_source(spec, "永", errors=[])


def test_an_unknown_character_is_told_a_source_that_can_help(tmp_path):
    from brushwork.glyphs.sources import add_source_hint, bundled_dir, outlines_path

    mine = f"glyphs:{bundled_dir()}"                      # 永 is a bundled file, 明 only a median
    with pytest.raises(GlyphError, match="no glyph for '明'") as err:
        load_source(mine, "明")
    hint = add_source_hint(mine)
    suggested = hint.split("--source ")[1]
    assert set(load_source(suggested, "明永")) == set("明永")
    for spec in ("default", "glyphs:x+default"):          # the bundled ones are there already
        assert "graphics.txt" not in add_source_hint(spec) and "glyphs/README.md" in add_source_hint(spec)
    assert outlines_path().is_file() and set(load_source(f"mmah:{outlines_path()}")) == set("永和它凡明")


@pytest.mark.parametrize("source, name, text", [
    ("medians:{f}", "m.txt", "[" * 100000 + "\n"),
    ("medians:{f}", "m.txt", '{"character": "永", "medians": ' + "[" * 100000 + "\n"),
    ("mmah:{f}", "g.txt", '{"character": "永", "strokes": ' + "[" * 100000 + "\n"),
    ("mmah:{d}", "永.json", "[" * 100000),
])
def test_deeply_nested_json_is_one_line_and_exit_2(tmp_path, capsys, source, name, text):
    """JSON nested 100,000 deep, wherever a source reads JSON: one line naming the file, exit 2."""
    from brushwork import cli

    (tmp_path / name).write_text(text, encoding="utf-8")
    spec = source.format(f=tmp_path / name, d=tmp_path)
    rc = cli.main(["render", "永", "--source", spec, "-o", str(tmp_path / "o.png"), "--size", "64"])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and str(tmp_path) in err, err
