"""The turn gesture of a plan (the root on the median's tangent, running on past a corner) and
where a fitted stroke's ink misses its outline, by region (`brushwork fit --regions`)."""
import json
from pathlib import Path

import numpy as np
import pytest

from brushwork.cli import main
from brushwork.writing import Style
from brushwork.writing.plan import Median, PlanError, corners_mm, sample, smooth_polyline, stroke_plan_from_json
from brushwork.writing.planned import InkGrid, PlanWriter
from brushwork.writing.regions import REGIONS, stroke_tally

DATA = Path(__file__).parent / "data" / "mmah" / "graphics.txt"
SOURCE = f"mmah:{DATA}"
# an L: right along y = 70 mm, then down x = 70 mm (a 横折's corner at (70, 70))
ELL = np.array([[20.0, 70.0], [70.0, 70.0], [70.0, 20.0]])


def _plan(turn=None, press=0.3):
    doc = {"controls": {"along": [8.5] * 5, "across": [0.0], "press": [press] * 5, "tilt": [15.0],
                        "azimuth": [0.0], "twist": [0.0], "speed": [0.5]},
           "start_mm": 0.0, "end_mm": 0.0, "entry": {"frames": 4, "back_mm": 0.0},
           "exit": {"frames": 4, "move_mm": 0.0}}
    if turn is not None:
        doc["turn"] = turn
    return stroke_plan_from_json(doc, "test")


def test_a_median_has_a_corner_where_it_turns_sharply_and_none_on_a_gentle_arc():
    assert corners_mm(Median(ELL)) == pytest.approx([50.0], abs=0.3)
    arc = np.stack([50 + 40 * np.cos(np.linspace(0, 1.2, 40)), 50 + 40 * np.sin(np.linspace(0, 1.2, 40))], axis=1)
    assert len(corners_mm(Median(arc))) == 0


def _turns_deg(p: np.ndarray) -> np.ndarray:
    """Degrees the polyline p turns at each inner vertex (signed: left positive)."""
    d = np.diff(p, axis=0)
    return np.degrees(np.angle(np.exp(1j * np.diff(np.arctan2(d[:, 1], d[:, 0])))))


def _distance_to(points: np.ndarray, line: np.ndarray) -> np.ndarray:
    """(len(points),) mm from each point to the polyline `line`."""
    a, ab = line[:-1], np.diff(line, axis=0)
    t = np.clip(np.einsum("pij,ij->pi", points[:, None] - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    return np.min(np.hypot(*(a + t[..., None] * ab - points[:, None]).transpose(2, 0, 1)), axis=1)


def test_a_coarse_median_of_a_curve_turns_smoothly_and_stays_on_its_points():
    # five points of a circle of radius 30 mm, 30 deg apart: the polyline turns 30 deg at a vertex
    a = np.radians(np.arange(0, 121, 30))
    coarse = np.stack([50 + 30 * np.cos(a), 20 + 30 * np.sin(a)], axis=1)
    med = Median(coarse)
    curve = med.curve
    assert np.array_equal(med.points, coarse)
    # no facet: where the polyline turns 30 deg at once, the curve (points 0.2 mm apart) turns at
    # most 2 deg from one point to the next, always the same way (each turn spread over a few mm)
    assert _turns_deg(coarse).min() == pytest.approx(30.0)
    assert _turns_deg(curve).min() > -1e-6 and _turns_deg(curve).max() < 2.0
    # it keeps to the polyline: within 0.35 mm of every vertex, on the chords between them, its
    # ends the polyline's and leaving along its end segments
    assert _distance_to(coarse, curve).max() < 0.35
    mid = np.hypot(curve[:, 0] - 50, curve[:, 1] - 20) < 30 * np.cos(np.radians(15)) + 0.05
    assert _distance_to(curve[mid], coarse).max() < 0.05
    assert np.array_equal(curve[[0, -1]], coarse[[0, -1]])
    assert med.e0 == pytest.approx(med.t0, abs=0.01) and med.e1 == pytest.approx(med.t1, abs=0.01)


def test_a_kink_of_the_median_stays_a_corner_and_a_straight_median_stays_straight():
    curve = smooth_polyline(ELL)
    corner = int(np.argmin(np.hypot(curve[:, 0] - 70, curve[:, 1] - 70)))
    # both legs straight up to the corner: the L is not rounded off
    assert np.abs(curve[:corner + 1, 1] - 70).max() < 1e-9
    assert np.abs(curve[corner:, 0] - 70).max() < 1e-9
    line = np.array([[0.0, 0.0], [10.0, 5.0], [30.0, 15.0]])
    assert np.abs(smooth_polyline(line) @ np.array([0.5, -1.0])).max() < 1e-9


def test_with_a_turn_the_root_runs_on_past_the_corner_and_without_it_cuts_across():
    med = Median(ELL)
    plain = sample(_plan(), med, 18.0, 1.0, 0.12).root
    turned = sample(_plan({"mm": 1.0, "press": 0.0, "reach_mm": 2.0}), med, 18.0, 1.0, 0.12).root
    # on the median the root never passes x = 70; on the tangent it runs on up to 8.5 + 2 mm past
    # it (the heading turns over +-1 mm of the corner)
    assert plain[:, 0].max() == pytest.approx(70.0, abs=1e-6)
    assert 78.5 < turned[:, 0].max() <= 80.5 + 1e-6
    # and comes back to the median's second leg, 8.5 mm down it, once past the corner
    assert np.min(np.hypot(turned[:, 0] - 70.0, turned[:, 1] - 20.0 + 8.5)) < 0.6


def _ink(plan) -> np.ndarray:
    st = Style.load("kai")      # the style whose hand writes plans
    grid = InkGrid(256, st.em_mm)
    writer = PlanWriter(st, grid)
    writer.brush.load_ink(total_mm2=st.ink_mm2, excess=0.0)
    writer.write_stroke(plan, Median(ELL))
    return grid.ink()


def test_a_turned_corner_fills_the_outer_shoulder_the_trailing_tuft_cuts_otherwise():
    ppm = 256 / 100.0
    # the outer shoulder: the square 3 mm up and right of the corner's outer edge (y down in px)
    x0, x1 = int(70.5 * ppm), int(73.5 * ppm)
    y0, y1 = int((100 - 73.5) * ppm), int((100 - 70.5) * ppm)
    # pressed 0.4 L: a stroke about 6 mm wide, whose outer shoulder the 3 mm square lies in
    cut = _ink(_plan(press=0.4))[y0:y1, x0:x1].mean()
    turned = _ink(_plan({"mm": 1.0, "press": 0.0, "reach_mm": 2.0}, press=0.4))[y0:y1, x0:x1].mean()
    assert turned > cut + 0.3


def test_a_bad_turn_names_the_field():
    with pytest.raises(PlanError, match="turn.reach_mm"):
        _plan({"mm": 1.0, "press": 0.0, "reach_mm": "far"})


def test_a_plans_turn_survives_its_json():
    plan = _plan({"mm": 1.5, "press": 0.05, "reach_mm": 3.0})
    again = stroke_plan_from_json(json.loads(json.dumps(plan.to_json())), "test")
    assert (again.turn.mm, again.turn.press, again.turn.reach_mm) == (1.5, 0.05, 3.0)
    assert "turn" not in _plan().to_json()


def test_the_tally_puts_a_missed_corner_in_the_corner_and_nothing_where_ink_matches():
    med, ppm = Median(ELL), 256 / 100.0
    ink = _ink(_plan({"mm": 1.0, "press": 0.0, "reach_mm": 2.0}))
    same = stroke_tally(ink, ink, med, "㇕", ppm, 100.0)
    assert same[:, 1:].sum() == 0 and same[:, 0].sum() == ink.sum()
    holed = ink.copy()
    cx, cy = int(70 * ppm), int(30 * ppm)
    holed[cy - 4:cy + 4, cx - 4:cx + 4] = False
    tally = stroke_tally(holed, ink, med, "㇕", ppm, 100.0)
    corner = REGIONS.index("corner")
    assert tally[corner, 1] == (ink & ~holed).sum() and tally[:, 2].sum() == 0


def test_fit_regions_prints_each_familys_misses_by_region(tmp_path, capsys):
    assert main(["fit", "--chars", "凡", "--source", SOURCE, "--out", str(tmp_path), "--no-progress",
                 "--regions"]) == 0
    out = capsys.readouterr().out.splitlines()
    rows = [ln.split() for ln in out if ln.split() and ln.split()[0] in ("plain", "hook", "tapered", "dot")]
    assert rows and all(r[1] in REGIONS for r in rows)
    shares = [float(r[3].rstrip("%")) for r in rows]
    assert sum(shares) == pytest.approx(100.0, abs=0.5)


def _flicked(flick=None):
    doc = json.loads(json.dumps(_plan({"mm": 1.0, "press": 0.0, "reach_mm": 2.0}).to_json()))
    if flick is not None:
        doc["flick"] = flick
    return stroke_plan_from_json(doc, "test")


def test_a_flick_runs_past_the_hooks_end_easing_the_press_from_its_corner():
    """The flick: from the median's last corner past 60% of it (a hook's turn) the press eases in
    a straight line to flick.press, reached flick.past_mm past the median's end, where the travel
    stops."""
    # a hook: right along y = 70 mm to a corner at (80, 70), 60 mm along, then 10 mm down
    med = Median(np.array([[20.0, 70.0], [80.0, 70.0], [80.0, 60.0]]))
    f = sample(_flicked({"past_mm": 4.0, "press": 0.1}), med, 18.0, 1.0, 0.12)
    root, press = f.root[f.on][:, :2], f.press[f.on]
    # the travel's last reference point lies 4 mm past the end, straight on down the hook, where
    # the root stands `along` (8.5 mm) ahead on the tangent, pressed flick.press
    assert root[-1] == pytest.approx([80.0, 60.0 - 4.0 - 8.5], abs=0.05)
    assert press[-1] == pytest.approx(0.1, abs=1e-9)
    # before the corner the plan's own press (0.3); down the hook, the reference point 60 + d mm
    # along (d from the root's height), a straight line from 0.3 at the corner to 0.1 at 74 mm
    before = root[:, 0] < 80.0 - 8.5 - 1.0
    assert np.all(press[before] == pytest.approx(0.3))
    # (past the turn's run on, which ends 3 mm of arc past the corner)
    down = (np.abs(root[:, 0] - 80.0) < 1e-6) & (root[:, 1] < 70.0 - 8.5 - 3.5)
    d = 70.0 - 8.5 - root[down, 1]
    assert down.sum() > 15 and d.max() == pytest.approx(14.0, abs=0.01)
    assert press[down] == pytest.approx(0.3 + (0.1 - 0.3) * d / 14.0, abs=0.01)
    # a median without a corner past its first 60% (a 捺) eases from its deepest press there: a
    # straight 60 mm pressed 0.3 all along holds 0.3 to 36 mm, then runs on 4 mm past its end
    # down to 0.1
    f = sample(_flicked({"past_mm": 4.0, "press": 0.1}), Median(np.array([[20.0, 50.0], [80.0, 50.0]])),
               18.0, 1.0, 0.12)
    root, press = f.root[f.on][:, :2], f.press[f.on]
    assert root[-1] == pytest.approx([80.0 + 4.0 + 8.5, 50.0], abs=0.05) and press[-1] == pytest.approx(0.1)
    along = root[:, 0] - 8.5 - 20.0
    assert np.all(press[along < 36.0 - 0.01] == pytest.approx(0.3))
    assert press[along > 36.5].min() < 0.3 and np.all(np.diff(press[along > 36.5]) <= 1e-12)


def test_a_flick_keeps_to_its_file_and_a_bad_one_names_the_field():
    plan = _flicked({"past_mm": 4.0, "press": 0.1})
    again = stroke_plan_from_json(json.loads(json.dumps(plan.to_json())), "test")
    assert (again.flick.past_mm, again.flick.press) == (4.0, 0.1)
    with pytest.raises(PlanError, match="test: flick.past_mm: expected a number in 0..30"):
        _flicked({"past_mm": -1.0})
    with pytest.raises(PlanError, match="test: flick: expected an object"):
        _flicked([4.0])


def test_a_learned_hand_flicks_its_hooks_and_its_feet_and_no_other_stroke():
    from brushwork.glyphs import load_source
    from brushwork.writing.hand import FOOT_FLICK, HOOK_FLICK, Hand
    from brushwork.writing.style import family

    st = Style.load("kai")
    glyph = load_source(SOURCE, "永")["永"]
    plans = Hand.cached(st.hand_path()).plan(glyph, st).strokes
    fams = [family(s.kind) for s in glyph.strokes]
    assert {"hook", "flared"} <= set(fams) and len(set(fams)) > 2
    assert [p.flick for p in plans] == [{"hook": HOOK_FLICK, "flared": FOOT_FLICK}.get(f) for f in fams]


def test_a_plan_writer_counts_a_bead_where_the_footprint_necks_and_swells_at_the_end():
    """Asked for beads, a PlanWriter measures the footprint across the travel each frame: a stroke
    whose press eases almost off the paper near its end and presses again ends in a bead, one
    pressed evenly does not; each is tallied in its family."""
    from brushwork.glyphs.model import Glyph, Stroke
    from brushwork.writing.plan import GlyphPlan

    st = Style.load("kai")
    line = np.array([[0.2, 0.5], [0.8, 0.5]])
    glyph = Glyph("一", ord("一"), [Stroke(line, "㇐"), Stroke(line - [0.0, 0.2], "㇐")], "test", (0.0, 0.0, 1.0, 1.0))
    even = _plan(press=0.3)
    necked = _plan(press=0.3)
    necked.controls["press"] = [0.3, 0.3, 0.3, 0.02, 0.45]
    beads: dict = {}
    PlanWriter(st, InkGrid(256, st.em_mm), beads=beads).write(glyph, GlyphPlan("一", [even, necked], "kai"))
    assert beads == {"plain": [1, 2]}
