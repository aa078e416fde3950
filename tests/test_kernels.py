"""Closure Newton kernels (rcm_pin.model.kernels, provider ocp.kernels): the kernel route
and the numpy route give the same solutions, iteration counts and typed errors."""

from __future__ import annotations

import subprocess
import sys
import warnings
from concurrent.futures import ThreadPoolExecutor

import casadi as ca
import numpy as np
import pytest
from conftest import closed_cases

import rcm_pin
from ocp import so_cache
from ocp.kernels import CHUNK, provider, same_residual, vm_function
from ocp.kernels.closure_kernel import MAX_ITER, ClosureNewtonKernel, SharedFunction
from ocp.kernels.newton_function import KAPPA_LIMIT, _newton_direction
from rcm_pin.analysis.closed_position import solve_drives
from rcm_pin.errors import SolverError
from rcm_pin.model import kernels
from rcm_pin.model.newton import RESIDUAL_TOL

#: Two routes of one Newton: the same iterates up to rounding (|Δq| seen: <= 2e-15 rad).
AGREE = 1e-12
#: Every closed catalogue mechanism (their closure Jacobians on the passive joints are
#: square, or tall: eye_4dof 9 x 8, translational_3ppapa_loops 30 x 18).
CLOSED = (
    "planar_3rrr",
    "five_bar",
    "four_bar",
    "spherical_3rrr",
    "translational_3ppapa",
    "eye_4dof",
    "translational_3ppapa_loops",
)


def _both(mech, drives, q0, **options):
    """(kernel route, numpy route) of solve_drives; a SolverError is returned, not raised."""
    out = []
    for use in (True, False):
        previous = kernels.set_enabled(use)
        try:
            out.append(solve_drives(mech, drives, q0, **options))
        except SolverError as exc:
            out.append(exc)
        finally:
            kernels.set_enabled(previous)
    return out


@pytest.mark.parametrize("name", CLOSED)
def test_kernel_and_numpy_routes_agree(name):
    """Seeded random drives and starts (near, and far enough that steps are clipped)."""
    mech = rcm_pin.load(name)
    kernel = kernels.warm(mech)
    assert isinstance(kernel, ClosureNewtonKernel)
    rng = np.random.default_rng(20261201)
    answered = []
    for spread in (0.05, 0.6):
        answered.append(0)
        for drives, q0 in closed_cases(mech, rng, 40, spread):
            fast, slow = _both(mech, drives, q0)
            if isinstance(slow, SolverError):
                assert type(fast) is SolverError and str(fast) == str(slow)
                continue
            np.testing.assert_allclose(fast[0], slow[0], rtol=0, atol=AGREE)
            assert fast[1] == slow[1]
            assert fast[2] < RESIDUAL_TOL and slow[2] < RESIDUAL_TOL
            answered[-1] += kernel(q0, drives, max_iter=60, max_step=0.5) is not None
    # the kernel itself answered nearly every near start (far ones may walk > MAX_ITER)
    assert answered[0] >= 38 and answered[1] >= 5, answered


def test_the_vm_route_agrees(m3):
    """The same function in CasADi's virtual machine (no C compiler)."""
    vm = ClosureNewtonKernel(SharedFunction(provider.newton_function(m3, vm=True), "", None), CHUNK)
    rng = np.random.default_rng(3)
    for drives, q0 in closed_cases(m3, rng, 20, 0.01, 0.05):
        out = vm(q0, drives, max_iter=60, max_step=0.5)
        with kernels.disabled():
            q, it, res = solve_drives(m3, drives, q0)
        assert out is not None and out.iterations == it
        np.testing.assert_allclose(out.q, q, rtol=0, atol=AGREE)
        assert out.residual < RESIDUAL_TOL


def test_disable_switch():
    mech = rcm_pin.load("four_bar")
    assert isinstance(kernels.closure_newton(mech), ClosureNewtonKernel)
    with kernels.disabled():
        assert not kernels.enabled()
        assert kernels.closure_newton(mech) is None
    assert kernels.enabled()


def test_vm_and_compiled_functions_give_the_same_bits(m3):
    """So a result does not depend on whether the structure was compiled before it."""
    rng = np.random.default_rng(17)
    vm = ClosureNewtonKernel(SharedFunction(provider.newton_function(m3, vm=True), "", None), 4)
    shared = kernels.warm(m3).shared
    shared.compile()
    assert shared.compiled and shared.function.name() == vm.shared.function.name()
    compiled = ClosureNewtonKernel(shared, CHUNK)
    for drives, q0 in closed_cases(m3, rng, 30, 0.3):
        a = vm(q0, drives, max_iter=60, max_step=0.5)
        b = compiled(q0, drives, max_iter=60, max_step=0.5)
        assert (a is None) == (b is None)
        if a is not None:
            np.testing.assert_array_equal(a.q, b.q)
            assert a[1:] == b[1:]


def test_a_structure_compiles_after_its_calls(m5):
    fresh = SharedFunction(provider.newton_function(m5, vm=True), kernels.warm(m5).shared.key, 3)
    kernel = ClosureNewtonKernel(fresh, CHUNK)
    home = m5.home
    for calls in range(1, 5):
        kernel(home, home[m5.loops.drive_q], max_iter=60, max_step=0.5)
        assert fresh.compiled == (calls >= 3)


def test_environment_variable_disables_kernels():
    code = "from rcm_pin.model import kernels; print(kernels.enabled())"
    env = {"RCM_PIN_NO_KERNELS": "1", "PATH": ""}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert out.stdout.strip() == "False", out.stderr


def test_no_convergence_gives_the_same_error(m5):
    """Drives that admit no assembly, and an iteration cap below what the start needs."""
    kernels.warm(m5)
    home = m5.home
    fast, slow = _both(m5, np.array([0.0, np.pi]), home)  # cranks apart: the loop cannot close
    assert type(fast) is type(slow) is SolverError and str(fast) == str(slow)
    assert "did not converge in 60 iterations" in str(slow)
    drives = home[m5.loops.drive_q] + 0.1
    fast, slow = _both(m5, drives, home, max_iter=1)
    assert type(fast) is type(slow) is SolverError and str(fast) == str(slow)
    # clipped steps: a step moves each passive joint by at most max_step, so the 0.11 rad
    # walk takes >= 6 iterations at 0.02 rad (the kernel answers) and >= 12 at 0.01 rad,
    # beyond the kernel's MAX_ITER = 12 there (it declines and numpy serves)
    kernel = kernels.warm(m5)
    counts = []
    for max_step in (0.5, 0.02, 0.01):
        fast, slow = _both(m5, drives, home, max_step=max_step)
        np.testing.assert_allclose(fast[0], slow[0], rtol=0, atol=AGREE)
        assert fast[1] == slow[1]
        walk = np.abs(np.angle(np.exp(1j * (slow[0] - home))))[m5.loops.passive_q].max()
        assert slow[1] >= np.ceil(walk / max_step)
        out = kernel(home, drives, max_iter=60, max_step=max_step)
        assert (out is None) == (slow[1] > MAX_ITER)
        counts.append(slow[1])
    assert counts[0] < counts[1] <= MAX_ITER < counts[2]  # both outcomes of the kernel met


def test_kernel_declines_where_numpy_leaves_its_plain_solve(m3):
    """A NaN (or >= 1e3) step makes numpy switch to least squares: the kernel returns None."""
    kernel = kernels.warm(m3)
    home = m3.home
    drives = home[m3.loops.drive_q]
    assert kernel(np.full(m3.nq, np.nan), drives, max_iter=60, max_step=0.5) is None
    out = kernel(home, drives, max_iter=60, max_step=0.5)
    assert out is not None and out.residual < RESIDUAL_TOL


class _Broken:
    def closure_newton(self, mech):
        raise RuntimeError("no kernel today")


class _Declines:
    def closure_newton(self, mech):
        return lambda q, d, *, max_iter, max_step: None


def test_a_failing_provider_warns_and_numpy_serves(monkeypatch):
    mech = rcm_pin.load("five_bar")
    monkeypatch.setattr(kernels, "_providers", (_Broken(), _Declines()))
    with pytest.warns(kernels.KernelWarning, match="no kernel today"):
        kernel = kernels.warm(mech)
    assert kernel is not None  # the second provider's (always declining) kernel
    home = mech.home
    drives = home[mech.loops.drive_q] + 0.05
    fast, slow = _both(mech, drives, home)
    np.testing.assert_array_equal(fast[0], slow[0])  # both from the numpy route
    assert fast[1:] == slow[1:]


def test_threads_give_the_same_results(m3):
    kernels.warm(m3)
    rng = np.random.default_rng(11)
    cases = closed_cases(m3, rng, 40, 0.01, 0.05)
    with kernels.disabled():
        expected = [solve_drives(m3, d, q0)[0] for d, q0 in cases]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with ThreadPoolExecutor(2) as pool:
            got = list(pool.map(lambda c: solve_drives(m3, c[0], c[1])[0], cases * 3))
    np.testing.assert_allclose(np.array(got), np.array(expected * 3), rtol=0, atol=AGREE)


def test_public_forward_is_unchanged(m3):
    kernels.warm(m3)
    rng = np.random.default_rng(5)
    for drives, q0 in closed_cases(m3, rng, 10, 0.01, 0.05):
        a = rcm_pin.forward(m3, drives, q_guess=q0).solutions[0]
        with kernels.disabled():
            b = rcm_pin.forward(m3, drives, q_guess=q0).solutions[0]
        np.testing.assert_allclose(a.q, b.q, rtol=0, atol=AGREE)
        np.testing.assert_allclose(a.output, b.output, rtol=0, atol=AGREE)
        assert a.iterations == b.iterations and a.within_limits == b.within_limits


def test_the_vm_function_is_cached_on_disk(m5, tmp_path, monkeypatch):
    monkeypatch.setenv("RCM_PIN_CACHE", str(tmp_path))
    key = kernels.warm(m5).shared.key
    built = vm_function(m5, key)
    (saved,) = tmp_path.glob("closure_newton_*.casadi")
    loaded = vm_function(m5, key)  # from the file
    home = m5.home
    args = [home + 0.01, home[m5.loops.drive_q], 0.5, kernels.warm(m5).bounds]
    for a, b in zip(built.call(args), loaded.call(args), strict=True):
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    saved.write_text("damaged")
    with pytest.warns(so_cache.CacheWarning, match="it has 7 bytes; its record says"):
        assert vm_function(m5, key).name() == built.name()  # rebuilt and saved again
    assert so_cache.verify(saved) is None


def test_a_geometry_gets_its_own_function(m5):
    """The structure key holds the geometry; a function of another geometry is refused."""
    other = rcm_pin.load("five_bar", distal_1=0.27)
    mine, theirs = kernels.warm(m5), kernels.warm(other)
    assert mine.shared is not theirs.shared and mine.shared.key != theirs.shared.key
    assert same_residual(other, theirs.shared.function)
    assert not same_residual(other, mine.shared.function)
    home = m5.home
    drives = home[m5.loops.drive_q] + 0.02
    fast, slow = _both(other, drives, home)
    np.testing.assert_allclose(fast[0], slow[0], rtol=0, atol=AGREE)
    assert np.linalg.norm(other.closure_residual(fast[0])) < RESIDUAL_TOL


def test_tall_step_is_numpys_least_squares_and_its_guard():
    """Tall J_p: the QR step equals lstsq's; κ = ‖R‖_F ‖R⁻¹‖_F flags a (near) rank loss,
    where lstsq would drop a singular value (numpy's route then serves)."""
    jp, e = ca.SX.sym("J", 9, 8), ca.SX.sym("e", 9)
    step, kappa = _newton_direction(jp, e)
    fun = ca.Function("direction", [jp, e], [step, kappa])
    rng = np.random.default_rng(2)
    jac, res = rng.normal(size=(9, 8)), rng.normal(size=9)
    s, k = (np.asarray(v).ravel() for v in fun(jac, res))
    np.testing.assert_allclose(s, -np.linalg.lstsq(jac, res, rcond=1e-10)[0], rtol=0, atol=1e-13)
    assert k[0] >= np.linalg.cond(jac) and k[0] < 1e3
    jac[:, 7] = jac[:, 6] * (1.0 + 1e-12)  # numerically rank 7
    k = float(fun(jac, res)[1])
    assert not k < KAPPA_LIMIT  # NaN or huge: flagged


def test_a_failed_compilation_keeps_the_vm(m5, monkeypatch):
    import ocp.compiled

    def fail(*args, **kwargs):
        raise RuntimeError("cannot load the library")

    monkeypatch.setattr(ocp.compiled, "compile_lazy", fail)
    fresh = SharedFunction(provider.newton_function(m5, vm=True), "k", 1)
    vm = fresh.function
    kernel = ClosureNewtonKernel(fresh, CHUNK)
    home = m5.home
    with pytest.warns(kernels.KernelWarning, match="cannot load the library"):
        out = kernel(home, home[m5.loops.drive_q], max_iter=60, max_step=0.5)
    assert out is not None and fresh.function is vm and not fresh.compiled
    assert fresh.compile_after is None  # no second attempt
