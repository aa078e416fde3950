"""The tracking OCP with compiled, disk-cached stage functions and the cost-only Hessian
(ocp.stagewise, ocp.compiled): the same solutions as CasADi's VM with the exact Hessian.

One compilation per test session (a temporary cache, -O0: ~10 s for the exact Hessian,
well under a second more for the cost Hessian; the stage functions do not depend on the
bounds, so the binding case reuses them).
"""

from __future__ import annotations

import numpy as np
import pytest

from ocp import compiled as cc
from ocp import paper000 as paper
from rcm_pin.errors import InvalidInputError

N = 10  # intervals: the stage functions are those of any N with the same h


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("RCM_PIN_CACHE", str(tmp_path_factory.mktemp("casadi_cache")))
        yield


def _build(hessian="exact", compile=False, lock_wrist=False, reduced=True):
    return paper.build(
        n_intervals=N, lock_wrist=lock_wrist, hessian=hessian, compile=compile, reduced=reduced
    )


def _binding(mech) -> np.ndarray:
    lim = np.full(mech.nq, np.inf)
    lim[:3] = 0.8 * paper.peak_efforts(mech, 401)[:3]
    return lim


def _same(res, ref, q_tol: float, tau_tol: float) -> None:
    np.testing.assert_allclose(res.q_colloc, ref.q_colloc, rtol=0, atol=q_tol)
    np.testing.assert_allclose(res.v_colloc, ref.v_colloc, rtol=0, atol=q_tol / paper.HORIZON * N)
    # efforts: A = D D Q / h^2 amplifies a position difference by ~1/h^2 ~ 2.5e3 here
    np.testing.assert_allclose(res.tau, ref.tau, rtol=0, atol=tau_tol)


@pytest.mark.parametrize("reduced", [True, False])
def test_compiled_exact_hessian_gives_the_vm_solution(cache, reduced):
    """IPOPT on the full or the reduced NLP (URDF limits, no screening) and Newton's method
    (no limits): compiled stage functions give the VM's iterates."""
    ocp_vm, mech = _build(reduced=reduced)
    ocp_c, _ = _build(compile="-O0", reduced=reduced)
    assert len(ocp_c.nlp.compiled) == 4 and all(r.path is not None for r in ocp_c.nlp.compiled)
    for lim, screen in ((mech.model.effortLimit.copy(), False), (None, True)):
        ref = paper.solve(ocp_vm, mech, effort_limits=lim, screen=screen)
        res = paper.solve(ocp_c, mech, effort_limits=lim, screen=screen)
        assert res.success and res.iterations == ref.iterations and res.solver == ref.solver
        _same(res, ref, 1e-12, 1e-9)
        assert abs(res.objective - ref.objective) <= 1e-12 * max(1.0, abs(ref.objective))


def test_second_build_loads_from_the_cache(cache, monkeypatch):
    """Loaded, not compiled: no compiler runs (a compiler call would fail the build) and
    every stage function is a cache hit (no wall-clock bound: that measures the machine)."""
    _build(compile="-O0")  # compiled by the previous test, or here
    before = cc.STATS.copy()

    def no_compiler(*args, **kwargs):
        raise AssertionError(f"the C compiler ran: {args}")

    monkeypatch.setattr(cc.subprocess, "run", no_compiler)
    ocp, _ = _build(compile="-O0", lock_wrist=True)  # other bounds: the same stage
    assert cc.STATS["compiled"] == before["compiled"] and all(r.cached for r in ocp.nlp.compiled)
    assert cc.STATS["hits"] == before["hits"] + len(ocp.nlp.compiled)


def test_cost_hessian_converges_to_the_exact_solution_with_binding_limits(cache):
    ocp_e, mech = _build(compile="-O0", lock_wrist=True)
    ocp_c, _ = _build(hessian="cost", compile="-O0", lock_wrist=True)
    lim = _binding(mech)
    exact = paper.solve(ocp_e, mech, effort_limits=lim)
    cost = paper.solve(ocp_c, mech, effort_limits=lim)
    assert exact.success and cost.success
    assert np.abs(cost.tau).max(0)[:3] == pytest.approx(lim[:3], rel=1e-6)  # limits bind
    # the same KKT point, reached by other iterates: IPOPT's tolerance 1e-12 on the
    # scaled KKT residual bounds the difference
    _same(cost, exact, 1e-9, 1e-6)
    assert abs(cost.objective - exact.objective) <= 1e-9 * abs(exact.objective)


def test_invalid_options_are_refused():
    with pytest.raises(InvalidInputError, match=r"valid: hessian 'exact' \| 'cost'"):
        paper.build(n_intervals=5, hessian="gauss")  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="fatrop differentiates the expanded NLP"):
        paper.build(n_intervals=5, solver="fatrop", compile=True)
    with pytest.raises(InvalidInputError, match=r"jit=True; valid: .*compile without jit"):
        paper.build(n_intervals=5, jit=True, compile="-O0")


@pytest.mark.parametrize("reduced", [True, False])
def test_screening_returns_the_unlimited_solution_when_it_keeps_the_limits(reduced):
    """URDF limits (inactive): the unlimited solve (Newton's method, or IPOPT on the full
    NLP) is returned; it is the same optimum as the limited solve (interior-point iterates
    differ: ~1e-13 in q, efforts amplified by 1/h^2)."""
    ocp, mech = paper.build(n_intervals=N, reduced=reduced)
    free, _ = paper.build(n_intervals=N, drive_limits=False, reduced=reduced)
    x0, lim = paper.initial_state(mech), mech.model.effortLimit.copy()
    screened = ocp.solve(paper.reference_position, x0, effort_limits=lim, screen=True)
    unlimited = paper.solve(free, mech)
    limited = paper.solve(ocp, mech, effort_limits=lim, screen=False)
    status = "Step_Converged" if reduced else "Solve_Succeeded"
    assert screened.status == status and screened.iterations == unlimited.iterations
    np.testing.assert_array_equal(screened.q_colloc, unlimited.q_colloc)
    assert np.all(np.abs(screened.tau) <= lim)
    _same(screened, limited, 1e-11, 1e-7)


def test_screening_falls_back_to_the_limited_solve_when_the_limits_bind():
    ocp, mech = paper.build(n_intervals=N, lock_wrist=True)
    x0, lim = paper.initial_state(mech), _binding(mech)
    plain = ocp.solve(paper.reference_position, x0, effort_limits=lim, screen=False)
    screened = ocp.solve(paper.reference_position, x0, effort_limits=lim)  # the default
    np.testing.assert_array_equal(screened.q_colloc, plain.q_colloc)  # the same solve
    free, _ = paper.build(n_intervals=N, drive_limits=False, lock_wrist=True)
    first = paper.solve(free, mech)  # the screening solve: it violates the limits
    assert np.abs(first.tau[:, :3]).max(0) == pytest.approx(lim[:3] / 0.8, rel=0.05)
    assert screened.iterations == plain.iterations + first.iterations
    unscreened = ocp.solve(paper.reference_position, x0, screen=True)  # no finite limit
    assert unscreened.iterations == paper.solve(ocp, mech).iterations


def test_without_a_compiler_the_ocp_falls_back_to_the_vm(monkeypatch):
    monkeypatch.setattr(cc, "c_compiler", lambda: None)
    with pytest.warns(cc.CompileWarning, match="no C compiler found"):
        ocp, mech = paper.build(n_intervals=N, drive_limits=False, compile=True)
    assert all(r.path is None for r in ocp.nlp.compiled)
    ref_ocp, _ = paper.build(n_intervals=N, drive_limits=False)
    with pytest.warns(cc.CompileWarning, match="newton_stage is not compiled"):
        res = paper.solve(ocp, mech)  # Newton's function is built at the first solve
    ref = paper.solve(ref_ocp, mech)
    assert res.solver == ref.solver == "newton" and res.iterations == ref.iterations
    _same(res, ref, 1e-12, 1e-9)
