"""The serial branch kernel answers the near-aligned wrist band (SING_TOL < |sin q5| or
|cos q5| < 1e-3) as the numpy route does there: the scalar IK hands such a pose to the
vectorised code, which recomputes q6 from the well-conditioned q4 ± q6; the kernel
repeats that formula (``branches_function._near_aligned_q6``), so ``rcm_pin.inverse``
gives the same branches in the same order, the same limit flags, and q, output values
and residuals to 1e-12 (numpy's ufuncs may round an ulp away from the C library's; seen:
8.9e-16)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from test_branch_kernel import AGREE, _routes, assert_same

import rcm_pin
from rcm_pin.analysis.pose_target import plain_pose
from rcm_pin.mechanisms.rcm.ik_scalar import ik_pose_one
from rcm_pin.mechanisms.rcm.ik_tables import _NEAR, SING_TOL
from rcm_pin.model import serial_branches

#: The band's offsets from the aligned wrist [rad]: its two ends and between, both signs.
OFFSETS = [s * d for d in (2.0 * SING_TOL, 1e-7, 1e-5, 3e-4, 0.9 * _NEAR) for s in (-1, 1)]
CASES = [("rcm_bevel", "zyz"), ("rcm_belt", "zyz"), ("rcm_bevel", "rpy")]


def _mech(name, wrist):
    return rcm_pin.load(name, wrist_type=wrist) if wrist == "rpy" else rcm_pin.load(name)


def _aligned(wrist):
    """q5 where the wrist is aligned (h = |sin q5|, zyz, or |cos q5|, rpy, is 0) [rad]."""
    return (0.0, np.pi) if wrist == "zyz" else (np.pi / 2, -np.pi / 2)


def _band_pose(mech, q, wrist, q5):
    T = rcm_pin.tool_pose(mech, np.array([q[0], q[1], q[2], q[3], q5, q[5]]))
    assert ik_pose_one(T, wrist) is None  # the numpy route leaves the scalar fast path
    return T


@pytest.mark.parametrize(("name", "wrist"), CASES)
@pytest.mark.parametrize("offset", OFFSETS)
def test_the_kernel_answers_the_near_aligned_band_as_numpy(name, wrist, offset):
    mech = _mech(name, wrist)
    kernel = serial_branches.warm(mech)
    rng = np.random.default_rng(17)
    for aligned in _aligned(wrist):
        for q in rng.uniform(-np.pi, np.pi, (4, 6)):
            q[2] = rng.uniform(0.05, 0.12)  # [m]
            T = _band_pose(mech, q, wrist, aligned + offset)
            assert kernel(plain_pose(mech.output, T)) is not None
            assert_same(*_routes(mech, T), q_tol=AGREE)
            assert_same(*_routes(mech, T, limits=True), q_tol=AGREE)


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.floats(-1.0, 1.0), min_size=6, max_size=6),
    st.floats(np.log10(2.0 * SING_TOL), np.log10(0.9 * _NEAR)),
    st.sampled_from([-1.0, 1.0]),
    st.sampled_from(CASES),
)
@example([0.0, 0.5, 0.0, 0.0, 0.0, 0.0], -4.0, -1.0, CASES[0])  # q2 = π/2: p on the base axis
def test_any_near_aligned_pose_takes_the_kernel_with_numpys_results(unit, log_d, sign, case):
    """Any pose of the band (the wrist within 2e-9 .. 9e-4 rad of aligned, any q1, q2, q4,
    q6 over a turn, q3 in [0.05, 0.1] m). Where the tool point also lies on the base axis
    (q2 = ±π/2: ρ = |(p_y, p_z)| ≤ SING_TOL·|p|, the position's own degeneracy) the kernel
    declines as documented; both routes must still agree there."""
    name, wrist = case
    mech = _mech(name, wrist)
    q = np.array(unit) * np.pi
    q[2] = 0.05 + 0.05 * abs(unit[2])  # [m]
    aligned = _aligned(wrist)[int(unit[4] > 0.0)]
    T = _band_pose(mech, q, wrist, aligned + sign * 10.0**log_d)
    p = T[:3, 3]
    if np.hypot(p[1], p[2]) > 10.0 * SING_TOL * np.linalg.norm(p):
        assert serial_branches.warm(mech)(plain_pose(mech.output, T)) is not None
    assert_same(*_routes(mech, T), q_tol=AGREE)
