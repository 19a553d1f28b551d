"""The README is documentation a user runs: its Python block works as written from any folder, its
style table and docs/parameters.md's brush table are the ones the code validates with, and the
images it shows are what the commands under them write."""
import re
from pathlib import Path

import cv2
import numpy as np
import pytest

from brushwork import cli
from brushwork.writing.style import style_table

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text(encoding="utf-8")

# an image re-made on this machine may differ from the committed copy only in a few edge pixels
# (another GL driver rounds coverage differently): at most this fraction of pixels may differ by
# more than PIXEL_LEVELS of 255
PIXEL_FRACTION = 1e-3
PIXEL_LEVELS = 32


def _python_blocks() -> list[str]:
    return re.findall(r"```python\n(.*?)```", README, flags=re.S)


def test_readme_is_short():
    assert len(README.splitlines()) <= 300


def test_python_block_runs_as_written(tmp_path, monkeypatch):
    blocks = _python_blocks()
    assert len(blocks) == 1, "the README has one Python block"
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    exec(compile(blocks[0], "README.md", "exec"), namespace)
    for name in ("stroke.png", "ai.png"):
        image = cv2.imread(str(tmp_path / name), cv2.IMREAD_GRAYSCALE)
        assert image is not None, f"the README's block should write {name}"
        assert (image < 128).mean() > 0.01, f"{name} should show ink"


def test_style_table_is_the_codes():
    found = re.search(r"<!-- style-table -->\n(.*?)<!-- /style-table -->", README, flags=re.S)
    assert found, "the README marks its style table"
    assert found.group(1).strip() == style_table().strip(), \
        "re-make the README's style table with `brushwork params --style --markdown`"


def test_glyph_limits_are_the_codes():
    from brushwork.glyphs.jsonfmt import limits_text

    found = re.search(r"<!-- glyph-limits -->(.*?)<!-- /glyph-limits -->", README, flags=re.S)
    assert found, "the README marks the glyph files' limits"
    assert " ".join(found.group(1).split()) == limits_text(), \
        "write brushwork.glyphs.jsonfmt.limits_text() between the README's glyph-limits marks"


def test_parameter_table_is_the_codes():
    from brushwork.bench.report import parameter_table

    doc = (ROOT / "docs" / "parameters.md").read_text(encoding="utf-8")
    found = re.search(r"<!-- parameter-table -->\n(.*?)<!-- /parameter-table -->", doc, flags=re.S)
    assert found, "docs/parameters.md marks its table"
    assert found.group(1).strip() == parameter_table("medium").strip(), \
        "re-make docs/parameters.md's table with `brushwork params --markdown`"


def _shown_images() -> set[str]:
    return set(re.findall(r"!\[[^\]]*\]\((docs/[^)]+\.png)\)", README))


def test_every_shown_image_is_made_by_the_script():
    script = (ROOT / "docs" / "make_images.sh").read_text(encoding="utf-8")
    for path in _shown_images():
        assert path in script, f"{path} is shown but docs/make_images.sh does not make it"


def _close(made: Path, kept: Path) -> None:
    a = cv2.imread(str(made), cv2.IMREAD_UNCHANGED)
    b = cv2.imread(str(kept), cv2.IMREAD_UNCHANGED)
    assert a is not None and b is not None
    assert a.shape == b.shape, f"{kept.name}: {a.shape} made against {b.shape} kept"
    off = np.abs(a.astype(np.int16) - b.astype(np.int16)).max(axis=-1) > PIXEL_LEVELS
    assert off.mean() <= PIXEL_FRACTION, \
        f"{kept.name}: {off.sum()} pixels differ from what its command writes (docs/make_images.sh)"


@pytest.mark.parametrize("argv, made, kept", [
    (["render", "永和九年", "-o", "{tmp}/yonghe.png"], "yonghe.png", "docs/yonghe.png"),
    (["gallery", "-o", "{tmp}/gallery.png", "--views", "{tmp}/brush_view.png"], "gallery.png",
     "docs/gallery.png"),
    (["batch", "--chars", (ROOT / "docs" / "sheet_chars.txt").read_text(encoding="utf-8").strip(),
      "--size", "1024", "--sheet-px", "320", "--out", "{tmp}/chars", "--sheet", "{tmp}/sheet.png", "--no-progress"],
     "sheet.png", "docs/sheet.png"),
])
def test_shown_image_is_what_its_command_writes(tmp_path, argv, made, kept):
    argv = [a.format(tmp=tmp_path) for a in argv]
    assert cli.main(argv) in (0, None)
    _close(tmp_path / made, ROOT / kept)
    if made == "gallery.png":
        _close(tmp_path / "brush_view.png", ROOT / "docs" / "brush_view.png")
