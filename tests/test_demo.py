"""The README's main job runs headless and writes a picture (a smoke test with few frames)."""
import numpy as np

from brushwork.demo import render_demo


def test_demo_writes_a_png(tmp_path):
    out = tmp_path / "demo.png"
    summary = render_demo(str(out), frames=60)
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
    assert summary["frames"] == 60 and np.isfinite(summary["mean_iterations"])
    assert summary["max_area"] > 0.0, "the pressed brush leaves a footprint"
    assert not list(tmp_path.glob("*.png.*")) and len(list(tmp_path.iterdir())) == 1
