"""Analytic IK through a loaded Mechanism: every branch reproduces the pose in Pinocchio."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_q

import rcm_pin
from rcm_pin.errors import (
    NotARotationError,
    SingularConfigurationError,
    UnknownMechanismError,
    UnreachablePoseError,
)
from rcm_pin.mechanisms.rcm.inverse import solve_ik, solve_ik_position, solve_ik_within_limits
from rcm_pin.report.position import A_B, Q_PUBLISHED


def test_every_branch_reproduces_the_pose_in_pinocchio(rcm_mech):
    rng = np.random.default_rng(10)
    for q in random_q(rcm_mech, 300, rng, margin=0.01):
        T = rcm_pin.tool_pose(rcm_mech, q)
        result = solve_ik(rcm_mech, T)
        assert result.within_limits.any()
        # 6-DOF: 4 position x 2 wrist branches; 4-DOF: the tool z axis fixes the sign of q3.
        assert len(result.q) == (8 if rcm_mech.nq == 6 else 2)
        for branch in result.q:
            np.testing.assert_allclose(rcm_pin.tool_pose(rcm_mech, branch), T, atol=1e-10)
        # The configuration we started from is one of the branches.
        assert np.min(np.abs(result.q - q).max(axis=1)) < 1e-9


def test_paper_example_is_among_the_branches():
    mech = rcm_pin.load("rcm_bevel")
    result = solve_ik(mech, A_B)
    assert np.min(np.abs(result.q - Q_PUBLISHED).max(axis=1)) < 5e-4
    assert not result.within_limits.any()  # q3 = 0.01 m is below the rig's 0.05 m
    assert result.projection_distance == pytest.approx(3.89e-5, rel=1e-2)


def test_position_only_for_four_dof():
    mech = rcm_pin.load("rcm_bevel_4dof")
    p = np.array([0.02, -0.03, 0.09])
    result = solve_ik_position(mech, p)
    for q in result.q:
        q_full = np.concatenate([q, [0.0]])
        np.testing.assert_allclose(rcm_pin.tool_pose(mech, q_full)[:3, 3], p, atol=1e-12)
    assert result.within_limits.sum() == 1


def test_singular_pose_is_reported():
    mech = rcm_pin.load("rcm_bevel")
    T = np.eye(4)
    with pytest.raises(SingularConfigurationError, match=r"TOOL_AT_RCM"):
        solve_ik(mech, T)
    with pytest.raises(SingularConfigurationError, match=r"AXIS_ALONG_BASE"):
        solve_ik_position(mech, [0.1, 0.0, 0.0])


def test_not_a_rotation():
    mech = rcm_pin.load("rcm_bevel")
    T = np.eye(4)
    T[:3, 3] = [0.0, 0.0, 0.08]
    T[0, 0] = 1.5
    with pytest.raises(NotARotationError, match=r"from SO\(3\)|rotation"):
        solve_ik(mech, T)


def test_unreachable_within_limits_lists_limits():
    mech = rcm_pin.load("rcm_bevel")
    from rcm_pin.mechanisms.rcm import closed_form

    T = closed_form.tool_pose(np.array([0.1, 0.2, 0.5, 0.3, 0.4, 0.5]))  # q3 > 0.12 m limit
    with pytest.raises(UnreachablePoseError, match=r"no IK branch lies within the joint limits"):
        solve_ik_within_limits(mech, T)


def test_non_rcm_mechanism_is_refused(tmp_path):
    path = tmp_path / "arm.urdf"
    path.write_text(
        '<robot name="arm"><link name="a"/><link name="b"/>'
        '<joint name="j" type="revolute"><parent link="a"/><child link="b"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        "</robot>"
    )
    mech = rcm_pin.load(path, tool_frame="b")
    with pytest.raises(UnknownMechanismError, match=r"analytic IK is defined for the RCM"):
        solve_ik(mech, np.eye(4))
