"""The hot path of rcm_pin.forward (rcm_pin.analysis.forward_route) gives what the general
route (forward_reference, the code it replaced) gives: every array bit for bit, the same
labels, residuals, iteration counts, limit flags and methods, and the same typed errors
with the same messages; the output values of Output.value bit for bit the former loop's.
One exception: where the closure kernel solves ``forward(q_guess=)``, the output value is
the kernel's (its symbolic forward kinematics), Pinocchio's to rounding (:data:`KERNEL_OUTPUT`)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from conftest import random_q

import rcm_pin
from rcm_pin.analysis.branch_check import LIMIT_TOL, within_limits
from rcm_pin.analysis.forward_route import forward_reference, plan
from rcm_pin.analysis.results import PositionResult, PositionSolution, one_solution
from rcm_pin.errors import RcmPinError
from rcm_pin.model import kernels
from rcm_pin.model.output import _ANGLE, _FLAT, Output

#: The kernel's output value against Pinocchio's forward kinematics at the same q: the same
#: operations in another order (seen: 1.4e-17 on spherical_3rrr, bit for bit elsewhere)
#: [m, rad].
KERNEL_OUTPUT = 1e-15
#: Every closed catalogue mechanism.
CLOSED = ("five_bar", "four_bar", "planar_3rrr", "spherical_3rrr", "translational_3ppapa",
          "eye_4dof")  # fmt: skip


def _result(call):
    try:
        return call()
    except RcmPinError as exc:
        return exc


def assert_same(new, ref, output_tol=0.0):
    """Two results (or two typed errors) alike: arrays bit for bit (the output values
    within ``output_tol`` where it is not 0), the rest equal."""
    if isinstance(ref, Exception):
        assert type(new) is type(ref) and str(new) == str(ref)
        return
    assert type(new) is PositionResult and list(vars(new)) == list(vars(ref))
    assert new.mechanism is ref.mechanism and new.output == ref.output
    assert (new.kind, new.method, new.count) == (ref.kind, ref.method, ref.count)
    assert new.given.dtype == ref.given.dtype and np.array_equal(new.given, ref.given)
    for a, b in zip(new.solutions, ref.solutions, strict=True):
        assert type(a) is PositionSolution and list(vars(a)) == list(vars(b))
        assert a.q.tobytes() == b.q.tobytes()
        assert a.output.dtype == b.output.dtype and a.output.shape == b.output.shape
        if output_tol:
            np.testing.assert_allclose(a.output, b.output, rtol=0, atol=output_tol)
        else:
            assert a.output.tobytes() == b.output.tobytes()
        assert (a.mode, a.residual, a.iterations) == (b.mode, b.residual, b.iterations)
        assert type(a.within_limits) is bool and a.within_limits == b.within_limits


@pytest.mark.parametrize("name", CLOSED)
@pytest.mark.parametrize("use_kernels", [True, False])
def test_the_guess_route_equals_the_general_one(name, use_kernels):
    """Seeded random drives near home, guesses near and far (the kernel declines some)."""
    mech = rcm_pin.load(name)
    kernels.warm(mech)
    loops, home = mech.loops, mech.home
    rng = np.random.default_rng(20261202)
    previous = kernels.set_enabled(use_kernels)
    try:
        for spread in (0.02, 0.3, 1.5):
            for _ in range(12):
                drives = home[loops.drive_q] + rng.uniform(-0.1, 0.1, loops.dof)
                q0 = home + rng.normal(0.0, spread, mech.nq)
                new = _result(lambda: rcm_pin.forward(mech, drives, q_guess=q0))  # noqa: B023
                ref = _result(lambda: forward_reference(mech, drives, q0))  # noqa: B023
                assert_same(new, ref, KERNEL_OUTPUT if use_kernels else 0.0)
    finally:
        kernels.set_enabled(previous)


def test_inputs_are_copied_or_only_read(m3):
    home = m3.home
    drives, q0 = home[m3.loops.drive_q], home.copy()
    res = rcm_pin.forward(m3, drives, q_guess=q0)
    drives[:] = 7.0
    assert np.array_equal(q0, home) and np.array_equal(res.given, home[m3.loops.drive_q])


#: Inputs that leave the hot path: other types, dtypes, shapes, NaN, inf, large entries.
BAD = (
    "list", "int", "float32", "nan", "inf", "big", "hypot", "short", "2d", "string", "none",
)  # fmt: skip


def _variant(x, kind):
    return {
        "list": lambda: x.tolist(),
        "int": lambda: np.round(x).astype(int),
        "float32": lambda: x.astype(np.float32),
        "nan": lambda: np.where(np.arange(x.size) == 1, np.nan, x),
        "inf": lambda: np.where(np.arange(x.size) == 0, -np.inf, x),
        "big": lambda: np.where(np.arange(x.size) == 0, 2e6, x),
        "hypot": lambda: np.full(x.size, 9e5),  # each entry within MAX_ABS, the hypot not
        "short": lambda: x[:-1],
        "2d": lambda: x[None, :],
        "string": lambda: ["a"] * x.size,
        "none": lambda: None,
    }[kind]()


@pytest.mark.parametrize("kind", BAD)
@pytest.mark.parametrize("which", ["drives", "q_guess"])
def test_other_inputs_take_the_general_route(m3, kind, which):
    """The same results or the same typed errors and messages as the general route."""
    home = m3.home
    drives, q0 = home[m3.loops.drive_q], home.copy()
    if which == "drives":
        drives = _variant(drives, kind)
    else:
        q0 = _variant(q0, kind)
    if which == "q_guess" and kind == "none":
        return  # q_guess=None is the all-modes route
    new = _result(lambda: rcm_pin.forward(m3, drives, q_guess=q0))
    assert_same(new, _result(lambda: forward_reference(m3, drives, q0)), KERNEL_OUTPUT)


@pytest.mark.parametrize("name", ["rcm_bevel", "rcm_belt", "rcm_bevel_4dof"])
def test_the_serial_route_equals_the_general_one(name):
    """Inside and outside the limits, and the inputs that leave the hot path."""
    mech = rcm_pin.load(name)
    rng = np.random.default_rng(7)
    wide = random_q(mech, 20, rng, margin=-0.05)  # some beyond the limits
    assert not all(within_limits(mech, q) for q in wide)
    for q in [*wide, *(_variant(wide[0], k) for k in BAD)]:
        new = _result(lambda: rcm_pin.forward(mech, q))  # noqa: B023
        assert_same(new, _result(lambda: forward_reference(mech, q)))  # noqa: B023
        if isinstance(q, np.ndarray) and not isinstance(new, Exception):
            assert new.given is not q  # a copy


def test_the_serial_route_with_continuous_joints():
    """A Pinocchio q other than the coordinates (cos θ, sin θ: the to_pin step)."""
    path = Path(__file__).parent / "data" / "continuous_joints.urdf"
    mech = rcm_pin.load(str(path), tool_frame="tool_link")
    assert not mech.identity_order
    rng = np.random.default_rng(3)
    for q in rng.uniform(-3.0, 3.0, (10, mech.nq)):
        assert_same(rcm_pin.forward(mech, q), forward_reference(mech, q))


def test_limit_bounds_are_within_limits_floats(m3):
    """The plan's bounds are within_limits' floats; at a bound, one ulp either side, the
    flag is within_limits' flag (serial route; the closed one reads the same bounds)."""
    p = plan(m3)
    assert p.lo == [lo - LIMIT_TOL for lo in m3.lower.tolist()]
    assert p.hi == [hi + LIMIT_TOL for hi in m3.upper.tolist()]
    mech = rcm_pin.load("rcm_bevel")
    p, home, flags = plan(mech), mech.home, set()
    for i in range(mech.nq):
        for edge, out in ((p.lo[i], -math.inf), (p.hi[i], math.inf)):
            for v in (edge, math.nextafter(edge, out), math.nextafter(edge, -out)):
                q = home.copy()
                q[i] = v
                flag = rcm_pin.forward(mech, q).solutions[0].within_limits
                assert flag == within_limits(mech, q)
                flags.add(flag)
    assert flags == {True, False}


def _value_reference(output: Output, oMf: pin.SE3) -> np.ndarray:
    """Output.value as it was: a loop over the tokens."""
    out: list[float] = []
    h = oMf.homogeneous.ravel().tolist()
    for c in output.coords:
        if c == "rotation":
            out += h[0:3] + h[4:7] + h[8:11]
        elif c in _FLAT:
            out.append(h[_FLAT[c]])
        else:
            i, j = _ANGLE[c]
            out.append(math.atan2(h[i], h[j]))
    return np.array(out)


@pytest.mark.parametrize(
    "coords",
    [("x", "y", "z", "rotation"), ("rotation",), ("x", "y", "rz"), ("rz",), ("x", "y"),
     ("z", "x"), ("rx", "ry", "rz", "y"), ("ry",), ("rotation", "z")],
)  # fmt: skip
def test_output_values_equal_the_token_loop(coords):
    output = Output("tool", coords, 1)
    rng = np.random.default_rng(11)
    for _ in range(50):
        M = pin.SE3.Random()
        M.translation = rng.normal(0.0, 2.0, 3)
        new, ref = output.value(M), _value_reference(output, M)
        assert new.dtype == ref.dtype and new.tobytes() == ref.tobytes()
    assert Output("", ()).value(pin.SE3.Identity()).shape == (0,)


def test_one_solution_equals_the_constructors():
    q, v = np.arange(4.0), np.arange(1.0)
    mech = rcm_pin.load("four_bar")
    made = one_solution(mech, "forward", q[:1], "Newton", (q, v, "guess", 1e-16, 3, False))
    sol = PositionSolution(q, v, "guess", 1e-16, 3, False)
    built = PositionResult(mech, "forward", q[:1], mech.output, (sol,), "Newton")
    assert type(made) is PositionResult and list(vars(made)) == list(vars(built))
    assert made == built
    (fast,) = made.solutions
    assert type(fast) is PositionSolution and list(vars(fast)) == list(vars(sol))
    assert fast == sol
    with pytest.raises(AttributeError):
        fast.mode = "other"  # type: ignore[misc]
    with pytest.raises(AttributeError):
        made.kind = "inverse"  # type: ignore[misc]
