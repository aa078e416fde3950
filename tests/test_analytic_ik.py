"""Vectorised analytic IK: every branch, degeneracies, limits, typed errors."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rcm_pin.errors import (
    InvalidInputError,
    NotARotationError,
    SingularConfigurationError,
    UnreachablePoseError,
)
from rcm_pin.mechanisms.rcm.analytic_ik import (
    Degeneracy,
    ik_pose,
    ik_pose_4dof,
    ik_position,
)
from rcm_pin.mechanisms.rcm.closed_form import (
    WristType,
    output_axis,
    output_rotation,
    tool_pose,
    tool_position,
)
from rcm_pin.mechanisms.rcm.ik_solve import solve_pose
from rcm_pin.rotations import rot_x, rot_y, rot_z

A_B = np.array(
    [[0.75, -0.433, 0.5, 0], [0.5, 0.866, 0, 0], [-0.433, 0.25, 0.866, 0.01], [0, 0, 0, 1]]
)
PI = np.pi


def regular_q(n: int, wrist: str | None, seed: int = 0) -> np.ndarray:
    """Random q away from every degeneracy (|cos q2|, |sin q5| or |cos q5| > 0.05)."""
    rng = np.random.default_rng(seed)
    q = rng.uniform(-PI, PI, (n, 6 if wrist else 4))
    q[:, 2] = rng.choice([-1, 1], n) * rng.uniform(0.02, 0.2, n)
    q[:, 1] = np.where(np.abs(np.cos(q[:, 1])) < 0.05, 0.3, q[:, 1])
    if wrist == "zyz":
        q[:, 4] = np.where(np.abs(np.sin(q[:, 4])) < 0.05, 1.0, q[:, 4])
    elif wrist == "rpy":
        q[:, 4] = np.where(np.abs(np.cos(q[:, 4])) < 0.05, 0.4, q[:, 4])
    return q


def ang_dist(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Per-coordinate distance, angles modulo 2π, q3 (index 2) plain."""
    d = np.abs(np.angle(np.exp(1j * (a - b))))
    d[..., 2] = np.abs(a[..., 2] - b[..., 2])
    return d


def test_branch_identities() -> None:
    q1, q2 = np.random.default_rng(3).uniform(-3, 3, (2, 100))
    e4 = output_axis(q1, q2)
    assert np.allclose(output_axis(q1 + PI, PI - q2), e4, atol=1e-14)
    assert np.allclose(output_axis(q1 + PI, -q2), -e4, atol=1e-14)
    assert np.allclose(output_axis(q1, q2 + PI), -e4, atol=1e-14)
    r = output_rotation(q1, q2)
    assert np.allclose(output_rotation(q1 + PI, PI - q2), r @ rot_z(PI), atol=1e-14)
    assert np.allclose(output_rotation(q1 + PI, -q2), r @ rot_x(PI), atol=1e-14)
    assert np.allclose(output_rotation(q1, q2 + PI), r @ rot_y(PI), atol=1e-14)


@pytest.mark.parametrize("wrist", ["zyz", "rpy"])
def test_fk_of_every_branch(wrist: WristType) -> None:
    q = regular_q(10_000, wrist)
    t = tool_pose(q, wrist)
    sol = ik_pose(t, wrist)
    assert sol.q.shape == (10_000, 8, 6)
    assert (sol.degenerate == Degeneracy.NONE).all()
    back = tool_pose(sol.q.reshape(-1, 6), wrist).reshape(10_000, 8, 4, 4)
    assert np.abs(back - t[:, None]).max() < 1e-10
    assert (ang_dist(sol.q, q[:, None]).max(-1).min(-1) < 1e-9).all()  # q is a branch
    ang = sol.q[..., [0, 1, 3, 4, 5]]
    assert (ang > -PI).all() and (ang <= PI).all()
    pair = ang_dist(sol.q[:, :, None], sol.q[:, None]).max(-1)  # branches are distinct
    assert (pair + np.eye(8) > 1e-6).all()
    assert sol.projection_distance.max() < 1e-12


@given(
    st.lists(st.floats(-PI, PI), min_size=5, max_size=5),
    st.floats(0.01, 0.3),
    st.sampled_from(["zyz", "rpy"]),
)
@settings(max_examples=300, deadline=None)
def test_property_round_trip(ang: list[float], q3: float, wrist: WristType) -> None:
    q = np.array([ang[0], ang[1], q3, *ang[2:]])
    t = tool_pose(q, wrist)
    sol = ik_pose(t, wrist)
    if sol.degenerate[0] != Degeneracy.NONE:
        return
    back = tool_pose(sol.q[0], wrist)
    assert np.abs(back - t).max() < 1e-8
    assert ang_dist(sol.q[0], q).max(-1).min() < 1e-6


def test_paper_position_example() -> None:
    sol = ik_pose(A_B)
    assert 1e-5 < sol.projection_distance[0] < 1e-3  # A_b is rounded to 3 decimals
    paper = np.array([0, 0, 0.01, 0, 0.524, 0.524])
    assert ang_dist(sol.q[0], paper).max(-1).min() < 1e-3
    assert np.allclose(sol.q[0, 0], [0, 0, 0.01, 0, PI / 6, PI / 6], atol=5e-4)
    lower = np.array([-1, -1, 0.005, -1, 0, -1.0])
    (only,) = solve_pose(A_B, lower, -lower + [0, 0, 0.02, 0, 2, 0])
    assert np.allclose(only, sol.q[0, 0])


def test_ik_position() -> None:
    q = regular_q(1000, None)[:, :3]
    p = tool_position(q)
    sol = ik_position(p)
    assert sol.q.shape == (1000, 4, 3)
    back = tool_position(sol.q.reshape(-1, 3)).reshape(1000, 4, 3)
    assert np.abs(back - p[:, None]).max() < 1e-15
    assert (ang_dist(sol.q, q[:, None]).max(-1).min(-1) < 1e-12).all()
    assert (ik_position(p, +1).q[..., 2] > 0).all()
    assert (ik_position(p, -1).q[..., 2] < 0).all()
    deg = ik_position(np.array([[0, 0, 0], [0.1, 0, 0], [0, 0, 0.1]]))
    assert deg.degenerate.tolist() == [1, 2, 0]
    assert np.isnan(deg.q[0, :, :2]).all() and np.isnan(deg.q[1, :, 0]).all()
    assert np.allclose(deg.q[1, 0, 1:], [PI / 2, 0.1])


def test_four_dof() -> None:
    q = regular_q(2000, None, seed=5)
    t = tool_pose(q, None)
    sol = ik_pose_4dof(t)
    assert sol.q.shape == (2000, 2, 4)
    back = tool_pose(sol.q.reshape(-1, 4), None).reshape(2000, 2, 4, 4)
    assert np.abs(back - t[:, None]).max() < 1e-12
    assert (ang_dist(sol.q, q[:, None]).max(-1).min(-1) < 1e-9).all()
    at_a = tool_pose(np.array([0.2, 0.3, 0.0, 0.1]), None)  # p = 0 is regular for 4 DOF
    assert ik_pose(at_a, None).degenerate[0] == Degeneracy.NONE
    off = t[0].copy()
    off[:3, 3] += 1e-3 * off[:3, 0]
    with pytest.raises(UnreachablePoseError, match=r"0\.001 m off the tool z axis .*1e-09 m"):
        ik_pose_4dof(off)


def test_degeneracies() -> None:
    t_rcm = tool_pose(np.array([0.1, 0.2, 0.0, 0.3, 0.4, 0.5]))
    t_base = tool_pose(np.array([0.7, PI / 2, 0.1, 0.3, 0.4, 0.5]))
    t_wrist = tool_pose(np.array([0.1, 0.2, 0.1, 0.3, 0.0, 0.5]))
    t_rpy = tool_pose(np.array([0.1, 0.2, 0.1, 0.3, PI / 2, 0.5]), "rpy")
    sol = ik_pose(np.stack([t_rcm, t_base, t_wrist]))
    assert [Degeneracy(c) for c in sol.degenerate] == [
        Degeneracy.TOOL_AT_RCM, Degeneracy.AXIS_ALONG_BASE, Degeneracy.WRIST_ALIGNED]  # fmt: skip
    q = sol.q
    assert np.isnan(q[0][:, [0, 1, 3, 4, 5]]).all() and (q[0][:, 2] == 0).all()
    assert np.isnan(q[1][:, [0, 3, 5]]).all() and np.isclose(q[1, 0, 4], 0.4)
    assert np.isnan(q[2][:, [3, 5]]).all() and np.allclose(q[2, 0, :3], [0.1, 0.2, 0.1])
    assert ik_pose(t_rpy, "rpy").degenerate[0] == Degeneracy.WRIST_ALIGNED
    with pytest.raises(SingularConfigurationError, match=r"TOOL_AT_RCM.*valid poses have \|p\|"):
        solve_pose(t_rcm)
    with pytest.raises(SingularConfigurationError, match=r"AXIS_ALONG_BASE.*q1 is not determined"):
        solve_pose(t_base)
    with pytest.raises(SingularConfigurationError, match=r"only q4 \+ q6 = \+0\.800000 rad"):
        solve_pose(t_wrist)
    with pytest.raises(SingularConfigurationError, match=r"only q4 - q6 = -0\.200000 rad"):
        solve_pose(t_rpy, wrist_type="rpy")


@pytest.mark.parametrize("wrist", ["zyz", "rpy"])
@pytest.mark.parametrize("eps", [1e-3, 1e-6, 2e-9])
def test_near_singular_poses_stay_exact(wrist: WristType, eps: float) -> None:
    """Next to (not at) every degeneracy the solutions still reproduce T to ~1e-15."""
    q = regular_q(500, wrist, seed=11)
    sign = np.where(np.arange(500) % 2, 1.0, -1.0)
    q[:, 1] = sign * PI / 2 + eps * sign[::-1]
    q[:, 4] = (0.0 if wrist == "zyz" else PI / 2) + eps * sign
    t = tool_pose(q, wrist)
    sol = ik_pose(t, wrist)
    assert (sol.degenerate == Degeneracy.NONE).all()
    back = tool_pose(sol.q.reshape(-1, 6), wrist).reshape(500, 8, 4, 4)
    assert np.abs(back - t[:, None]).max() < 1e-12


def test_chunking_is_invisible(monkeypatch: pytest.MonkeyPatch) -> None:
    q = regular_q(1000, "zyz", seed=9)
    q[::97, 4] = 0.0  # wrist-aligned poses scattered across blocks
    t = tool_pose(q)
    ref = ik_pose(t)
    from rcm_pin.mechanisms.rcm import ik_tables

    monkeypatch.setattr(ik_tables, "CHUNK", 64)
    small = ik_pose(t)
    assert np.array_equal(ref.q, small.q, equal_nan=True)
    assert np.array_equal(ref.degenerate, small.degenerate)
    assert (small.degenerate[::97] == Degeneracy.WRIST_ALIGNED).all()


def test_limits_and_wrap() -> None:
    q = np.array([-PI / 2, 0.2, 0.1, 0.3, 0.4, 0.5])
    sol = ik_pose(tool_pose(q))
    lower = np.array([0.0, -1, 0.05, -PI, 0, -PI])
    upper = np.array([2 * PI, 1, 0.2, PI, PI, PI])
    ok = sol.within_limits(lower, upper)
    assert ok.shape == (1, 8) and ok[0].sum() == 1
    (only,) = solve_pose(tool_pose(q), lower, upper)
    assert np.allclose(only, q + [2 * PI, 0, 0, 0, 0, 0])  # q1 shifted by +2π into range
    tight = np.array([0.0, -0.1, 0.05, -0.1, 0, -0.1])
    with pytest.raises(UnreachablePoseError, match=r"no IK branch lies within .*closest branch"):
        solve_pose(tool_pose(q), tight, -tight + [0, 0, 0.25, 0, 0.1, 0])


def test_input_errors() -> None:
    t = np.tile(A_B, (10, 1, 1))
    t[5, 1, 2] = np.nan
    with pytest.raises(InvalidInputError, match=r"NaN or infinite entries \(first at pose 5\)"):
        ik_pose(t)
    with pytest.raises(InvalidInputError, match=r"4\) or \(\.\.\., 3, 4\), got \(3, 3\)"):
        ik_pose(np.eye(3))
    bad = A_B.copy()
    bad[3, 3] = 2.0
    with pytest.raises(InvalidInputError, match=r"pose 0 deviates by 1"):
        ik_pose(bad)
    with pytest.raises(InvalidInputError, match=r"T must have shape \(4, 4\) or \(3, 4\)"):
        solve_pose(np.stack([A_B, A_B]))
    skew = A_B.copy()
    skew[:3, :3] *= 1.5
    with pytest.raises(NotARotationError, match=r"distance to the nearest rotation 0\.866"):
        solve_pose(skew)
    with pytest.raises(InvalidInputError, match="wrist_type must be 'zyz', 'rpy' or None"):
        ik_pose(A_B, "xyz")  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match=r"q3_sign must be None, \+1 or -1"):
        ik_position([0, 0, 1], 2)
    with pytest.raises(InvalidInputError, match=r"limits must have shape \(6,\)"):
        ik_pose(A_B).within_limits(np.zeros(4), np.ones(4))


def test_three_by_four_and_unprojected() -> None:
    q = regular_q(50, "zyz", seed=4)
    t = tool_pose(q)
    a = ik_pose(t[:, :3])
    b = ik_pose(t, check_rotation=False)
    assert np.array_equal(a.q, b.q) and (b.projection_distance == 0).all()
    assert np.allclose(rot_y(0.0), np.eye(3))
