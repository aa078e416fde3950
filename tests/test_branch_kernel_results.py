"""The results of ``rcm_pin.inverse``'s kernel route (solutions built without the frozen
dataclasses' ``__init__``, the target read by one fancy index, the limit flags from a
table) behave as the numpy route's: they pickle, copy, compare, print and ``replace``
alike, and own their arrays (a later call does not overwrite an earlier result)."""

from __future__ import annotations

import copy
import dataclasses
import pickle

import numpy as np
import pytest
from test_branch_kernel import _routes

import rcm_pin
from rcm_pin.analysis.pose_target import plain_pose
from rcm_pin.analysis.results import PositionResult, PositionSolution
from rcm_pin.model import serial_branches


def _fields(obj):
    return [(f.name, getattr(obj, f.name)) for f in dataclasses.fields(obj)]


def _same(a, b):
    for (na, va), (nb, vb) in zip(_fields(a), _fields(b), strict=True):
        assert na == nb
        if isinstance(va, np.ndarray):
            np.testing.assert_array_equal(va, vb)
        else:
            assert type(va) is type(vb) and va == vb


@pytest.mark.parametrize("name", ["rcm_bevel", "rcm_bevel_4dof"])
def test_kernel_results_pickle_copy_and_replace_as_the_constructors(name):
    mech = rcm_pin.load(name)
    T = rcm_pin.tool_pose(mech, mech.configurations["mid"])
    assert serial_branches.warm(mech)(plain_pose(mech.output, T)) is not None
    fast, slow = _routes(mech, T)
    assert type(fast) is PositionResult and type(slow) is PositionResult
    assert [f.name for f in dataclasses.fields(fast)] == [f.name for f in dataclasses.fields(slow)]
    assert fast.given.flags.owndata and fast.given.dtype == np.float64
    for a, b in zip(fast.solutions, slow.solutions, strict=True):
        assert type(a) is PositionSolution and list(vars(a)) == list(vars(b))
        for made in (pickle.loads(pickle.dumps(a)), copy.deepcopy(a), copy.copy(a)):
            _same(made, a)
        moved = dataclasses.replace(a, mode="other")
        assert type(moved) is PositionSolution and moved.mode == "other" and moved.q is a.q
        assert repr(a).startswith("PositionSolution(q=array(") and a.mode in repr(a)
        with pytest.raises(dataclasses.FrozenInstanceError):
            a.residual = 0.0  # type: ignore[misc]
    again = pickle.loads(pickle.dumps(fast.solutions))
    for a, b in zip(again, fast.solutions, strict=True):
        _same(a, b)


def test_a_later_call_does_not_change_an_earlier_result():
    """The kernel's buffers are reused; its results are copies."""
    mech = rcm_pin.load("rcm_bevel")
    serial_branches.warm(mech)
    first_pose = rcm_pin.tool_pose(mech, mech.configurations["mid"])
    first = rcm_pin.inverse(mech, first_pose)
    kept = [(s.q.copy(), s.output.copy(), s.residual, s.within_limits) for s in first.solutions]
    given = first.given.copy()
    rcm_pin.inverse(mech, rcm_pin.tool_pose(mech, mech.configurations["regular"]))
    np.testing.assert_array_equal(first.given, given)
    for s, (q, out, res, inside) in zip(first.solutions, kept, strict=True):
        np.testing.assert_array_equal(s.q, q)
        np.testing.assert_array_equal(s.output, out)
        assert s.residual == res and s.within_limits is inside
