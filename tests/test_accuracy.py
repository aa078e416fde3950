"""Accuracy: first-order sensitivities vs the nonlinear (re-rendered / perturbed) result."""

from __future__ import annotations

import numpy as np
import pytest

import rcm_pin
from rcm_pin.errors import InvalidInputError
from rcm_pin.mechanisms.rcm import PLACEMENT_JOINTS
from rcm_pin.mechanisms.rcm import accuracy as acc

Q = np.array([0.5, 0.8, 0.085, 0.2, 0.5, 0.1])


def _agree(d, change, delta=1e-5):
    lin, nonlin = d * delta, change(delta)
    scale = max(np.abs(nonlin).max(), 1e-300)
    if scale < 1e-14:  # insensitive output: both vanish
        assert np.abs(lin).max() < 1e-12
        return
    assert np.abs(lin - nonlin).max() / scale < 1e-3


@pytest.mark.parametrize(
    ("name", "params"),
    [("rcm_bevel", ("l9", "a7_x", "z13", "z22")), ("rcm_belt", ("a7_z", "d1", "d4"))],
)
def test_xacro_first_order_matches_rerender(name, params):
    for p in params:
        d, change = acc.xacro_sensitivity(rcm_pin.load(name), Q, p)
        _agree(d, change)


def test_placement_first_order_matches_perturbed_model():
    mech = rcm_pin.load("rcm_bevel")
    for joint in PLACEMENT_JOINTS:
        for k in range(6):
            d, change = acc.placement_sensitivity(mech, Q, joint, k)
            _agree(d, change)


def test_which_errors_move_the_rcm_point():
    name = rcm_pin.load("rcm_bevel")
    # consistent design changes keep the parallelogram: the line still passes through A
    for p in ("l9", "a7_x", "a7_z"):
        d, _ = acc.xacro_sensitivity(name, Q, p)
        assert np.abs(d[6:]).max() < 1e-8
    # a tooth-count error breaks the equal-rotation transmission: the line misses A
    d, _ = acc.xacro_sensitivity(name, Q, "z13")
    assert np.linalg.norm(d[6:]) > 1e-4
    d, _ = acc.placement_sensitivity(name, Q, "pair24", 0)  # lateral offset of the slide
    np.testing.assert_allclose(np.linalg.norm(d[6:]), 1.0, atol=1e-6)


def test_errors():
    with pytest.raises(InvalidInputError) as exc:
        acc.xacro_sensitivity(rcm_pin.load("rcm_bevel"), Q, "m_tool")
    assert str(exc.value) == (
        "xacro parameter 'm_tool' not in rcm_bevel; valid: l9, a7_x, a7_z, z13, z14, z16, "
        "z17, z18, z19, z21, z22"
    )


@pytest.mark.parametrize(
    ("name", "kind", "params"),
    [
        ("rcm_bevel", "RcmAccuracy", 11),
        ("spherical_3rrr", "Spherical3RRRAccuracy", 6),
        ("translational_3ppapa", "Translational3PPaPaAccuracy", 3),
        ("four_bar", "PlacementAccuracy", 0),
        ("ur5", "PlacementAccuracy", 0),
    ],
)
def test_one_accuracy_model_per_mechanism_and_one_row_shape(name, kind, params):
    """The resolver gives the family's model or the default; every row prints one line
    and keeps its table's JSON keys; the hooks are gone from Family."""
    from rcm_pin.analysis.accuracy import AccuracyRow, accuracy_model
    from rcm_pin.analysis.capabilities import reference_poses
    from rcm_pin.model.family import Family

    assert not hasattr(Family, "accuracy_report") and not hasattr(Family, "accuracy_parameters")
    m = rcm_pin.load(name)
    model = accuracy_model(m)
    assert type(model).__name__ == kind and len(model.parameters(m)) == params
    rep = model.report(m, reference_poses(m).accuracy(m))
    out = rep.to_dict()
    assert list(out)[:2] == ["mechanism", "q"] and list(out)[-1] == "rows"
    assert all(isinstance(r, AccuracyRow) for r in rep.rows)
    assert [dict(r.fields) for r in rep.rows] == out["rows"]
    assert len(rep.lines()) == len(out["rows"]) and all(rep.lines())
