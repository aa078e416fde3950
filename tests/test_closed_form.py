"""Closed-form kinematics of papers 000/003: identities and the worked position example."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from rcm_pin.errors import InvalidInputError
from rcm_pin.mechanisms.rcm.closed_form import (
    joint_axes,
    output_axis,
    tool_pose,
    tool_position,
    tool_rotation,
)
from rcm_pin.rotations import rot_x, rot_y, rot_z

A_B = np.array(
    [[0.75, -0.433, 0.5, 0], [0.5, 0.866, 0, 0], [-0.433, 0.25, 0.866, 0.01], [0, 0, 0, 1]]
)
Q6 = arrays(np.float64, 6, elements=st.floats(-4, 4, allow_nan=False))


def test_paper_position_example_forward() -> None:
    """FK of the published solution reproduces A_b up to its 3-decimal rounding."""
    q = np.array([0, 0, 0.01, 0, np.pi / 6, np.pi / 6])
    assert np.abs(tool_pose(q) - A_B).max() < 5e-4


def test_paper_element_ax1_errata() -> None:
    """The product gives A_x1 = c6(c2 c4 c5 − s2 s5) − c2 s4 s6 (printed: + c2 s4 s6)."""
    q = np.array([0.3, -0.7, 0.1, 0.9, 0.4, -1.2])
    c, s = np.cos(q), np.sin(q)
    ours = c[5] * (c[1] * c[3] * c[4] - s[1] * s[4]) - c[1] * s[3] * s[5]
    printed = -(c[5] * (s[1] * s[4] - c[1] * c[3] * c[4]) - c[1] * s[3] * s[5])
    assert np.isclose(tool_rotation(q)[0, 0], ours, atol=1e-14)
    assert not np.isclose(tool_rotation(q)[0, 0], printed)


@given(Q6)
@settings(max_examples=200, deadline=None)
def test_rotation_identities(q: np.ndarray) -> None:
    for wrist in ("zyz", "rpy"):
        r = tool_rotation(q, wrist)
        assert np.allclose(r.T @ r, np.eye(3), atol=1e-12)
        assert np.isclose(np.linalg.det(r), 1.0, atol=1e-12)
    r_out = rot_x(q[0]) @ rot_y(q[1])
    e4 = output_axis(q[0], q[1])
    assert np.allclose(e4, r_out[:, 2], atol=1e-15)
    assert np.allclose(tool_position(q), q[2] * e4, atol=1e-15)
    # the tool z axis is e4 rotated about the q5 axis; before the wrist it is e4
    assert np.allclose((r_out @ rot_z(q[3]))[:, 2], e4, atol=1e-15)


@given(Q6)
@settings(max_examples=200, deadline=None)
def test_position_paper_formulas(q: np.ndarray) -> None:
    x, y, z = tool_position(q)
    assert np.isclose(x, q[2] * np.sin(q[1]), atol=1e-15)
    assert np.isclose(y, -q[2] * np.sin(q[0]) * np.cos(q[1]), atol=1e-15)
    assert np.isclose(z, q[2] * np.cos(q[0]) * np.cos(q[1]), atol=1e-15)


def test_vectorised_matches_scalar() -> None:
    rng = np.random.default_rng(1)
    q = rng.uniform(-3, 3, (4, 5, 6))
    t = tool_pose(q)
    assert t.shape == (4, 5, 4, 4)
    assert np.allclose(t[2, 3], tool_pose(q[2, 3]), atol=0)
    assert np.allclose(t[..., 3, :], [0, 0, 0, 1])
    q4 = q[..., :4]
    r4 = tool_rotation(q4, None)
    ref = rot_x(q4[..., 0]) @ rot_y(q4[..., 1]) @ rot_z(q4[..., 3])
    assert np.allclose(r4, ref, atol=1e-15)


def test_joint_axes() -> None:
    rng = np.random.default_rng(2)
    q = rng.uniform(-3, 3, (50, 6))
    c, s = np.cos(q), np.sin(q)
    for wrist in ("zyz", "rpy"):
        ax = joint_axes(q, wrist)
        assert ax.shape == (50, 6, 3)
        assert np.allclose(np.linalg.norm(ax, axis=-1), 1.0, atol=1e-12)
        assert np.allclose(ax[:, 1], np.stack([0 * c[:, 0], c[:, 0], s[:, 0]], -1))
        r45 = rot_x(q[:, 0]) @ rot_y(q[:, 1]) @ rot_z(q[:, 3])
        assert np.allclose(ax[:, 4], r45[:, :, 1], atol=1e-14)  # e5 = R_out·Rz(q4)·y
        r = tool_rotation(q, wrist)
        assert np.allclose(ax[:, 5], r[:, :, 2 if wrist == "zyz" else 0], atol=1e-15)
    # the printed third component of e5 (c4 s1 − c1 s2 s4) is not a unit vector in general
    e5_printed = np.stack(
        [-c[:, 1] * s[:, 3], c[:, 0] * c[:, 3] - s[:, 0] * s[:, 1] * s[:, 3],
         c[:, 3] * s[:, 0] - c[:, 0] * s[:, 1] * s[:, 3]], -1)  # fmt: skip
    assert np.abs(np.linalg.norm(e5_printed, axis=-1) - 1).max() > 0.1
    assert joint_axes(q[:, :4], None).shape == (50, 4, 3)


def test_invalid_q() -> None:
    with pytest.raises(InvalidInputError, match=r"q must have shape \(\.\.\., 6\), got \(4,\)"):
        tool_pose(np.zeros(4))
    with pytest.raises(InvalidInputError, match=r"q must have shape \(\.\.\., 4\), got \(6,\)"):
        tool_pose(np.zeros(6), None)
    with pytest.raises(InvalidInputError, match="q contains NaN or infinite entries"):
        tool_pose(np.full(6, np.nan))
    with pytest.raises(InvalidInputError, match="wrist_type must be 'zyz', 'rpy' or None"):
        tool_pose(np.zeros(6), "xyz")  # type: ignore[arg-type]
