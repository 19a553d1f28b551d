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
    with pytest.raises(GlyphError, match=r"^default: no glyph .*brushwork\[kanjivg\]"):
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
