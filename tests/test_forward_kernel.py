"""The closure kernel's ``forward`` call (rcm_pin.model.newton_kernel, provider
ocp.kernels): the solve of its ``__call__`` bit for bit, the output value of Pinocchio's
forward kinematics at that q to rounding, and the limit flag of ``within_limits``'s very
comparisons (at the bounds too); the VM and the compiled function give the same bits."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import closed_cases
from hypothesis import given, settings
from hypothesis import strategies as st

import rcm_pin
from ocp.kernels import CHUNK, provider
from ocp.kernels.closure_kernel import ClosureNewtonKernel, SharedFunction
from rcm_pin.analysis.branch_check import LIMIT_TOL, within_limits
from rcm_pin.catalog import mechanisms
from rcm_pin.model import kernels

#: The kernel's output value against Pinocchio's at the same q: the same operations in
#: another order (seen: 1.4e-17 on spherical_3rrr, bit for bit elsewhere) [m, rad].
OUTPUT_AGREE = 1e-15
LAAS = Path(__file__).parent / "data" / "laas"
#: Every closed catalogue mechanism, and LAAS fixtures without an output frame.
MECHANISMS = (
    *(e.name for e in mechanisms() if e.kind == "closed"),
    str(LAAS / "five_bar.urdf"),
    str(LAAS / "delta.urdf"),
)


@pytest.mark.parametrize("name", MECHANISMS)
def test_forward_is_the_solve_with_its_output_and_limit_flag(name):
    mech = rcm_pin.load(name)
    kernel = kernels.warm(mech)
    assert isinstance(kernel, ClosureNewtonKernel)
    rng = np.random.default_rng(20261202)
    answered = 0
    for drives, q0 in closed_cases(mech, rng, 24, 0.05, 0.1) + closed_cases(mech, rng, 8, 1.0, 0.1):
        out = kernel.forward(q0, drives, 60, 0.5)
        solve = kernel(q0, drives, max_iter=60, max_step=0.5)
        assert (out is None) == (solve is None)
        if out is None:
            continue
        answered += 1
        assert out.q.tobytes() == solve.q.tobytes()
        assert (out.iterations, out.residual) == (solve.iterations, solve.residual)
        assert out.output.shape == (mech.output.size,) and out.output.dtype == np.float64
        np.testing.assert_allclose(out.output, mech.output_value(out.q), rtol=0, atol=OUTPUT_AGREE)
        assert type(out.within_limits) is bool
        assert out.within_limits == within_limits(mech, out.q)
    assert answered >= 24  # every near start at least


def _flag(lo, q, hi):
    """within_limits' comparisons on bounds already widened."""
    return all(a <= x <= b for a, x, b in zip(lo.tolist(), q.tolist(), hi.tolist(), strict=True))


@settings(max_examples=60, deadline=None)
@given(
    shifts=st.lists(st.integers(-2, 2), min_size=2, max_size=2),
    which=st.integers(0, 7),
    infinite=st.booleans(),
)
def test_the_limit_flag_is_within_limits_at_the_bounds(m3, shifts, which, infinite):
    """Bounds a few ulps either side of one coordinate of a solution (others loose or
    infinite): the kernel's flag is the comparison chain's, ulp for ulp."""
    base = kernels.warm(m3)
    drives, home = m3.home[m3.loops.drive_q] + 0.02, m3.home
    q = base(home, drives, max_iter=60, max_step=0.5).q
    loose = np.inf if infinite else 10.0
    lo, hi = q - loose, q + loose
    i = which % m3.nq
    ulp = abs(np.spacing(q[i]))  # (np.spacing is negative below 0)
    lo[i], hi[i] = q[i] + shifts[0] * ulp, q[i] + shifts[1] * ulp
    kernel = ClosureNewtonKernel(base.shared, CHUNK, np.concatenate([lo, hi]))
    out = kernel.forward(home, drives, 60, 0.5)
    assert out is not None and out.q.tobytes() == q.tobytes()
    assert out.within_limits == _flag(lo, q, hi) == (shifts[0] <= 0 <= shifts[1])


def test_the_kernels_bounds_are_the_widened_limits(m3):
    kernel = kernels.warm(m3)
    widened = [*(m3.lower - LIMIT_TOL).tolist(), *(m3.upper + LIMIT_TOL).tolist()]
    assert kernel.bounds.tolist() == [*(lo - LIMIT_TOL for lo in m3.lower.tolist()),
                                      *(hi + LIMIT_TOL for hi in m3.upper.tolist())]  # fmt: skip
    assert kernel.bounds.tolist() == widened


def test_vm_and_compiled_forward_give_the_same_bits(m3):
    rng = np.random.default_rng(5)
    shared = kernels.warm(m3).shared
    shared.compile()
    bounds = kernels.warm(m3).bounds
    vm_fun = SharedFunction(provider.newton_function(m3, vm=True), "", None)
    vm = ClosureNewtonKernel(vm_fun, CHUNK, bounds)
    compiled = ClosureNewtonKernel(shared, CHUNK, bounds)
    for drives, q0 in closed_cases(m3, rng, 20, 0.3, 0.1):
        a, b = vm.forward(q0, drives, 60, 0.5), compiled.forward(q0, drives, 60, 0.5)
        assert (a is None) == (b is None)
        if a is not None:
            assert a.q.tobytes() == b.q.tobytes() and a.output.tobytes() == b.output.tobytes()
            assert a[1:3] == b[1:3] and a.within_limits == b.within_limits


def test_another_output_gets_its_own_function(m3):
    """The output (frame and coordinates) is part of the structure key."""
    xy = rcm_pin.load("planar_3rrr", output_coords=("x", "y"))
    mine, theirs = kernels.warm(m3), kernels.warm(xy)
    assert mine.shared.key != theirs.shared.key
    drives, home = m3.home[m3.loops.drive_q] + 0.02, m3.home
    a, b = mine.forward(home, drives, 60, 0.5), theirs.forward(home, drives, 60, 0.5)
    assert a.q.tobytes() == b.q.tobytes()
    assert b.output.tolist() == a.output[:2].tolist()
