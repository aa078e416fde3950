"""The serial branch kernel (rcm_pin.model.serial_branches, provider ocp.kernels) gives
``rcm_pin.inverse`` of a six-DOF RCM pose exactly what the numpy route gives: the same
branches in the same order (q bit for bit: the kernel repeats the scalar IK's and
fit_limits' operations, compiled without fused multiply-adds; to 1e-12 in the
near-aligned wrist band, tests/test_branch_kernel_near.py), the same limit flags, the
output values and residuals to 1e-12 (CasADi's forward kinematics rounds differently
from Pinocchio's), and the same typed errors (the kernel declines, numpy raises)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from conftest import random_q
from hypothesis import given, settings
from hypothesis import strategies as st

import rcm_pin
from ocp.kernels import branches_function, provider
from ocp.kernels.branches_kernel import SerialBranchesKernel
from ocp.kernels.closure_kernel import SharedFunction
from rcm_pin.analysis.pose_target import plain_pose
from rcm_pin.analysis.results import (
    PositionResult,
    PositionSolution,
    closed_form_solutions,
    inverse_result,
)
from rcm_pin.errors import (
    InvalidInputError,
    RcmPinError,
    SingularConfigurationError,
    UnreachablePoseError,
)
from rcm_pin.mechanisms.rcm.ik_scalar import ik_pose_one
from rcm_pin.model import kernels, serial_branches

#: Forward kinematics by CasADi vs Pinocchio: the same numbers to rounding (seen: 5e-15).
AGREE = 1e-12


@pytest.fixture(scope="module", params=["rcm_bevel", "rcm_belt", "rcm_bevel_rpy"])
def mech(request):
    if request.param == "rcm_bevel_rpy":
        return rcm_pin.load("rcm_bevel", wrist_type="rpy")
    return rcm_pin.load(request.param)


def _routes(mech, target, **options):
    """(kernel route, numpy route) of rcm_pin.inverse; a typed error is returned. The
    kernel is built first (else the first WARM_CALLS requests take the numpy route)."""
    serial_branches.warm(mech)
    out = []
    for use in (True, False):
        previous = kernels.set_enabled(use)
        try:
            out.append(rcm_pin.inverse(mech, target, **options))
        except RcmPinError as exc:
            out.append(exc)
        finally:
            kernels.set_enabled(previous)
    return out


def assert_same(fast, slow, q_tol=0.0):
    """The routes agree: q bit for bit (``q_tol`` = 0), or to ``q_tol``."""
    if isinstance(slow, Exception):
        assert type(fast) is type(slow) and str(fast) == str(slow)
        return
    assert fast.method == slow.method and fast.kind == slow.kind
    np.testing.assert_array_equal(fast.given, slow.given)
    assert [s.mode for s in fast.solutions] == [s.mode for s in slow.solutions]
    for a, b in zip(fast.solutions, slow.solutions, strict=True):
        assert type(a) is PositionSolution
        np.testing.assert_allclose(a.q, b.q, rtol=0, atol=q_tol)
        np.testing.assert_allclose(a.output, b.output, rtol=0, atol=AGREE)
        assert abs(a.residual - b.residual) <= AGREE and a.iterations == b.iterations == 0
        assert a.within_limits is b.within_limits


def _q_tol(mech, T):
    """0 (bit for bit) where the numpy route is the scalar IK; 1e-12 where it hands the
    pose to the vectorised code (the near-aligned wrist band, numpy's ufuncs)."""
    return 0.0 if ik_pose_one(T, mech.args.get("wrist_type", "zyz")) is not None else AGREE


def test_kernel_route_equals_numpy_route_on_seeded_poses(mech):
    kernel = serial_branches.warm(mech)
    assert isinstance(kernel, SerialBranchesKernel)
    rng = np.random.default_rng(7)
    answered = 0
    for q in random_q(mech, 60, rng):
        T = rcm_pin.tool_pose(mech, q)
        answered += kernel(plain_pose(mech.output, T)) is not None
        tol = _q_tol(mech, T)
        assert_same(*_routes(mech, T), q_tol=tol)
        assert_same(*_routes(mech, T, limits=True), q_tol=tol)
    assert answered == 60  # no seeded pose is degenerate


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(-1.0, 1.0), min_size=6, max_size=6), st.sampled_from([-1, 1]))
def test_kernel_route_equals_numpy_route_for_any_pose(unit, sign):
    """Any pose of the tool, inside or outside the joint limits (angles over a turn)."""
    mech = rcm_pin.load("rcm_bevel")
    q = np.array(unit) * np.pi
    q[2] = sign * (0.05 + 0.05 * (unit[2] + 1.0))  # [m]
    T = rcm_pin.tool_pose(mech, q)
    assert_same(*_routes(mech, T), q_tol=_q_tol(mech, T))


def test_four_dof_kernel_route_equals_numpy_route():
    """The four-DOF IK is numpy's vectorised code, whose ``arctan2`` ufunc may round
    differently from the C library's by an ulp (seen: 4.4e-16 in q1, q2, q4): q to 1e-12;
    the limit flags and every decision the same."""
    mech = rcm_pin.load("rcm_bevel_4dof")
    kernel = serial_branches.warm(mech)
    assert isinstance(kernel, SerialBranchesKernel)
    for q in random_q(mech, 60, np.random.default_rng(11)):
        T = rcm_pin.tool_pose(mech, q)
        fast = kernel(plain_pose(mech.output, T))
        assert fast is not None and fast.labels == ("branch_0", "branch_1")
        assert_same(*_routes(mech, T), q_tol=AGREE)
        assert_same(*_routes(mech, T, limits=True), q_tol=AGREE)


def test_four_dof_kernel_declines_where_numpy_raises():
    mech = rcm_pin.load("rcm_bevel_4dof")
    kernel = serial_branches.warm(mech)
    q = np.array([0.3, 0.2, 0.08, 0.1])
    T = rcm_pin.tool_pose(mech, q)
    T[:3, 3] += 1e-6 * T[:3, 0]  # the tool centre off the tool z axis: unreachable
    q[1] = np.pi / 2  # the output axis along the base axis: singular
    for target in (T, rcm_pin.tool_pose(mech, q)):
        assert kernel(plain_pose(mech.output, target)) is None
        fast, slow = _routes(mech, target)
        assert isinstance(slow, RcmPinError)
        assert_same(fast, slow)


@pytest.mark.parametrize("name", ["rcm_bevel", "rcm_bevel_4dof"])
def test_compiled_and_vm_functions_give_the_same_bits(name):
    """So a result does not depend on whether the structure was compiled before it."""
    mech = rcm_pin.load(name)
    shared = serial_branches.warm(mech).shared
    shared.compile()
    assert shared.compiled
    fun = branches_function.build(mech, shared.function.name())  # CasADi's VM
    vm = SerialBranchesKernel(SharedFunction(fun, shared.key, None), mech.lower, mech.upper)
    compiled = SerialBranchesKernel(shared, mech.lower, mech.upper)
    rng = np.random.default_rng(3)
    for q in random_q(mech, 20, rng):
        value = plain_pose(mech.output, rcm_pin.tool_pose(mech, q))
        a, b = vm(value), compiled(value)
        assert (a is None) == (b is None)
        if a is not None:
            for x, y in zip(a, b, strict=True):
                np.testing.assert_array_equal(x, y)


def test_the_kernel_declines_degenerate_poses(mech):
    """The aligned wrist and the output axis along the base axis: numpy raises. (The
    near-aligned band is answered: tests/test_branch_kernel_near.py.)"""
    kernel = serial_branches.warm(mech)
    q = 0.5 * (mech.lower + mech.upper)
    q[2] = 0.08
    wrist = mech.args.get("wrist_type", "zyz")
    q[4] = 0.0 if wrist == "zyz" else np.pi / 2  # sin q5 = 0 / cos q5 = 0
    T = rcm_pin.tool_pose(mech, q)
    assert kernel(plain_pose(mech.output, T)) is None
    fast, slow = _routes(mech, T)
    assert isinstance(slow, SingularConfigurationError)
    assert_same(fast, slow)
    q[1] = np.pi / 2  # the output axis along the base axis
    T = rcm_pin.tool_pose(mech, q)
    assert kernel(plain_pose(mech.output, T)) is None
    fast, slow = _routes(mech, T)
    assert isinstance(slow, SingularConfigurationError)
    assert_same(fast, slow)


@pytest.mark.parametrize("delta", [1e-13, 1e-11])
def test_a_rotation_off_the_keep_screen_declines(mech, delta):
    """R off SO(3) by more than plain_pose's KEEP_TOL (1e-14; the scalar IK's screen,
    1e-12, is wider): the kernel declines (inverse leaves that test to it), and a matrix
    target then takes the projected value as without a kernel."""
    kernel = serial_branches.warm(mech)
    T = rcm_pin.tool_pose(mech, mech.configurations["mid"])
    value = plain_pose(mech.output, T)
    assert kernel(value) is not None
    off = value.copy()
    off[3] += delta
    assert kernel(off) is None
    T[0, 0] += delta
    assert plain_pose(mech.output, T) is None
    assert kernel(plain_pose(mech.output, T, screen=False)) is None
    assert_same(*_routes(mech, T))


@pytest.mark.parametrize("name", ["rcm_two_mass", "panda", "five_bar"])
def test_mechanisms_it_does_not_mirror_get_no_kernel(name):
    mech = rcm_pin.load(name)
    assert not branches_function.supported(mech)
    assert provider.serial_branches(mech) is None
    assert serial_branches.serial_branches(mech) is None


def test_position_only_and_other_options_take_the_numpy_route(monkeypatch):
    mech = rcm_pin.load("rcm_bevel")
    T = rcm_pin.tool_pose(mech, mech.configurations["regular"])

    def refuse(value):
        raise AssertionError("the kernel was asked")

    monkeypatch.setitem(serial_branches._cache, mech, refuse)
    rcm_pin.inverse(mech, T[:3, 3], ("x", "y", "z"))
    rcm_pin.inverse(mech, T, starts=4)
    with pytest.raises(InvalidInputError, match="starts 0"):
        rcm_pin.inverse(mech, T, starts=0)


def test_a_value_target_takes_the_kernel_route_too():
    """A target given as the value vector (x, y, z, R), read by ``Output.coerce``."""
    mech = rcm_pin.load("rcm_belt")
    T = rcm_pin.tool_pose(mech, mech.configurations["regular"])
    value = np.concatenate([T[:3, 3], T[:3, :3].ravel()]).tolist()
    assert serial_branches.warm(mech)(np.asarray(value)) is not None
    assert_same(*_routes(mech, value))


def test_the_kernel_is_looked_up_after_warm_calls_requests():
    """A one-shot inverse never imports the kernel's provider; a loop gets it."""
    mech = rcm_pin.load("rcm_bevel")
    assert [serial_branches.serial_branches(mech) for _ in range(serial_branches.WARM_CALLS)] == [
        None
    ] * serial_branches.WARM_CALLS
    assert serial_branches.serial_branches(mech) is not None
    code = (
        "import sys, rcm_pin; m = rcm_pin.load('rcm_bevel'); "
        "rcm_pin.inverse(m, rcm_pin.tool_pose(m, m.configurations['mid'])); "
        "print('ocp.kernels' in sys.modules, 'casadi' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "False"]


def test_disable_switch_and_environment_variable():
    mech = rcm_pin.load("rcm_bevel")
    assert serial_branches.warm(mech) is not None
    with kernels.disabled():
        assert serial_branches.serial_branches(mech) is None
    code = (
        "import rcm_pin; from rcm_pin.model import serial_branches as s; "
        "m = rcm_pin.load('rcm_bevel'); print(s.serial_branches(m)); "
        "print(rcm_pin.inverse(m, rcm_pin.tool_pose(m, m.configurations['mid'])).count)"
    )
    env = {"RCM_PIN_NO_KERNELS": "1", "PATH": ""}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert out.stdout.split() == ["None", "8"], out.stderr


class _Broken:
    def serial_branches(self, mech):
        raise RuntimeError("no kernel today")


def test_a_failing_provider_warns_and_numpy_serves(monkeypatch):
    mech = rcm_pin.load("rcm_bevel", l9=0.2)  # a Mechanism the cache has not seen
    monkeypatch.setattr(kernels, "_providers", (_Broken(),))
    with pytest.warns(kernels.KernelWarning, match="no kernel today"):
        assert serial_branches.warm(mech) is None
    T = rcm_pin.tool_pose(mech, mech.configurations["regular"])
    assert_same(*_routes(mech, T))


def test_closed_form_solutions_equal_the_constructors():
    q, v = np.arange(6.0), np.arange(12.0)
    (fast,) = closed_form_solutions([q], [v], ["branch_0"], [1e-16], [True])
    slow = PositionSolution(q, v, "branch_0", 1e-16, 0, True)
    assert type(fast) is PositionSolution and list(vars(fast)) == list(vars(slow))
    assert fast == slow and hash(fast.mode) == hash(slow.mode)
    with pytest.raises(AttributeError):
        fast.mode = "other"  # type: ignore[misc]
    mech = rcm_pin.load("rcm_bevel")
    args = (v, mech.output, (fast,), "closed form")
    made, built = inverse_result(mech, *args), PositionResult(mech, "inverse", *args)
    assert type(made) is PositionResult and list(vars(made)) == list(vars(built))
    assert made == built and made.count == 1


@pytest.mark.parametrize("q1", [0.0, -0.0, np.pi])
def test_signed_zeros_take_the_scalar_routes_branch(q1):
    """y = ±0 with z < 0: q1 = atan2(0.0 − y, z) = +π on both routes (not −π)."""
    mech = rcm_pin.load("rcm_bevel")
    q = np.array([q1, 0.0, -0.1, 0.0, 0.5 * np.pi, 0.0])
    T = rcm_pin.tool_pose(mech, q)
    assert serial_branches.warm(mech)(plain_pose(mech.output, T)) is not None
    assert_same(*_routes(mech, T))


def test_threads_give_the_same_results():
    """Per-thread buffers: concurrent calls do not overwrite each other's results."""
    from concurrent.futures import ThreadPoolExecutor

    mech = rcm_pin.load("rcm_bevel")
    poses = [rcm_pin.tool_pose(mech, q) for q in random_q(mech, 40, np.random.default_rng(5))]
    alone = [rcm_pin.inverse(mech, T) for T in poses]
    with ThreadPoolExecutor(4) as pool:
        together = list(pool.map(lambda T: rcm_pin.inverse(mech, T), poses * 3))
    for a, b in zip(alone * 3, together, strict=True):
        assert_same(b, a)


def test_the_function_compiles_after_its_calls():
    mech = rcm_pin.load("rcm_belt")
    key = serial_branches.warm(mech).shared.key
    fresh = SharedFunction(branches_function.build(mech, f"rcm_branches_{key[-12:]}"), key, 3)
    kernel = SerialBranchesKernel(fresh, mech.lower, mech.upper)
    value = plain_pose(mech.output, rcm_pin.tool_pose(mech, mech.configurations["regular"]))
    first = kernel(value)
    for calls in range(2, 5):
        again = kernel(value)
        assert fresh.compiled == (calls >= 3)
        for x, y in zip(first, again, strict=True):
            np.testing.assert_array_equal(x, y)


def test_no_branch_inside_the_limits_gives_the_same_error():
    mech = rcm_pin.load("rcm_bevel")
    T = rcm_pin.tool_pose(mech, np.array([0.1, 0.2, 0.2, 0.3, 0.4, 0.5]))  # q3 > 0.12 m
    assert serial_branches.warm(mech)(plain_pose(mech.output, T)) is not None
    fast, slow = _routes(mech, T, limits=True)
    assert isinstance(slow, UnreachablePoseError) and "within the joint limits" in str(slow)
    assert_same(fast, slow)
    assert_same(*_routes(mech, T))  # without ``limits``: every branch, flagged
