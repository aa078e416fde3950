"""The one-pass branch check of a serial inverse equals the per-branch route it replaced.

``rcm_pin.inverse`` reads a plain pose target in scalar arithmetic
(:mod:`rcm_pin.analysis.pose_target`) and checks every branch in one pass
(:func:`~rcm_pin.analysis.branch_check.check_branches`); the reference is the previous
route: ``Output.coerce`` of the target, the family's candidates, then
:func:`~rcm_pin.analysis.branch_check.check_branches_reference` branch after branch.
Both must give the same branches in the same order (to 1e-12) and the same typed errors.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_q
from hypothesis import given, settings
from hypothesis import strategies as st

import rcm_pin
from rcm_pin.analysis import branch_check
from rcm_pin.analysis.branch_check import (
    BRANCH_TOL,
    check_branches,
    check_branches_reference,
)
from rcm_pin.analysis.branch_check import placement as _frame
from rcm_pin.analysis.capabilities import position_solver
from rcm_pin.analysis.pose_target import KEEP_TOL, plain_pose
from rcm_pin.analysis.position import _as_value
from rcm_pin.errors import InvalidInputError, NotARotationError, SolverError
from rcm_pin.model.family import Branch
from rcm_pin.model.output import Output

#: Serial mechanisms whose inverse is a closed form (the rcm family): every pose.
CLOSED_FORM = ("rcm_bevel", "rcm_bevel_4dof", "rcm_belt")
#: Serial mechanisms on the numeric route: the check itself, on branches of known q.
NUMERIC = ("rcm_two_mass", "panda", "ur5")


@pytest.fixture(scope="module", params=CLOSED_FORM + NUMERIC)
def serial(request):
    return rcm_pin.load(request.param)


def reference_inverse(mech, target, coords=None):
    """The previous route of ``rcm_pin.inverse`` (serial, no ``limits``): (given, sols)."""
    output = mech.output if coords is None else mech.output.subset(coords)
    value = output.coerce(_as_value(output, target))
    found = position_solver(mech).inverse(mech, value, output)
    return value, check_branches_reference(mech, output, value, found.branches)


def no_reference(*args):
    raise AssertionError("the one-pass check fell back to the per-branch route")


def assert_same(result, given, sols):
    np.testing.assert_allclose(result.given, given, rtol=0, atol=1e-12)
    assert [s.mode for s in result.solutions] == [s.mode for s in sols]
    for a, b in zip(result.solutions, sols, strict=True):
        np.testing.assert_allclose(a.q, b.q, rtol=0, atol=1e-12)
        np.testing.assert_allclose(a.output, b.output, rtol=0, atol=1e-12)
        assert a.residual == pytest.approx(b.residual, abs=1e-12)
        assert (a.iterations, a.within_limits) == (b.iterations, b.within_limits)


@pytest.mark.parametrize("name", CLOSED_FORM)
def test_inverse_equals_the_per_branch_route_on_random_poses(name):
    mech = rcm_pin.load(name)
    rng = np.random.default_rng(27)
    for q in random_q(mech, 40, rng, margin=0.01):
        T = rcm_pin.tool_pose(mech, q)
        p = T[:3, 3]
        with pytest.MonkeyPatch.context() as m:  # the one-pass check serves every pose
            m.setattr(branch_check, "check_branches_reference", no_reference)
            new, new_p = rcm_pin.inverse(mech, T), rcm_pin.inverse(mech, p, ("x", "y", "z"))
        assert_same(new, *reference_inverse(mech, T))
        assert_same(new_p, *reference_inverse(mech, p, ("x", "y", "z")))


@pytest.mark.parametrize("name", CLOSED_FORM)
def test_a_target_off_so3_takes_the_projecting_route_with_the_same_result(name):
    mech = rcm_pin.load(name)
    rng = np.random.default_rng(28)
    for q in random_q(mech, 10, rng, margin=0.01):
        T = rcm_pin.tool_pose(mech, q)
        T[:3, :3] += 1e-9 * rng.standard_normal((3, 3))  # far beyond KEEP_TOL
        assert plain_pose(mech.output, T) is None
        assert_same(rcm_pin.inverse(mech, T), *reference_inverse(mech, T))
        assert_same(rcm_pin.inverse(mech, T[:3].tolist()), *reference_inverse(mech, T))


def test_plain_pose_keeps_only_what_the_general_route_accepts():
    mech = rcm_pin.load("rcm_bevel")
    out = mech.output
    T = rcm_pin.tool_pose(mech, mech.home)
    value = plain_pose(out, T)
    assert value is not None
    np.testing.assert_allclose(value, out.coerce(_as_value(out, T)), rtol=0, atol=KEEP_TOL)
    np.testing.assert_array_equal(plain_pose(out, T[:3]), value)
    bad = {
        "int matrix": np.eye(4, dtype=int),
        "list": T.tolist(),
        "shape": T[:3, :3].copy(),
        "last row": T + np.diag([0, 0, 0, 1e-6]),
        "NaN": np.where(np.eye(4) > 0, np.nan, T),
        "huge": T + 2e6 * (np.arange(16).reshape(4, 4) == 3),
        "reflection": T @ np.diag([1.0, 1.0, -1.0, 1.0]),
        "off SO(3)": T + 1e-12 * (np.arange(16).reshape(4, 4) == 0),
    }
    for label, target in bad.items():
        assert plain_pose(out, target) is None, label
    assert plain_pose(Output(out.frame, ("x", "y", "z"), out.frame_id), T) is None
    with pytest.raises(NotARotationError):
        rcm_pin.inverse(mech, bad["reflection"])
    with pytest.raises(InvalidInputError):
        rcm_pin.inverse(mech, bad["NaN"])


def shifted_branches(mech, q):
    """q and copies with revolute coordinates moved by ±2π: every one meets FK(q)."""
    out = [Branch(q.copy(), "b0")]
    for k, s in enumerate((2 * np.pi, -2 * np.pi), start=1):
        shifted = q.copy()
        shifted[mech.revolute] += s
        out.append(Branch(shifted, f"b{k}"))
    return out


OUTPUTS = (("x", "y", "z", "rotation"), ("x", "y", "z"), ("rotation",), ("z", "rx", "y"),
           ("ry",), ("rz", "x"))  # fmt: skip


@settings(max_examples=30, deadline=None, derandomize=True)
@given(data=st.data())
def test_check_equals_the_reference_for_every_output(serial, data):
    mech = serial
    u = data.draw(st.lists(st.floats(0.01, 0.99), min_size=mech.nq, max_size=mech.nq))
    q = mech.lower + np.array(u) * (np.minimum(mech.upper, 3) - np.maximum(mech.lower, -3))
    q = np.clip(q, mech.lower, mech.upper)
    coords = data.draw(st.sampled_from(OUTPUTS))
    output = Output(mech.output.frame, coords, mech.output.frame_id)
    branches = shifted_branches(mech, q)
    target = output.value(_frame(mech, q))
    ref = check_branches_reference(mech, output, target, branches)
    with pytest.MonkeyPatch.context() as m:  # good branches never take the reference route
        m.setattr(branch_check, "check_branches_reference", no_reference)
        new = check_branches(mech, output, target, branches)
    assert [s.mode for s in new] == [s.mode for s in ref]
    for a, b in zip(new, ref, strict=True):
        np.testing.assert_allclose(a.q, b.q, rtol=0, atol=1e-12)
        np.testing.assert_allclose(a.output, b.output, rtol=0, atol=1e-12)
        assert a.residual == pytest.approx(b.residual, abs=1e-12)
        assert a.residual <= BRANCH_TOL
        assert a.within_limits == b.within_limits


def raised(fn):
    with pytest.raises((SolverError, InvalidInputError)) as info:
        fn()
    return type(info.value), str(info.value)


def test_a_missing_or_malformed_branch_raises_the_reference_error(serial):
    mech = serial
    q = np.clip(mech.home, mech.lower, mech.upper)
    output = mech.output
    target = output.value(_frame(mech, q))
    good = shifted_branches(mech, q)
    far = q.copy()
    far[0] += 0.3
    cases = {
        "miss": [good[0], Branch(far, "far"), good[1]],
        "NaN": [good[0], Branch(np.full(mech.nq, np.nan), "nan")],
        "length": [Branch(q[:-1].copy(), "short"), good[0]],
        "strings": [good[0], Branch(np.array(["1"] * mech.nq), "str")],
        "huge": [good[0], Branch(np.full(mech.nq, 1e7), "huge")],
        "miss before NaN": [Branch(far, "far"), Branch(np.full(mech.nq, np.nan), "nan")],
    }
    for label, branches in cases.items():
        expected = raised(lambda b=branches: check_branches_reference(mech, output, target, b))
        assert raised(lambda b=branches: check_branches(mech, output, target, b)) == expected, label
    assert check_branches(mech, output, target, []) == []


def test_the_limit_flag_is_the_per_coordinate_test():
    mech = rcm_pin.load("rcm_bevel")
    q = mech.home.copy()
    target = mech.output.value(_frame(mech, q))
    inside = check_branches(mech, mech.output, target, [Branch(q, "b")])[0]
    assert inside.within_limits
    q_out = q.copy()
    q_out[0] += 2 * np.pi  # the same pose, outside [lower, upper] of q1
    assert q_out[0] > mech.upper[0] + 1e-12
    outside = check_branches(mech, mech.output, target, [Branch(q_out, "b")])[0]
    assert not outside.within_limits
