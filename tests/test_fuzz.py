"""Property-based tests: glyph files, style files, SVG path data and command lines, valid and
broken, end in success or one error line with exit code 2 (never a traceback, a hang or a partial
file). The generators are brushwork.bench.fuzz's, shared with `brushwork bench fuzz`."""
import json
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from brushwork import cli
from brushwork.bench import fuzz

FUZZ = settings(max_examples=150, deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])


@pytest.fixture
def folder(tmp_path):
    d = tmp_path / "fuzz"
    d.mkdir()
    return d


@FUZZ
@given(rng=st.randoms(use_true_random=False), render=st.integers(0, 9))
def test_glyph_files_load_render_or_fail_in_one_line(folder, rng, render):
    text = fuzz.glyph_json(rng)
    assert fuzz.check_glyph(cli.main, text, folder, render=render == 0) is None


@FUZZ
@given(rng=st.randoms(use_true_random=False), render=st.integers(0, 9))
def test_style_files_load_render_or_fail_in_one_line(folder, rng, render):
    text = fuzz.style_json(rng)
    assert fuzz.check_style(cli.main, text, folder, render=render == 0) is None


@settings(FUZZ, max_examples=300)
@given(rng=st.randoms(use_true_random=False))
def test_svg_paths_parse_or_fail_in_one_line(rng):
    assert fuzz.check_svg(fuzz.svg_path(rng)) is None


@settings(FUZZ, max_examples=300)
@given(d=st.text(alphabet="MmLlCcQqSsTtHhVvZzAa0123456789.-+eE ,", max_size=60))
def test_any_svg_text_parses_or_fails_in_one_line(d):
    assert fuzz.check_svg(d) is None


@settings(FUZZ, max_examples=200)
@given(rng=st.randoms(use_true_random=False))
def test_command_lines_succeed_or_fail_in_one_line(folder, rng):
    assert fuzz.check_argv(cli.main, fuzz.argv(rng), folder) is None


@settings(FUZZ, max_examples=200)
@given(args=st.lists(st.sampled_from(["render", "batch", "params", "-o", "o.png", "--size", "16", "--style",
                                      "x", "--seed", "-1", "--chars", "一", "--out", "out", "--bits", "--help"]),
                     max_size=8))
def test_token_soups_succeed_or_fail_in_one_line(folder, args):
    if "render" in args or "batch" in args:       # a command that renders does so tiny
        args = args + ["--size", "16"]
    assert fuzz.check_argv(cli.main, args, folder) is None


def test_the_checks_see_failures(folder):
    """The fuzz's verdicts are not vacuous: a traceback, a second line, a partial file are caught."""
    assert fuzz.verdict(1, "Traceback ...\n", [], folder).startswith("exit code 1")
    assert fuzz.verdict(2, "usage: x\nbrushwork: error: y\n", [], folder).startswith("not one error line")
    (folder / "o.png").write_bytes(b"\x89PNG\r\n")
    assert "partial file" in fuzz.verdict(0, "", [folder / "o.png"], folder)
    assert "left an output file" in fuzz.verdict(2, "brushwork: error: x\n", [folder / "o.png"], folder)
    assert fuzz.check_svg(12) is None                 # a GlyphError, not a traceback
    assert fuzz._load_only(lambda: [][1], ValueError).startswith("traceback: IndexError")


def test_bench_fuzz_counts_per_kind(tmp_path, capsys):
    out = tmp_path / "fuzz.json"
    assert cli.main(["bench", "fuzz", "--n", "60", "--render-every", "1000", "--json", str(out)]) == 0
    result = json.loads(out.read_text())
    assert sum(k["tried"] for k in result["kinds"].values()) == 60
    assert all(k["failed"] == 0 for k in result["kinds"].values())
    assert "| kind" in capsys.readouterr().out
