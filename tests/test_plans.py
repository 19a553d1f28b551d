"""Stroke plans: the format, the sampler, the GL-free ink, `brushwork fit`, `render --plans` and `learn`."""
import json
import math
from pathlib import Path

import numpy as np
import pytest

from brushwork.cli import main
from brushwork.glyphs import load_source
from brushwork.glyphs.score import iou, outline_mask
from brushwork.writing import Style
from brushwork.writing.plan import (PlanError, Median, bspline_basis, fit_controls, load_plan, plan_path, sample,
                                    stroke_plan_from_json)
from brushwork.writing.planned import InkGrid, PlanWriter
from brushwork.writing.style import STYLE_DIR

DATA = Path(__file__).parent / "data" / "mmah" / "graphics.txt"
SOURCE = f"mmah:{DATA}"


def test_the_spline_basis_is_a_partition_of_unity_and_reproduces_a_line():
    s = np.linspace(0.0, 1.0, 41)
    for k in (1, 2, 4, 7):
        assert np.allclose(bspline_basis(s, k).sum(axis=1), 1.0)
    line = 0.3 + 2.0 * s
    c = fit_controls(s, line, 6, smooth=0.0)
    assert np.allclose(bspline_basis(s, 6) @ c, line, atol=1e-6)


def _plan_doc(press=0.3, k=5):
    return {"controls": {"along": [8.5] * k, "across": [0.0], "press": [press] * k, "tilt": [15.0], "azimuth": [0.0],
                         "twist": [0.0], "speed": [1.0]},
            "start_mm": 0.0, "end_mm": 0.0, "entry": {"frames": 4, "back_mm": 0.0}, "exit": {"frames": 4, "move_mm": -2.0}}


def test_a_plan_samples_into_an_entry_a_travel_along_the_median_and_an_exit():
    plan = stroke_plan_from_json(_plan_doc(), "test")
    med = Median(np.array([[10.0, 50.0], [70.0, 50.0]]))
    f = sample(plan, med, shape_length=18.0, step_mm=1.0, hover=0.12)
    assert f.press[0] == pytest.approx(-0.12) and f.press[-1] == pytest.approx(-0.12)
    travel = f.root[f.on]
    # the root runs `along` ahead of the reference point, which covers the median at 1 mm a frame
    assert travel[0, 0] == pytest.approx(18.5) and travel[-1, 0] == pytest.approx(78.5)
    assert np.all(np.abs(travel[:, 1] - 50.0) < 1e-9)
    assert np.max(np.diff(travel[:, 0])) <= 1.0 + 1e-9
    # the root's height: L cos(tilt) - press L
    assert travel[5, 2] == pytest.approx(18.0 * math.cos(math.radians(15.0)) - 0.3 * 18.0)


def test_a_bad_plan_names_the_field():
    doc = _plan_doc()
    doc["controls"]["press"] = [0.3, "deep"]
    with pytest.raises(PlanError, match="controls.press"):
        stroke_plan_from_json(doc, "x.json")


def test_the_ink_grid_fills_a_pressed_drag_as_wide_as_the_footprint():
    st = Style.load("kai")
    grid = InkGrid(256, st.em_mm)
    writer = PlanWriter(st, grid)
    writer.brush.load_ink(total_mm2=st.ink_mm2, excess=0.0)
    writer.write_stroke(stroke_plan_from_json(_plan_doc(press=0.3), "test"), Median(np.array([[20.0, 50.0], [80.0, 50.0]])))
    ink = grid.ink()
    cols = ink[:, int(0.5 * 256)]                           # the column at x = 50 mm
    width_mm = cols.sum() / grid.ppm
    assert 3.5 < width_mm < 8.0                             # the small brush at 0.3 L: ~5 mm
    assert ink[:, int(0.95 * 256):].sum() == 0              # nothing past the stroke's end and lift


class _ShapeSink:
    """A sink that keeps the tuft's root and shape (its joints relative to the root) at every deposit."""

    def __init__(self):
        self.shapes, self.roots = [], []

    def deposit(self, brush):
        joints = np.asarray(brush.skeleton(), dtype=float)
        self.shapes.append(joints - joints[0])
        self.roots.append(joints[0])
        return type("Stats", (), {"contact": True})()

    def end_stroke(self):
        pass


def _snap_writer():
    """A writer whose kai tuft is pressed 0.3 L and dragged 6 mm, bent behind its root."""
    from brushwork.brush import Pose
    from brushwork.recorded import root_height

    writer = PlanWriter(Style.load("kai"), None)
    writer.sink = _ShapeSink()
    z = root_height(writer.brush.model, 15.0, 0.3)
    for k in range(30):
        writer._step(Pose((20.0 + 0.2 * k, 50.0, z), 15.0, 0.0))
    return writer, z


def test_a_frame_in_which_the_tuft_snaps_is_written_in_substeps():
    """Lifted 0.1 L in one frame, the dragged tuft springs back: its joints move millimetres
    relative to its root. Written whole, the ink between the two frames would be a linear blend of
    the bent and the sprung shape; split, the frame is solved again at poses evenly between the two
    (one a SNAP_MM of that jump) and each solved shape deposited, the last at the frame's pose; it
    stays one frame."""
    from brushwork.brush import Pose
    from brushwork.writing.planned import MAX_SUBSTEPS, SNAP_MM

    whole, z = _snap_writer()
    split, _ = _snap_writer()
    lift = Pose((25.8, 50.0, z + 0.1 * whole.L), 15.0, 0.0)
    whole._step(lift, split=False)
    split._step(lift, split=True)
    jump = float(np.max(np.linalg.norm(whole.sink.shapes[-1] - whole.sink.shapes[-2], axis=1)))
    assert jump > 2.0 * SNAP_MM, jump
    k = min(math.ceil(jump / SNAP_MM), MAX_SUBSTEPS)
    assert len(whole.sink.roots) == 31 and len(split.sink.roots) == 30 + k
    heights = np.array(split.sink.roots[29:])[:, 2]
    assert np.allclose(np.diff(heights), 0.1 * whole.L / k), heights
    assert np.allclose(split.sink.roots[-1], lift.position)
    assert split.frames == whole.frames == 31
    # a small change is written whole
    calm, _ = _snap_writer()
    calm._step(Pose((26.0, 50.0, z), 15.0, 0.0), split=True)
    assert len(calm.sink.roots) == 31


@pytest.mark.parametrize("ink, splits", [("gl", True), ("geometry", False)])
def test_a_snapping_frame_is_split_only_where_the_egl_pass_inks(ink, splits, monkeypatch):
    """The EGL pass sweeps a linear blend of two frames' surfaces, which pinches a tuft that snaps:
    there the travel's frames are split where they snap. Ink as geometry is written frame by frame."""
    import brushwork as bw
    from brushwork.paper import make_paper

    asked = []
    real = PlanWriter._step

    def step(self, pose, split=False):
        asked.append(split)
        return real(self, pose, split)

    monkeypatch.setattr(PlanWriter, "_step", step)
    st = Style.load("kai")
    paper = make_paper(100, 100, 2, bw.Scene(samples=1), ink)
    writer = PlanWriter(st, paper)
    writer.brush.load_ink(total_mm2=st.ink_mm2, excess=0.0)
    plan = stroke_plan_from_json({"controls": {"along": [9.0], "across": [0.0], "press": [0.3], "tilt": [25.0],
                                               "azimuth": [0.0], "twist": [0.0], "speed": [0.5]}}, "test")
    writer.write_stroke(plan, Median(np.array([[20.0, 50.0], [60.0, 50.0]])))
    assert len(asked) > 40 and any(asked) == splits


def test_fit_writes_resumable_plans_that_render_close_to_the_outlines(tmp_path, capsys):
    out = tmp_path / "plans"
    assert main(["fit", "--chars", "凡它", "--source", SOURCE, "--out", str(out), "--no-progress"]) == 0
    printed = capsys.readouterr().out
    assert "fitted 2 characters (0 already fitted)" in printed and "s a character on one core" in printed
    doc = json.loads(plan_path(out, "凡").read_text(encoding="utf-8"))
    assert doc["version"] == 1 and len(doc["strokes"]) == 3 and doc["iou"] > 0.7
    assert main(["fit", "--chars", "凡它", "--source", SOURCE, "--out", str(out), "--no-progress"]) == 0
    assert "fitted 0 characters (2 already fitted)" in capsys.readouterr().out
    png = tmp_path / "fan.png"
    assert main(["render", "凡", "--plans", str(out), "--source", SOURCE, "--size", "256", "-o", str(png)]) == 0
    import cv2

    ink = cv2.imread(str(png), cv2.IMREAD_GRAYSCALE) < 128
    glyph = load_source(SOURCE, "凡")["凡"]
    assert iou(ink, outline_mask(glyph, 256)) > 0.7


def test_fit_says_in_one_line_when_a_character_has_no_outlines(tmp_path, capsys):
    medians = tmp_path / "m.txt"
    doc = json.loads(DATA.read_text(encoding="utf-8").splitlines()[0])
    medians.write_text(json.dumps({"character": doc["character"], "medians": doc["medians"]}) + "\n", encoding="utf-8")
    code = main(["fit", "--chars", doc["character"], "--source", f"medians:{medians}", "--out", str(tmp_path / "o"),
                 "--no-progress"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "no stroke outlines" in err[0]


def test_render_plans_without_a_plan_file_is_one_line(tmp_path, capsys):
    code = main(["render", "凡", "--plans", str(tmp_path), "--source", SOURCE, "-o", str(tmp_path / "x.png")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "no plan for 凡" in err[0]


def test_a_learned_hand_writes_a_character_from_its_medians_alone(tmp_path, capsys):
    plans, hand = tmp_path / "plans", tmp_path / "hand.json"
    assert main(["fit", "--chars", "凡和它永", "--source", SOURCE, "--out", str(plans), "--no-progress"]) == 0
    assert main(["learn", "--plans", str(plans), "--source", SOURCE, "-o", str(hand)]) == 0
    assert "4 characters" in capsys.readouterr().out
    style = json.loads((STYLE_DIR / "kai.json").read_text(encoding="utf-8"))
    style.update(name="learned", hand=str(hand))
    (tmp_path / "learned.json").write_text(json.dumps(style), encoding="utf-8")
    png = tmp_path / "ming.png"
    assert main(["render", "明", "--style", str(tmp_path / "learned.json"), "--source", SOURCE, "--size", "256",
                 "-o", str(png)]) == 0
    import cv2

    ink = cv2.imread(str(png), cv2.IMREAD_GRAYSCALE) < 128
    glyph = load_source(SOURCE, "明")["明"]
    assert iou(ink, outline_mask(glyph, 256)) > 0.5           # 明 was not among the fitted characters


def test_corners_count_sharp_turns_of_an_outline_and_not_a_smooth_one():
    import cv2

    from brushwork.glyphs.score import corner_count

    disk = np.zeros((400, 400), np.uint8)
    cv2.circle(disk, (200, 200), 120, 1, -1)
    square = np.zeros_like(disk)
    square[100:300, 100:300] = 1
    assert corner_count(disk.astype(bool)) == 0
    assert corner_count(square.astype(bool)) == 4


def test_a_bulb_at_a_strokes_end_is_a_bead_on_the_ink():
    import cv2

    from brushwork.glyphs.model import Glyph, Stroke
    from brushwork.bench.glyphs import ink_beads

    glyph = Glyph("一", ord("一"), [Stroke(np.array([[0.2, 0.5], [0.8, 0.5]]), "㇐")], "", (0.0, 0.0, 1.0, 1.0), False)
    plain = np.zeros((256, 256), np.uint8)
    cv2.line(plain, (51, 128), (205, 128), 1, 12)
    bulb = plain.copy()
    cv2.circle(bulb, (200, 128), 14, 1, -1)
    masks = [plain.astype(bool)]
    assert ink_beads(glyph, plain.astype(bool), masks) == {"plain": [0, 1]}
    assert ink_beads(glyph, bulb.astype(bool), masks) == {"plain": [1, 1]}


@pytest.mark.parametrize("style", ["kai", "xing"])
def test_the_shipped_learned_styles_write_from_medians_alone(style, tmp_path):
    import cv2

    png = tmp_path / "ming.png"
    assert main(["render", "明", "--style", style, "--source", SOURCE, "--size", "256", "-o", str(png)]) == 0
    ink = cv2.imread(str(png), cv2.IMREAD_GRAYSCALE) < 128
    assert iou(ink, outline_mask(load_source(SOURCE, "明")["明"], 256)) > 0.6


def test_a_learned_hand_hands_each_strokes_ink_to_the_caller_as_the_driver_does():
    """The font's weight masters take each stroke's ink off the paper once it is written: a learned
    hand calls on_stroke once a stroke, in order, with that stroke's ink alone on the paper."""
    from brushwork.font.variable import stroke_images

    glyph = load_source(SOURCE, "明")["明"]
    images = stroke_images(glyph, 128, Style.load("kai"))
    assert len(images) == len(glyph.strokes)
    inked = [int((np.asarray(im).min(axis=-1) < 128).sum()) for im in images]
    assert all(n > 0 for n in inked), inked


def test_a_fit_stopped_by_sigterm_ends_as_ctrl_c_does_and_resumes(tmp_path):
    """SIGTERM to `brushwork fit` with worker processes: the pool stopped with its workers, no
    traceback from any of them, exit 130; the plans written are whole and a rerun skips them."""
    import os
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "plans"
    cmd = [sys.executable, "-m", "brushwork", "fit", "--chars", "凡和它明永", "--source", SOURCE, "--out", str(out),
           "--jobs", "2", "--no-progress"]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not list(out.glob("U+*.json")) and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.05)
    proc.send_signal(signal.SIGTERM)
    stdout, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 130, stdout + stderr
    assert "Traceback" not in stderr and stderr.strip().splitlines()[-1] == "brushwork: interrupted"
    done = sorted(out.glob("U+*.json"))
    assert 1 <= len(done) < 5
    for path in done:                                 # every plan there reads back
        char = chr(int(path.stem[2:], 16))
        assert len(load_plan(out, char).strokes) == len(load_source(SOURCE, char)[char].strokes)
    rerun = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=300)
    assert rerun.returncode == 0 and f"({len(done)} already fitted)" in rerun.stdout
