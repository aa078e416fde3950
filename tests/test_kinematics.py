"""Pinocchio forward kinematics against the papers' closed form, yourdfpy, the RCM check."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import EXACT, RCM_NAMES, random_q

import rcm_pin
from rcm_pin.mechanisms.rcm import closed_form
from rcm_pin.mechanisms.rcm.closed_form import wrist_type


def _wrist(mech):
    return wrist_type(mech)  # None for 4-DOF


def test_pinocchio_fk_equals_closed_form(rcm_mech):
    rng = np.random.default_rng(1)
    qs = random_q(rcm_mech, 10_000, rng)
    poses = rcm_pin.tool_poses(rcm_mech, qs)
    expected = closed_form.tool_pose(qs, _wrist(rcm_mech))
    np.testing.assert_allclose(poses, expected, atol=EXACT)


def test_rpy_wrist_variant_equals_closed_form():
    mech = rcm_pin.load("rcm_bevel", wrist_type="rpy")
    assert wrist_type(mech) == "rpy"
    qs = random_q(mech, 2_000, np.random.default_rng(2))
    np.testing.assert_allclose(
        rcm_pin.tool_poses(mech, qs), closed_form.tool_pose(qs, "rpy"), atol=EXACT
    )


@pytest.mark.parametrize("name", RCM_NAMES)
def test_yourdfpy_fk_equals_pinocchio(name):
    import yourdfpy

    mech = rcm_pin.load(name)
    robot = yourdfpy.URDF(
        yourdfpy.URDF._parse_robot(yourdfpy.urdf.etree.fromstring(mech.urdf.encode())),
        load_meshes=False,
        build_scene_graph=True,
    )
    actuated = list(robot.actuated_joint_names)
    assert actuated == list(mech.joint_names)  # yourdfpy skips mimic joints too
    rng = np.random.default_rng(3)
    for q in random_q(mech, 300, rng):
        robot.update_cfg(dict(zip(actuated, q)))
        np.testing.assert_allclose(
            robot.get_transform("tool", "base"), rcm_pin.tool_pose(mech, q), atol=EXACT
        )


def test_rcm_error_is_zero(rcm_mech):
    rng = np.random.default_rng(4)
    errors = [rcm_pin.rcm_error(rcm_mech, q) for q in random_q(rcm_mech, 10_000, rng)]
    assert max(errors) < EXACT


@pytest.mark.parametrize(("args", "minimum"), [({"z14": 21}, 1e-4), ({"d4": 0.031}, 1e-4)])
def test_rcm_error_detects_a_broken_transmission(args, minimum):
    name = "rcm_bevel" if "z14" in args else "rcm_belt"
    mech = rcm_pin.load(name, **args)
    q = np.array([0.2, 0.5, 0.08, 0.0, 0.0, 0.0])
    assert rcm_pin.rcm_error(mech, q) > minimum
    assert rcm_pin.rcm_error(mech, np.zeros(6) + [0, 0, 0.08, 0, 0, 0]) < EXACT  # q2 = 0
