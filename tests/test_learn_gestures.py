"""A learned hand carries the turn gesture: each stroke's run past corners learned from the examples."""
from pathlib import Path

import numpy as np
import pytest

from brushwork.glyphs import load_source
from brushwork.writing import Style
from brushwork.writing.hand import Hand, learn_hand
from brushwork.writing.plan import GlyphPlan, StrokePlan, Turn

DATA = Path(__file__).parent / "data" / "mmah" / "graphics.txt"


def _glyph_plan(glyph, reach: float) -> GlyphPlan:
    ctl = {"along": [8.5] * 5, "across": [0.0] * 5, "press": [0.25] * 5, "tilt": [15.0], "azimuth": [0.0],
           "twist": [0.0], "speed": [0.5]}
    return GlyphPlan(glyph.char, [StrokePlan(dict(ctl), 1.0, -0.5, turn=Turn(1.0, 0.0, reach))
                                  for _ in glyph.strokes])


def test_a_hand_learns_the_turns_run_past_corners_and_keeps_it_in_its_file(tmp_path):
    st = Style.load("kai")
    glyphs = load_source(f"mmah:{DATA}", "凡和它明永")
    hand = learn_hand([(g, _glyph_plan(g, 3.25)) for g in glyphs.values()], st)
    hand.save(tmp_path / "hand.json")
    planned = Hand.load(tmp_path / "hand.json").plan(glyphs["永"], st)
    assert [p.turn.reach_mm for p in planned.strokes] == pytest.approx([3.25] * len(glyphs["永"].strokes))
    assert all(p.turn.mm == 1.0 and p.turn.press == 0.0 for p in planned.strokes)
    assert np.allclose([p.start_mm for p in planned.strokes], 1.0)


def test_a_hand_file_of_another_version_is_refused(tmp_path):
    path = tmp_path / "old.json"
    path.write_text('{"version": 1, "features": []}\n', encoding="utf-8")
    with pytest.raises(ValueError, match="not a hand file of version 2"):
        Hand.load(path)
