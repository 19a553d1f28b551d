"""BrushModel: presets, the parameter table, and bad input."""
import math

import pytest

import brushwork as bw


def test_presets_differ_in_size_and_stiffness():
    names = bw.BrushModel.presets()
    assert len(names) >= 2 and "medium" in names
    models = [bw.BrushModel.preset(n) for n in names]
    assert len({m.tuft_length for m in models}) == len(models)
    assert len({(m.bend_stiffness, m.stiffness_ratio) for m in models}) == len(models)
    for m in models:
        m.validate()
        lengths = m.segment_lengths()
        assert abs(lengths.sum() - m.tuft_length) < 1e-9 * m.tuft_length
        assert all(lengths[1:] < lengths[:-1]), "segments must shorten toward the tip"
        k = m.bend_kappa()
        assert all(k[1:] < k[:-1]), "the root is stiffer than the tip, joint by joint"
        # the hair-count law softens the thin tail beyond the geometric stiffness_ratio ...
        assert k[0] / k[-1] > m.stiffness_ratio
        # ... and without it the seed's geometric law is left, root : tip = stiffness_ratio
        m.stiffness_radius_power = 0.0
        k = m.bend_kappa()
        assert abs(k[0] / k[-1] - m.stiffness_ratio) < 1e-9 * m.stiffness_ratio


def test_unknown_preset_names_the_known_ones():
    with pytest.raises(ValueError, match="unknown brush preset 'huge'.*medium"):
        bw.BrushModel.preset("huge")


def test_every_parameter_documented_with_unit_and_range():
    table = bw.BrushModel.parameters()
    m = bw.BrushModel()
    assert len(table) >= 30
    for row in table:
        assert row["unit"] and row["doc"] and row["min"] <= row["max"], row
        value = getattr(m, row["name"])
        assert row["min"] <= float(value) <= row["max"], row["name"]
        assert row["unit"] in type(m).__dict__[row["name"]].__doc__ or row["unit"] == "-"


@pytest.mark.parametrize("field,value", [
    ("tuft_length", math.nan), ("tuft_length", -3.0), ("belly_radius", math.inf),
    ("exponent", 4.0), ("stiffness_ratio", 0.5), ("q_max", 0), ("n_segments", 40),
    ("collision_shrink", 0.0), ("tolerance", 1.0),
])
def test_out_of_range_field_raises_value_error_naming_it(field, value):
    m = bw.BrushModel.preset("medium")
    kept = getattr(m, field)
    with pytest.raises(ValueError, match=field):
        setattr(m, field, value)
    assert getattr(m, field) == kept, "a rejected value must leave the model unchanged"


def test_replace_changes_a_copy_and_checks_every_field():
    m = bw.BrushModel.preset("small")
    r = m.replace(exponent=3, q_max=50, tolerance=1e-8)
    assert (r.exponent, r.q_max, r.tolerance) == (3, 50, 1e-8)
    assert (m.exponent, m.q_max, m.tolerance) == (2, 40, 1e-5), "replace must not touch the original"
    assert r.tuft_length == m.tuft_length and r.belly_radius == m.belly_radius
    assert bw.Brush(r).step(bw.Pose((0.0, 0.0, 0.6 * r.tuft_length))).iterations >= 1   # a usable model
    with pytest.raises(TypeError, match="no field 'stiffnes'"):
        m.replace(stiffnes=2.0)
    with pytest.raises(ValueError, match="q_max"):
        m.replace(q_max=0)


def test_wrong_types_are_value_errors():
    m = bw.BrushModel()
    with pytest.raises(ValueError, match="n_segments.*integer"):
        m.n_segments = 5.5
    with pytest.raises(ValueError, match="collision.*True or False"):
        m.collision = 1
    with pytest.raises(ValueError, match="tuft_length.*number"):
        m.tuft_length = "long"


@pytest.mark.parametrize("kw,field", [
    (dict(position=(math.nan, 0, 10)), "position\\[0\\]"),
    (dict(position=(0, math.inf, 10)), "position\\[1\\]"),
    (dict(position=(0, 0, 1e30)), "position\\[2\\]"),
    (dict(position=(0, 0, 10), tilt_deg=95.0), "tilt_deg"),
    (dict(position=(0, 0, 10), tilt_deg=-1.0), "tilt_deg"),
    (dict(position=(0, 0, 10), azimuth_deg=math.nan), "azimuth_deg"),
    (dict(position=(0, 0, 10), twist_deg=math.inf), "twist_deg"),
])
def test_bad_pose_raises_value_error_naming_field(kw, field):
    with pytest.raises(ValueError, match=field):
        bw.Pose(**kw)

