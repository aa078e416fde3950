"""``IKSolutions.fit_limits`` (one pass of np.where) equals the previous masked updates.

The reference below is the previous implementation: q, then q + 2π, then q − 2π (angles
only) wherever strictly closer to the box. Both must agree bit for bit (−0.0 and NaN
included) for every box, bounded or not.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rcm_pin.errors import InvalidInputError
from rcm_pin.mechanisms.rcm.analytic_ik import ik_pose
from rcm_pin.mechanisms.rcm.closed_form import tool_pose
from rcm_pin.mechanisms.rcm.ik_solutions import IKSolutions


def reference_fit(q, lo, up, tol=1e-12):
    angle = np.arange(q.shape[-1]) != 2

    def violation(x):
        return np.maximum(lo - x, 0.0) + np.maximum(x - up, 0.0)

    best, viol = q.copy(), violation(q)
    for s in (2 * np.pi, -2 * np.pi):
        cand = q + s * angle
        v = violation(cand)
        better = v < viol
        best[better], viol[better] = cand[better], v[better]
    return best, (viol <= tol).all(-1)


def branches() -> IKSolutions:
    rng = np.random.default_rng(5)
    q = rng.uniform(-4.0, 4.0, (200, 6))
    q[:, 2] = rng.uniform(-0.2, 0.2, 200)
    q[::7, 1], q[::5, 2] = -0.0, -0.0
    sol = ik_pose(tool_pose(q, "zyz"), "zyz")
    extra = np.concatenate([q[:, None, :], np.full((200, 1, 6), np.nan)], axis=1)
    return IKSolutions(np.concatenate([sol.q, extra], axis=1), sol.degenerate,
                       sol.projection_distance, "zyz")  # fmt: skip


SOL = branches()
bound = st.floats(-8.0, 8.0) | st.sampled_from([-np.inf, np.inf, 0.0, np.pi, -np.pi])


@settings(max_examples=80, deadline=None, derandomize=True)
@given(a=st.lists(bound, min_size=6, max_size=6), b=st.lists(bound, min_size=6, max_size=6))
def test_fit_equals_the_masked_updates_bit_for_bit(a, b):
    lo, up = np.minimum(a, b), np.maximum(a, b)
    lo[lo == np.inf], up[up == -np.inf] = 0.0, 0.0  # keep lower <= upper
    lo, up = np.minimum(lo, up), np.maximum(lo, up)
    best, ok = SOL.fit_limits(lo, up)
    ref, ref_ok = reference_fit(SOL.q, lo, up)
    np.testing.assert_array_equal(best, ref)
    np.testing.assert_array_equal(np.signbit(best), np.signbit(ref))
    np.testing.assert_array_equal(ok, ref_ok)
    assert best is not SOL.q


def test_bad_limits_are_refused():
    with pytest.raises(InvalidInputError, match=r"shape \(6,\)"):
        SOL.fit_limits(np.zeros(5), np.ones(5))
    with pytest.raises(InvalidInputError, match="lower <= upper"):
        SOL.fit_limits(np.ones(6), np.zeros(6))
    with pytest.raises(InvalidInputError, match="no NaN"):
        SOL.fit_limits(np.full(6, np.nan), np.ones(6))
