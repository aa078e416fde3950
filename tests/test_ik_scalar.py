"""The one-pose fast path of the analytic IK gives exactly the vectorised branches."""

from __future__ import annotations

import numpy as np
import pytest

from rcm_pin.mechanisms.rcm import analytic_ik as ai
from rcm_pin.mechanisms.rcm.closed_form import tool_pose
from rcm_pin.mechanisms.rcm.ik_scalar import ik_pose_one


@pytest.mark.parametrize("wrist", ["zyz", "rpy"])
def test_scalar_branches_equal_the_vectorised_ones(wrist):
    rng = np.random.default_rng(11)
    q = rng.uniform(-np.pi, np.pi, (500, 6))
    q[:, 2] = rng.uniform(0.05, 0.12, 500)  # [m]
    poses = tool_pose(q, wrist)
    vec = ai.ik_pose(poses, wrist)
    used = 0
    for i, T in enumerate(poses):
        fast = ik_pose_one(np.ascontiguousarray(T), wrist)
        one = ai.ik_pose(np.ascontiguousarray(T), wrist)  # the dispatching entry point
        np.testing.assert_allclose(one.q[0], vec.q[i], rtol=0, atol=1e-12)
        assert one.degenerate[0] == vec.degenerate[i]
        if fast is not None:
            used += 1
            np.testing.assert_allclose(fast[0], vec.q[i], rtol=0, atol=1e-12)
            np.testing.assert_allclose(fast[1], vec.projection_distance[i], rtol=0, atol=1e-15)
    assert used >= 490  # all but the near-aligned-wrist band |sin q5| < 1e-3


@pytest.mark.parametrize(
    "case",
    ["tool at A", "axis along the base", "wrist aligned", "not a rotation", "NaN", "bad last row"],
)
def test_poses_the_fast_path_leaves_to_the_vectorised_code(case):
    q = np.array([0.3, -0.2, 0.08, 0.4, 0.7, -0.5])
    if case == "tool at A":
        q[2] = 0.0
    elif case == "axis along the base":
        q[1] = np.pi / 2
    elif case == "wrist aligned":
        q[4] = 1e-4
    T = np.ascontiguousarray(tool_pose(q, "zyz"))
    if case == "not a rotation":
        T[0, 0] += 1e-6
    elif case == "NaN":
        T[1, 1] = np.nan
    elif case == "bad last row":
        T[3, 0] = 1e-10
    assert ik_pose_one(T, "zyz") is None
    if case != "NaN":  # the vectorised code handles (or refuses) the pose as before
        np.testing.assert_array_equal(ai.ik_pose(T, "zyz").q, ai.ik_pose(T[None], "zyz").q)
