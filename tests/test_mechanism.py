"""Loading, the mimic coupling, xacro arguments and the committed URDFs."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from conftest import EXACT, RCM_NAMES, random_q

import rcm_pin
from rcm_pin.catalog.files import check_rendered
from rcm_pin.errors import (
    InvalidInputError,
    RcmPinError,
    UnknownFrameError,
    UnknownMechanismError,
    XacroArgumentError,
)


def test_catalogue_lists_rcm_mechanisms():
    names = [s.name for s in rcm_pin.catalogue()]
    for name in RCM_NAMES:
        assert name in names


@pytest.mark.parametrize(("name", "nq"), [("rcm_bevel", 6), ("rcm_bevel_4dof", 4), ("rcm_belt", 6)])
def test_load_coordinates(name, nq):
    mech = rcm_pin.load(name)
    assert mech.nq == nq == mech.model.nq
    assert mech.coordinate_names == tuple(f"q{i + 1}" for i in range(nq))
    # Tree order makes Pinocchio's q order the papers' order.
    np.testing.assert_array_equal(mech.q_index, np.arange(nq))
    assert mech.model_full.nq > mech.model.nq  # transmissions are extra joints
    assert mech.frame_id("tool") == mech.tool_frame_id
    assert mech.rcm_frame_id >= 0


def test_coupling_reproduces_pinocchio_mimic_placements(rcm_mech):
    """Every body placement of the mimic model equals the no-mimic model at G q + c."""
    rng = np.random.default_rng(0)
    data_full = rcm_mech.model_full.createData()
    for q in random_q(rcm_mech, 200, rng):
        q_pin = rcm_mech.to_pin(q)
        pin.framesForwardKinematics(rcm_mech.model, rcm_mech.data, q_pin)
        pin.framesForwardKinematics(rcm_mech.model_full, data_full, rcm_mech.coupling.q_full(q_pin))
        for frame in rcm_mech.model.frames:
            fid_full = rcm_mech.model_full.getFrameId(frame.name)
            np.testing.assert_allclose(
                rcm_mech.data.oMf[rcm_mech.model.getFrameId(frame.name)].homogeneous,
                data_full.oMf[fid_full].homogeneous,
                atol=EXACT,
            )


def test_coupling_multipliers_follow_tooth_counts():
    mech = rcm_pin.load("rcm_bevel", z13=20, z14=40, z16=30, z17=15)
    G = mech.coupling.G
    names = mech.coupling.full_names
    # pair10 = −(z13/z14)(z16/z17)·q2 = −(0.5)(2)·q2, shaft15 = −(z13/z14)·q2.
    assert G[names.index("pair10"), 1] == pytest.approx(-1.0, abs=EXACT)
    assert G[names.index("shaft15"), 1] == pytest.approx(-0.5, abs=EXACT)


def test_unknown_mechanism_message():
    with pytest.raises(UnknownMechanismError, match=r"unknown mechanism 'nope'; valid: rcm_bevel"):
        rcm_pin.load("nope")


def test_errors_share_one_base():
    with pytest.raises(RcmPinError):
        rcm_pin.load("nope")


def test_unknown_xacro_argument_lists_valid_names():
    with pytest.raises(XacroArgumentError, match=r"unknown xacro argument 'l99'.*valid: .*l9"):
        rcm_pin.load("rcm_bevel", l99=0.3)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"l9": "abc"}, r"^l9='abc' is not a number for rcm_bevel.urdf.xacro; valid: \(0, 10\]"),
        ({"l9": "nan"}, r"^l9=nan is not finite for rcm_bevel.urdf.xacro; valid: \(0, 10\]"),
        (
            {"wrist": "maybe"},
            r"^wrist='maybe' is not a boolean for rcm_bevel.urdf.xacro; valid: true or false$",
        ),
        (
            {"l9": -0.1},
            r"^l9=-0.1 is out of range for rcm_bevel.urdf.xacro; valid: \(0, 10\] \[m\]",
        ),
    ],
)
def test_malformed_xacro_arguments(args, message):
    with pytest.raises(XacroArgumentError, match=message):
        rcm_pin.load("rcm_bevel", **args)


def test_fixed_argument_of_a_variant_is_refused():
    with pytest.raises(XacroArgumentError, match=r"'wrist' is fixed by mechanism rcm_bevel_4dof"):
        rcm_pin.load("rcm_bevel_4dof", wrist=True)


def test_unknown_frame_lists_frames(rcm_mech):
    with pytest.raises(UnknownFrameError, match=r"unknown frame 'nope' in rcm_.*valid: .*tool"):
        rcm_mech.frame_id("nope")


@pytest.mark.parametrize(
    ("q", "message"),
    [
        ([0.0, 0.1], r"q has shape \(2,\); valid: \(6,\)"),
        ([0.0, np.nan, 0.1, 0, 0, 0], r"q has NaN or infinite entries"),
    ],
)
def test_bad_configuration(q, message):
    mech = rcm_pin.load("rcm_bevel")
    with pytest.raises(InvalidInputError, match=message):
        rcm_pin.tool_pose(mech, np.array(q))


def test_committed_urdfs_are_fresh():
    assert check_rendered() == [], "run `rcm-pin urdf --update` and commit urdf/"


@pytest.mark.parametrize("name", RCM_NAMES)
def test_committed_urdf_loads_everywhere(name):
    import yourdfpy

    spec = rcm_pin.catalog.get_entry(name)
    robot = yourdfpy.URDF.load(str(spec.urdf_path), load_meshes=False)
    assert robot.validate()
    model = pin.buildModelFromUrdf(str(spec.urdf_path), mimic=True)
    assert model.nq == rcm_pin.load(name).nq


@pytest.mark.parametrize(
    ("q", "message"),
    [
        (np.array([0.1, np.nan, 0.05, 0, 0, 0]), "q has NaN or infinite entries: "),
        (np.array([0.1, np.inf, 0.05, 0, 0, 0]), "q has NaN or infinite entries: "),
        (np.array([0.1, 2e6, 0.05, 0, 0, 0]), "q has an entry of magnitude 2e+06; valid: "),
        (np.zeros(5), "q has shape (5,); valid: (6,) for rcm_bevel"),
    ],
)
def test_check_q_fast_path_keeps_the_full_checks(q, message):
    """A float64 (n,) array takes a one-hypot fast path; what fails it gets the full
    checks and their messages, and an accepted array is returned as a copy."""
    mech = rcm_pin.load("rcm_bevel")
    with pytest.raises(InvalidInputError) as err:
        mech.check_q(q)
    assert str(err.value).startswith(message)
    ok = np.array([0.1, -0.2, 0.05, 1e6, -1e6 + 1, 0.0])  # hypot > 1e6: the slow path accepts
    for arr in (ok, np.array([0.1, -0.2, 0.05, 0.3, 0.4, 0.5])):
        out = mech.check_q(arr)
        assert out is not arr
        np.testing.assert_array_equal(out, arr)


def test_mechanism_repr_is_a_short_summary():
    """Printing a Mechanism names it, its family, joints, frames and closures, never the
    URDF text (the dataclass repr used to print the whole file, ~20 KB)."""
    assert repr(rcm_pin.load("rcm_bevel")) == (
        "Mechanism(name='rcm_bevel', family='rcm', "
        "coordinates='pair4 pair7 pair24 pair23 pair26 pair27', tool_frame='tool', "
        "rcm_frame='rcm', closures=None)"
    )
    assert repr(rcm_pin.load("five_bar")) == (
        "Mechanism(name='five_bar', family='five_bar', coordinates='A1 B1 A2 B2', "
        "output_frame='tip_1', closures='1 × 3d', drives='A1 A2')"
    )
    assert "args={'l9': '0.25'}" in repr(rcm_pin.load("rcm_bevel", l9=0.25))


@pytest.mark.parametrize("name", rcm_pin.names())
def test_every_catalogue_repr_is_short(name):
    mech = rcm_pin.load(name)
    text = repr(mech)
    assert len(text) < 400, text
    assert "<robot" not in text and "\n" not in text
    assert str(mech) == text
