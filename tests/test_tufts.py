"""Multiple tufts (seed "Simulation with multiple tufts", Figure 6): child tufts sprout from a
parent node of the main tuft when it spreads, merge once the brush is clear of the paper, and
deposit their own streaks."""
import functools

import numpy as np
import pytest

import brushwork as bw
from brushwork.recorded import along_path
from tolerances import PENETRATION_FRAC

PRESS_Z = (35, 30, 28, 26, 24, 22, 20, 18, 16)  # mm: the root lowered step by step (L = 30 mm)
LIFT_Z = (20, 25, 30, 35)
TILT = 20.0
PX_PER_MM = 5
END_MM = 8.0          # mm: the stroke's end over which its width must not grow again
REGROWTH_MM = 0.5     # mm: the most the width may grow back there (a streak's jitter, not a bead)
EVEN_WIDTH_RATIO = 2.0  # widest / narrowest streak of an even split, at most, along its middle


def model(tufts=3, **fields):
    m = bw.BrushModel.preset("medium")
    m.tufts = tufts
    for name, value in fields.items():
        setattr(m, name, value)
    return m


def press(brush, heights=PRESS_Z, frames=3):
    """Lower (or raise) the root through `heights`, `frames` steps at each; the last stats."""
    for z in heights:
        for _ in range(frames):
            st = brush.step(bw.Pose((0.0, 0.0, z), TILT))
    return st


@pytest.mark.parametrize("even", [False, True])
def test_children_leave_the_main_tuft_as_a_single_tuft_solves_it(even):
    # the children are solved after their parent, so the main tuft moves bit for bit as a
    # brush without tufts does (tufts = 0, the default, is that brush), even while even tufts
    # replace it on the paper
    single, split = bw.Brush(model(0)), bw.Brush(model(3, even_tufts=even))
    for z in PRESS_Z + LIFT_Z:
        a, b = single.step(bw.Pose((0.0, 0.0, z), TILT)), split.step(bw.Pose((0.0, 0.0, z), TILT))
        assert a.tufts_active == 0 and len(single.tufts()) == 1
        assert np.array_equal(single.skeleton(), split.skeleton()), f"z = {z}"
        assert a.iterations == b.iterations
    assert bw.BrushModel.preset("medium").tufts == 0


def test_pressing_sprouts_children_and_lifting_merges_them():
    brush = bw.Brush(model(3))
    st = press(brush, PRESS_Z[:3])
    assert st.contacts > 0 and st.tufts_active == 0, "a light touch keeps one tuft"
    st = press(brush, PRESS_Z[3:])
    # sprouted at sprout_spread, split while the score stays above half of it
    assert st.sprout_score >= 0.5 * brush.model.sprout_spread
    assert st.tufts_active == 3 and brush.tufts_active == 3
    assert st.tuft_iterations > 0
    spines = brush.tufts()
    assert len(spines) == 4
    n, node = brush.model.n_segments, brush.model.tuft_node
    assert all(s.shape == (n - node + 1, 3) for s in spines[1:]), "a child is the spine below N_i"
    st = press(brush, LIFT_Z)
    assert st.tufts_active == 0 and len(brush.tufts()) == 1
    # and the children come back on the next press
    assert press(brush).tufts_active == 3
    brush.reset()
    assert brush.tufts_active == 0


def test_each_child_root_lies_in_its_parent_section():
    brush = bw.Brush(model(5))
    press(brush)
    node = brush.model.tuft_node
    sec = brush.sections_array()[node]  # center u w n a_plus a_minus c
    origin = brush.skeleton()[node]     # O_ij: the section about the spine node
    u, w, nrm, a_plus, a_minus, c = sec[3:6], sec[6:9], sec[9:12], sec[12], sec[13], sec[14]
    roots = [s[0] for s in brush.tufts()[1:]]
    assert len(roots) == 5
    for j, root in enumerate(roots):
        d = root - origin
        assert abs(d @ nrm) < 1e-9 * brush.model.tuft_length, f"child {j} off the bisecting plane"
        x = d @ u / (a_plus if d @ u >= 0 else a_minus)
        y = d @ w / c
        assert x * x + y * y < 1.0, f"child {j}: r_j = ({x:.3f}, {y:.3f}) outside Omega_ij"
    # they spread across the section, not on one spot
    xs = sorted((r - origin) @ u for r in roots)
    assert xs[0] < 0 < xs[-1]


def test_state_restore_repeats_a_split_step_bit_for_bit():
    brush = bw.Brush(model(3))
    press(brush)
    assert brush.tufts_active == 3
    saved = brush.state()
    assert saved.tufts_active == 3
    poses = [bw.Pose((0.3 * k, 0.0, 16.0), TILT) for k in range(1, 6)]

    def run():
        out = []
        for p in poses:
            st = brush.step(p)
            out.append((st.iterations, st.tuft_iterations, [s.copy() for s in brush.tufts()]))
        return out

    first = run()
    brush.set_state(saved)
    again = run()
    for k, (a, b) in enumerate(zip(first, again)):
        assert a[:2] == b[:2], f"frame {k}: iterations differ"
        assert len(a[2]) == len(b[2])
        for t, (sa, sb) in enumerate(zip(a[2], b[2])):
            assert np.array_equal(sa, sb), f"frame {k}, tuft {t} differs"
    twin = brush.copy()
    p = bw.Pose((2.0, 0.0, 16.5), TILT)
    brush.step(p), twin.step(p)
    assert all(np.array_equal(a, b) for a, b in zip(brush.tufts(), twin.tufts()))


DEEP_Z = PRESS_Z + (15, 14)  # mm: on down until the section at N_3 parts as well


def test_the_split_reaches_up_and_the_children_grow_a_segment_at_their_root():
    # seed: "the parent node can become N_{i-1}; the child tuft then grows by one segment"
    brush = bw.Brush(model(3, tuft_node=3))
    n = brush.model.n_segments
    nodes = []
    for z in DEEP_Z:
        press(brush, (z,))
        if brush.tufts_active:
            nodes.append(len(brush.tufts()[1]))
    assert nodes[0] == n - 3 + 1 and nodes[-1] == n - 2 + 1, f"child spine lengths {nodes}"
    assert sorted(nodes) == nodes, "a child never shrinks while split"
    # the grown children hang from N_2: their roots on its bisecting plane, inside Omega_2
    sec, origin = brush.sections_array()[2], brush.skeleton()[2]
    for root in (s[0] for s in brush.tufts()[1:]):
        d = root - origin
        assert abs(d @ sec[9:12]) < 1e-9 * brush.model.tuft_length
        assert np.hypot(d @ sec[3:6] / max(sec[12], sec[13]), d @ sec[6:9] / sec[14]) < 1.0
    # lifted, they merge; pressed again, they sprout from N_3 anew
    press(brush, LIFT_Z)
    assert brush.tufts_active == 0
    press(brush, PRESS_Z)
    assert len(brush.tufts()[1]) == n - 3 + 1


def early_twin_spine(m, state):
    twin = bw.Brush(m)
    twin.set_state(state)
    return twin.tufts()[1]


def test_a_state_saved_across_the_growth_replays_on_a_fresh_brush():
    m = model(3, tuft_node=3)
    brush = bw.Brush(m)
    press(brush, DEEP_Z[:-3])
    early, grown_from = brush.state(), len(brush.tufts()[1])
    press(brush, DEEP_Z[-3:])
    assert len(brush.tufts()[1]) > grown_from, "the children grew"
    twin = bw.Brush(m)  # its children hang from N_3
    twin.set_state(brush.state())
    for k in range(1, 4):
        p = bw.Pose((0.3 * k, 0.0, 14.0), TILT)
        a, b = brush.step(p), twin.step(p)
        assert (a.iterations, a.tuft_iterations) == (b.iterations, b.tuft_iterations)
        assert all(np.array_equal(x, y) for x, y in zip(brush.tufts(), twin.tufts()))
    assert brush.state().split_node == 2
    with pytest.raises(ValueError, match="node 2"):
        bw.Brush(model(3, tuft_node=1)).set_state(brush.state())
    brush.set_state(early)  # and back to children on N_3
    assert len(brush.tufts()[1]) == grown_from and np.array_equal(brush.tufts()[1], early_twin_spine(m, early))


def test_a_state_for_another_tuft_count_is_refused():
    three, one = bw.Brush(model(3)), bw.Brush(model(1))
    with pytest.raises(ValueError, match="child tufts"):
        one.set_state(three.state())


def test_a_parent_node_past_the_tip_is_refused():
    with pytest.raises(ValueError, match="tuft_node"):
        bw.Brush(model(3, tuft_node=6))


def test_footprint_has_one_polygon_per_touching_tuft():
    brush = bw.Brush(model(3))
    st = press(brush)
    assert st.tufts_active == 3
    touching = 1 + sum(s[:, 2].min() < 0.05 for s in brush.tufts()[1:])
    assert touching == 4, "every child's tip lies on the paper"
    assert len(brush.own_footprint()) == 1
    assert len(brush.footprint()) == touching
    assert st.max_penetration < PENETRATION_FRAC * brush.model.tuft_length


def ink_runs(ink, rows):
    """Most separate runs of inked pixels across the stroke along `rows` of the ink image."""
    runs = []
    for r in rows:
        on = ink[r] > 0.3
        runs.append(int(on[0]) + int(np.sum(on[1:] & ~on[:-1])))
    return max(runs)


@functools.lru_cache(maxsize=None)
def stroke_ink(tufts, even=False, wet=None):
    # a moderately pressed pull: the part below N_i touches, the tufts trail the root; wet: the
    # brush's ink drops to this fraction of a full load once it has split (on paper that depletes)
    m = model(tufts, sprout_spread=0.5, even_tufts=even)
    brush = bw.Brush(m)
    ink = brush.load_ink()
    paper = bw.Paper(40, 50, PX_PER_MM, scene=bw.Scene(depletion=wet is not None))
    pts = np.array([[20.0, 8.0], [20.0, 44.0]])
    press_ = np.array([0.0, 0.2, 0.2, 0.2, 0.2, 0.0])
    path = np.linspace(pts[0], pts[1], 6)
    split = 0
    for pose in along_path(m, path, press_, TILT, None, step_mm=0.5):
        active = brush.step(pose).tufts_active
        if wet is not None and active and not split:
            ink.load = ink.capacity * wet
            brush.wetness = np.full(m.n_segments + 1, wet)
            paper.end_stroke()
            paper.clear()        # (the ink from the next frame on, the tufts' first with it)
            split = active
            continue
        split = max(split, active)
        paper.deposit(brush)
    paper.end_stroke()
    return paper.ink(), split


def test_a_split_brush_leaves_more_separate_streaks_than_one_tuft():
    single, _ = stroke_ink(0)
    split, active = stroke_ink(5)
    assert active == 5
    rows = range(int(0.45 * single.shape[0]), int(0.75 * single.shape[0]), 5)  # y 12.5 .. 27.5 mm
    assert ink_runs(single, rows) == 1, "one tuft draws one stroke"
    assert ink_runs(split, rows) >= 4, "the tufts draw separate streaks"
    # and still ink where the main tuft's core passes
    assert split.sum() > 0.3 * single.sum()


def test_the_tufts_share_the_brush_s_ink():
    # a brush whose ink falls to 3% of its load once split draws at 30% density (full down to a
    # tenth of a node's load): the satellites draw from the same ink, not at the full density
    # they sprouted with
    ink, active = stroke_ink(5, wet=0.03)
    assert active == 5
    assert 0.0 < ink.max() <= 0.35


def streak_widths(row):
    """The widths (px) of the runs of inked pixels along one row of the ink image."""
    on = np.concatenate([[False], row > 0.3, [False]])
    edges = np.diff(on.astype(int))
    return np.flatnonzero(edges == -1) - np.flatnonzero(edges == 1)


@pytest.mark.parametrize("k", [3, 5])
def test_an_even_split_draws_streaks_of_one_width_in_place_of_the_main_tuft(k):
    ink, active = stroke_ink(k, even=True)
    assert active == k
    rows = list(range(int(0.6 * ink.shape[0]), int(0.9 * ink.shape[0]), 5))  # y 5 .. 20 mm: split
    for r in rows:
        w = streak_widths(ink[r])
        assert len(w) == k, f"row {r}: {len(w)} streaks, not {k}"
        assert w.max() <= EVEN_WIDTH_RATIO * w.min(), f"row {r}: streak widths {list(w)}"
    # five satellites beside the main tuft: one wide streak among thin ones
    satellites, _ = stroke_ink(5)
    for r in rows:
        w = streak_widths(satellites[r])
        assert w.max() > EVEN_WIDTH_RATIO * w.min(), f"row {r}: streak widths {list(w)}"


def test_even_tufts_share_the_main_tuft_and_replace_it_on_the_paper():
    m = model(4, even_tufts=True)
    even = m.split_model()
    assert even.n_segments == m.n_segments and even.tuft_length == m.tuft_length
    assert even.belly_radius == pytest.approx(m.belly_radius / 2.0), "1/k of the hairs: r / sqrt(k)"
    assert even.bend_stiffness == pytest.approx(m.bend_stiffness / 4.0)
    brush = bw.Brush(m)
    press(brush)
    assert brush.tufts_active == 4
    spines = brush.tufts()
    assert len(spines) == 4, "the main tuft is off the paper's list"
    own, loops = brush.own_footprint(), brush.footprint()
    assert own and len(loops) >= 4, "the main tuft is still pressed, the even tufts touch"
    assert not any(a.shape == b.shape and np.array_equal(a, b) for a in own for b in loops)
    assert all(s.shape == brush.skeleton().shape for s in spines), "an even tuft is the whole spine"
    # rooted across the root's section Omega_0, about the main tuft's root
    sec, origin = brush.sections_array()[0], brush.skeleton()[0]
    u, radius = sec[3:6], max(sec[12], sec[13])
    offsets = sorted((s[0] - origin) @ u for s in spines)
    assert offsets[0] < -0.5 * radius and offsets[-1] > 0.5 * radius
    assert max(np.linalg.norm(s[0] - origin) for s in spines) < radius
    press(brush, LIFT_Z)
    assert brush.tufts_active == 0 and len(brush.tufts()) == 1


def test_a_split_brush_stays_split_until_every_tuft_clears_the_paper():
    # lifted a quarter millimetre a frame: the spread closes while the tufts still touch
    brush = bw.Brush(model(3))
    press(brush)
    assert brush.tufts_active == 3
    clear, half = brush.model.merge_clearance, 0.5 * brush.model.sprout_spread
    closed_on_paper, low = False, brush.clearance()
    for k in range(80):
        before = low
        st = brush.step(bw.Pose((0.0, 0.0, PRESS_Z[-1] + 0.25 * k), TILT))
        low = brush.clearance()  # mm: every sprouted tuft's lowest point
        if st.tufts_active == 0:
            break
        closed_on_paper |= st.sprout_score < half and low < 0.0
    else:
        pytest.fail("the brush never merged in the air")
    assert closed_on_paper, "the spread closed while a tuft touched the paper, and it stayed split"
    assert low > clear, f"merged with its lowest point {low:.3f} mm above the paper"
    assert before <= clear, f"still split a frame after clearing the paper by {before:.3f} mm"


def test_a_split_stroke_ends_without_a_bead():
    # the width of the ink across the stroke, along its last END_MM: going toward the end it
    # only narrows (merged on the paper, the single tuft would lay its belly down there)
    ink, active = stroke_ink(5)
    assert active == 5
    width = (ink > 0.3).sum(axis=1) / PX_PER_MM   # mm, per row; row 0 at the top, the stroke's end
    rows = np.flatnonzero(width)
    end = width[rows[0]:rows[0] + int(END_MM * PX_PER_MM)][::-1]  # toward the end
    regrowth = end - np.minimum.accumulate(end)
    assert regrowth.max() <= REGROWTH_MM, (
        f"the width grows back by {regrowth.max():.1f} mm, "
        f"{(len(end) - 1 - np.argmax(regrowth)) / PX_PER_MM:.1f} mm "
        "before the stroke's end")


def test_bench_solver_times_each_tuft_count(tmp_path, capsys):
    import json

    from brushwork import cli

    out = tmp_path / "solver.json"
    assert cli.main(["bench", "solver", "--tufts", "1", "3", "--frames", "60", "--repeats", "1",
                     "--json", str(out)]) == 0
    rows = {(r["tufts"], r["mode"]): r for r in json.loads(out.read_text())["tuft_rows"]}
    assert set(rows) == {(1, "carried"), (1, "fresh"), (3, "carried"), (3, "fresh")}
    assert rows[1, "carried"]["split_frac"] == 0 and rows[1, "carried"]["mean_child_iterations"] == 0
    assert rows[3, "carried"]["split_frac"] > 0 and rows[3, "carried"]["mean_child_iterations"] > 0
    # the carried Hessian saves iterations for the children as for the main tuft (seed Table 1)
    assert rows[3, "carried"]["mean_child_iterations"] < rows[3, "fresh"]["mean_child_iterations"]
    assert "mean q (child)" in capsys.readouterr().out
    assert cli.main(["bench", "solver", "--tufts", "0", "--frames", "60", "--repeats", "1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "tufts" in err[0]


def test_paint_settings_take_a_tuft_count():
    from brushwork.paint.painting import Painting, check_change

    painting = Painting({"width_mm": 40.0, "height_mm": 30.0, "px_per_mm": 4.0, "tufts": 3})
    assert painting.brush.model.tufts == 2, "three tufts: the main one and two children"
    assert Painting({"width_mm": 40.0, "height_mm": 30.0, "px_per_mm": 4.0}).brush.model.tufts == 0
    assert check_change({"tufts": 5}) == {"tufts": 5}
    for bad in (0, 10, 2.5, True, "3"):
        with pytest.raises(ValueError, match="tufts"):
            check_change({"tufts": bad})
