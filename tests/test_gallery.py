"""The README's main job (the Figure 11 gallery) and the render benchmark run headless."""
import json

import cv2
import numpy as np

from brushwork import cli
from brushwork.gallery import CELL_H, CELL_W, COLUMNS, samples


def test_gallery_command_writes_every_panel(tmp_path):
    out = tmp_path / "gallery.png"
    assert cli.main(["gallery", "-o", str(out), "--px-per-mm", "2"]) == 0
    img = cv2.imread(str(out), cv2.IMREAD_GRAYSCALE)
    rows = -(-len(samples()) // COLUMNS)
    assert img.shape == (int(rows * CELL_H * 2), int(COLUMNS * CELL_W * 2))
    # every panel holds ink (dark pixels away from its label and border)
    for i in range(len(samples())):
        r, c = divmod(i, COLUMNS)
        panel = img[int(r * CELL_H * 2) + 12:int((r + 1) * CELL_H * 2) - 2,
                    int(c * CELL_W * 2) + 2:int((c + 1) * CELL_W * 2) - 2]
        assert (panel < 100).sum() > 20, f"panel {samples()[i].key} is empty"
    assert [p.name for p in tmp_path.iterdir()] == ["gallery.png"]


def test_gallery_rejects_a_silly_resolution_and_a_missing_folder(tmp_path, capsys):
    assert cli.main(["gallery", "-o", str(tmp_path / "g.png"), "--px-per-mm", "500"]) == 2
    assert cli.main(["gallery", "-o", str(tmp_path / "no" / "g.png"), "--px-per-mm", "2"]) == 2
    err = capsys.readouterr().err
    assert "px-per-mm" in err and "no such folder" in err


def test_bench_render_prints_and_writes_both_scenes(tmp_path, capsys):
    out = tmp_path / "render.json"
    assert cli.main(["bench", "render", "--px", "256", "--frames", "60", "--repeats", "1",
                     "--json", str(out)]) == 0
    result = json.loads(out.read_text())
    scenes = {row["scene"]: row for row in result["rows"]}
    assert set(scenes) == {"minimal", "full"}
    assert scenes["minimal"]["features"] == "none"
    assert all(np.isfinite(row["fps"]) and row["fps"] > 0 for row in result["rows"])
    assert "frames/s" in capsys.readouterr().out


def test_bench_footprint_and_params(tmp_path, capsys):
    out = tmp_path / "fp.json"
    assert cli.main(["bench", "footprint", "--json", str(out)]) == 0
    result = json.loads(out.read_text())
    assert len(result["rows"]) == 6 and len(result["raw"]) == 30
    # deeper presses of an upright brush leave more ink
    upright = [r["area_mm2"] for r in result["raw"] if r["tilt_deg"] == 0 and r["motion"] == "static"]
    assert upright == sorted(upright)
    assert 0.0 <= result["flicker_15deg_025L"] < 10.0
    assert cli.main(["bench", "footprint", "--set", "nope=1"]) == 2
    assert cli.main(["params", "--preset", "small"]) == 0
    assert "`tuft_length` | mm" in capsys.readouterr().out
