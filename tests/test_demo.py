"""The brush demo runs headless and writes a picture (a smoke test with few frames); without
matplotlib (the `plot` extra) it says in one line how to get it."""
import sys

import numpy as np
import pytest

from brushwork.cli import main
from brushwork.demo import render_demo


def test_demo_writes_a_png(tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "demo.png"
    summary = render_demo(str(out), frames=60)
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
    assert summary["frames"] == 60 and np.isfinite(summary["mean_iterations"])
    assert summary["max_area"] > 0.0, "the pressed brush leaves a footprint"
    assert not list(tmp_path.glob("*.png.*")) and len(list(tmp_path.iterdir())) == 1


def test_demo_without_matplotlib_says_how_to_get_it(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "matplotlib", None)        # import matplotlib fails as if absent
    assert main(["demo", "-o", str(tmp_path / "demo.png")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and ".venv/bin/pip install '.[plot]'" in err
    assert not list(tmp_path.iterdir())
