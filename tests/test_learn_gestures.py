"""A learned hand carries the turn gesture: each stroke's run past corners learned from the examples."""
import json
from pathlib import Path

import numpy as np
import pytest

from brushwork.glyphs import load_source
from brushwork.writing import Style
from brushwork.writing.hand import FEATURES, Hand, learn_hand
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


def test_a_hand_writes_a_broader_style_with_deeper_presses_and_its_own_style_unchanged():
    """A variable font's weight masters scale the style's width_em; a hand's plans follow it: the
    press of each control moves to the press whose steady width is that many times its own."""
    from dataclasses import replace

    from brushwork.writing.fit import response
    from brushwork.writing.hand import widened
    from brushwork.writing.plan import BOUNDS

    st = Style.load("kai")
    hand = Hand.cached(st.hand_path())
    assert hand.width_em == st.width_em
    glyph = load_source(f"mmah:{DATA}", "永")["永"]
    plans = {f: hand.plan(glyph, replace(st, width_em=st.width_em * f)).strokes for f in (0.7, 1.0, 1.45)}
    resp = response(st.preset, float(st.tilt_deg), tuple(sorted(st.brush.items())))
    for light, regular, bold in zip(plans[0.7], plans[1.0], plans[1.45]):
        p = [np.asarray(s.controls["press"]) for s in (light, regular, bold)]
        touching = resp.at("width", p[1]) > 0.5
        assert touching.any()
        deepest = BOUNDS["press"][1]
        assert np.all(p[0][touching] < p[1][touching])
        assert np.all((p[1] < p[2])[touching & (p[1] < deepest)]) and np.all(p[2] >= np.minimum(p[1], deepest))
        # the root keeps its reach ahead of the deeper footprint's centre
        assert np.asarray(bold.controls["along"]) - np.asarray(regular.controls["along"]) == pytest.approx(
            resp.at("behind_root", p[2]) - resp.at("behind_root", p[1]))
    assert widened(plans[1.0][0], 1.0, st) is plans[1.0][0]


def test_a_hand_file_whose_width_is_not_a_width_names_the_field(tmp_path):
    path = tmp_path / "hand.json"
    doc = {"version": 2, "features": list(FEATURES), "scale": [], "width_em": -1, "families": {}}
    path.write_text(json.dumps(doc) + "\n", encoding="utf-8")
    with pytest.raises(ValueError, match="hand.json: width_em: expected a number in 0..0.5 or null"):
        Hand.load(path)
