"""Dry-brush texture: streaks where a style dries the brush, none in kai, no repeat, streaks along
the stroke, and the same texture whatever the output's resolution (brushwork.bench.texture)."""
import numpy as np
import pytest

from brushwork.bench import texture


@pytest.fixture(scope="module")
def dry8():
    """The long dry stroke at 8 px/mm."""
    return texture.dry_stroke(8.0)


def test_no_repeat_in_a_long_dry_stroke(dry8):
    assert texture.repeat_score(dry8, 8.0)["repeat"] < 0.4


def test_the_repeat_detector_finds_a_repeating_grain():
    score = texture.repeat_score(texture.dry_stroke(8.0, grain_image=texture.control_grain(3)), 8.0)
    assert score["repeat"] > 0.5, score


def test_streaks_run_along_the_stroke(dry8):
    # the stroke runs along +x: its texture stays alike 2 mm along, not 2 mm across
    import cv2

    core = cv2.erode(texture.inside_mask(dry8, 8.0).astype(np.uint8), np.ones((9, 9), np.uint8)).astype(bool)
    ac, _ = texture.autocorrelation(dry8, core)
    along, across = ac[0, 16], ac[16, 0]
    assert along > 0.5 and across < 0.3, (along, across)


def test_xing_exits_open_into_streaks_and_kai_stays_solid():
    rows = {r["style"]: r for r in texture.exits("永", 384)}
    assert rows["xing"]["exit_white"] > 0.02, rows
    assert rows["kai"]["exit_white"] < 0.01, rows
    assert rows["xing"]["exit_white"] > 4 * rows["kai"]["exit_white"], rows


def test_the_same_texture_at_two_resolutions():
    r = texture.resolution_agreement(coarse=4.0, fine=12.0)
    assert r["white_coarse"] > 0.02 and r["white_fine"] > 0.02, r      # there is texture to compare
    assert abs(r["ink_coarse"] - r["ink_fine"]) < 0.03, r
    assert r["blurred_corr"] > 0.9, r


def test_speed_dries_the_brush():
    slow = texture.dry_stroke(4.0, dry_speed=0.0, grain=False, split_map=False)
    fast = texture.dry_stroke(4.0, dry_speed=0.4, grain=False, split_map=False)
    inside = texture.inside_mask(slow, 4.0)
    assert texture.white_fraction(fast, inside) > texture.white_fraction(slow, inside) + 0.05
