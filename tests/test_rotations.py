"""Elementary rotations, RPY angles, projection onto SO(3), pose parsing."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rcm_pin.errors import InvalidInputError, NotARotationError
from rcm_pin.rotations import (
    matrix_to_rpy,
    pose_from_matrix,
    project_to_rotation,
    rot_x,
    rot_y,
    rot_z,
    rpy_to_matrix,
)

A_B = np.array(
    [[0.75, -0.433, 0.5, 0], [0.5, 0.866, 0, 0], [-0.433, 0.25, 0.866, 0.01], [0, 0, 0, 1]]
)
angles = st.floats(-np.pi, np.pi, allow_nan=False)


def test_elementary_shapes_and_orthonormality() -> None:
    a = np.linspace(-3, 3, 12).reshape(3, 4)
    for f in (rot_x, rot_y, rot_z):
        r = f(a)
        assert r.shape == (3, 4, 3, 3)
        assert np.allclose(r @ np.swapaxes(r, -1, -2), np.eye(3), atol=1e-12)
        assert np.allclose(np.linalg.det(r), 1.0, atol=1e-12)
    assert rot_x(0.3).shape == (3, 3)


def test_elementary_axes() -> None:
    # rotation by pi/2 maps the next axis: Rx y = z, Ry z = x, Rz x = y
    e = np.eye(3)
    assert np.allclose(rot_x(np.pi / 2) @ e[1], e[2], atol=1e-15)
    assert np.allclose(rot_y(np.pi / 2) @ e[2], e[0], atol=1e-15)
    assert np.allclose(rot_z(np.pi / 2) @ e[0], e[1], atol=1e-15)


@given(angles, st.floats(-1.5, 1.5), angles)
@settings(max_examples=200, deadline=None)
def test_rpy_round_trip(a: float, b: float, g: float) -> None:
    r = rpy_to_matrix(a, b, g)
    # the papers' elements
    assert np.isclose(r[0, 0], np.cos(b) * np.cos(g), atol=1e-12)
    assert np.isclose(r[2, 2], np.cos(a) * np.cos(b), atol=1e-12)
    assert np.isclose(r[2, 1], np.cos(b) * np.sin(a), atol=1e-12)
    x2 = np.cos(g) * np.sin(a) * np.sin(b) - np.cos(a) * np.sin(g)
    assert np.isclose(r[0, 1], x2, atol=1e-12)
    back = matrix_to_rpy(r)
    assert np.allclose(rpy_to_matrix(*back), r, atol=1e-12)


def test_rpy_gimbal_lock() -> None:
    r = rpy_to_matrix(0.4, np.pi / 2, 0.1)
    a, b, g = matrix_to_rpy(r)
    assert g == 0.0
    assert np.allclose(rpy_to_matrix(a, b, g), r, atol=1e-12)


def test_project_paper_matrix() -> None:
    proj, dist = project_to_rotation(A_B[:3, :3])
    assert 1e-5 < dist < 1e-3  # rounded to three decimals
    assert np.allclose(proj.T @ proj, np.eye(3), atol=1e-14)
    assert np.isclose(np.linalg.det(proj), 1.0)
    assert np.isclose(dist, np.linalg.norm(A_B[:3, :3] - proj))


def test_project_batch_and_exact() -> None:
    r = rot_z(np.linspace(0, 1, 5)) @ rot_x(0.3)
    proj, dist = project_to_rotation(r)
    assert proj.shape == (5, 3, 3) and dist.shape == (5,)
    assert np.allclose(proj, r, atol=1e-14) and dist.max() < 1e-14


def test_project_rejects_reflection_and_far() -> None:
    with pytest.raises(NotARotationError, match=r"nearest rotation 2 exceeds the tolerance 0\.01"):
        project_to_rotation(np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(NotARotationError, match=r"exceeds the tolerance 0\.001"):
        project_to_rotation(1.1 * np.eye(3), tol=1e-3)


def test_project_invalid_input() -> None:
    with pytest.raises(InvalidInputError, match=r"R must have shape \(\.\.\., 3, 3\), got \(4, 4"):
        project_to_rotation(np.eye(4))
    bad = np.eye(3)
    bad[0, 0] = np.nan
    with pytest.raises(InvalidInputError, match="R contains NaN or infinite entries"):
        project_to_rotation(bad)


def test_pose_from_matrix() -> None:
    r, p = pose_from_matrix(A_B)
    assert np.array_equal(r, A_B[:3, :3]) and np.array_equal(p, [0, 0, 0.01])
    r, p = pose_from_matrix(np.stack([A_B[:3], A_B[:3]]))
    assert r.shape == (2, 3, 3) and p.shape == (2, 3)
    bad = A_B.copy()
    bad[3, 0] = 0.5
    with pytest.raises(InvalidInputError, match=r"last row of T must be \[0, 0, 0, 1\]"):
        pose_from_matrix(bad)
    with pytest.raises(InvalidInputError, match=r"4\) or \(\.\.\., 3, 4\), got \(3, 3\)"):
        pose_from_matrix(np.eye(3))
