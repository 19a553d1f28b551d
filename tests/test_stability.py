"""The stiff and extreme cases of `bench stability`, run at reduced frame counts.

`brushwork bench stability` runs the same cases in full, plus >= 10,000 randomised frames.
"""
import pytest

from brushwork.bench import stability
from tolerances import PENETRATION_FRAC


@pytest.fixture(scope="module")
def rows():
    return {r["case"]: r for r in stability.run(frames_scale=0.3, seed=1, progress=False)}


NAMED = ["stiffness 1e2 m=2", "stiffness 1e4 m=2", "stiffness 1e2 m=3", "stiffness 1e4 m=3",
         "press 1.5 L below contact", "drag 1 L per frame", "exactly vertical", "tilt 1e-8 deg",
         "tilt 85 deg", "straight start", "1000 frames without motion", "random extreme jumps",
         "3 tufts", "5 tufts"]


@pytest.mark.parametrize("case", NAMED)
def test_extreme_case_stays_finite_and_above_the_paper(rows, case):
    r = rows[case]
    assert r["frames"] >= 5
    assert r["raised"] == "", r["raised"]
    assert r["nonfinite"] == 0
    assert r["worst_penetration_frac"] <= PENETRATION_FRAC, (case, r["worst_penetration_frac"])


def test_randomised_frames_stay_finite(rows):
    r = rows["random"]
    assert r["frames"] >= 200 and r["raised"] == "" and r["nonfinite"] == 0


@pytest.mark.parametrize("case", ["3 tufts", "5 tufts"])
def test_split_brush_cases_do_split(rows, case):
    # the children's own solves are in the case: the brush was split for part of it
    assert rows[case]["split_frames"] > 0
