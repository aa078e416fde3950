"""The reduced tracking OCP (ocp.tracking_reduced, ocp.tracking_newton): the gaps solved for
the node states, Newton's method without path constraints and IPOPT on the reduced NLP with
them, against IPOPT on the full NLP (``reduced=False``, the route before issue 27)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import rcm_pin
from ocp import TrackingOCP
from ocp import paper000 as paper

N = 20


def _pref(ocp):
    return paper.reference_position(ocp.collocation_times())


def _kkt(ocp, res, x0, posture=None) -> float:
    """max |grad f| of the reduced problem at a solution (its KKT residual)."""
    post = np.zeros(ocp.sm.nv) if posture is None else posture
    params = ocp.stage_parameters(res.p_ref, post)
    return float(
        np.abs(ocp._route().newton.derivatives(res.q_colloc.ravel(), x0, params, ocp.h)[1]).max()
    )


def test_newton_finds_the_full_nlps_optimum_more_accurately():
    """Zero-cost problem (paper 000, rcm_bevel, no limits): Newton's q is the analytic
    discrete solution to rounding (1e-14), IPOPT's within its tolerance (1e-12); the node
    states satisfy the eliminated gaps."""
    ocp, mech = paper.build(n_intervals=N, drive_limits=False)
    full, _ = paper.build(n_intervals=N, drive_limits=False, reduced=False)
    new, old = paper.solve(ocp, mech), paper.solve(full, mech)
    assert (new.solver, old.solver) == ("newton", "ipopt") and new.success and old.success
    exact = paper.discrete_exact(ocp, mech)
    assert np.abs(new.q_colloc - exact.q).max() < 1e-14
    assert np.abs(old.q_colloc - exact.q).max() < 1e-12
    assert np.abs(new.q_colloc - old.q_colloc).max() < 1e-12
    # efforts: A = D D Q / h^2 amplifies a q difference by ~1/h^2 (~1e3 here)
    assert np.abs(new.tau - old.tau).max() < 1e-9
    assert new.tracking_error <= old.tracking_error and new.tracking_error < 1e-14
    assert new.objective < 1e-24 and old.objective < 1e-18
    # the gaps: q_{k+1} = Q_{k,d}, v_{k+1} = V_d (Radau), to rounding
    d = ocp.col.degree
    assert np.array_equal(new.q[1:], new.q_colloc[d - 1 :: d])
    np.testing.assert_allclose(new.v[1:], new.v_colloc[d - 1 :: d], rtol=0, atol=1e-12)
    assert _kkt(ocp, new, paper.initial_state(mech)) < 1e-10


@pytest.mark.parametrize("effort_weight", [1e-2, 10.0])
def test_newton_matches_ipopt_with_a_nonzero_optimum(effort_weight):
    """An effort weight makes the optimum a compromise (cost > 0, tracking error > 0) and
    the banded Hessian dense: the same minimiser as IPOPT on the full NLP (q within 1e-10:
    measured 2e-12), the same objective to 1e-13, and a KKT residual (the reduced
    gradient, 6e-9 at w_tau = 10 where |f| = 54) no larger than IPOPT's."""
    mech = rcm_pin.load("rcm_two_mass")
    lo, hi = paper.limits(mech, lock_wrist=False)
    kw = dict(horizon=paper.HORIZON, n_intervals=N, lower=lo, upper=hi, drive_limits=False,
              effort_weight=effort_weight)  # fmt: skip
    x0 = paper.initial_state(mech)
    ocp = TrackingOCP(mech, "tool", **kw)
    new = ocp.solve(paper.reference_position, x0)
    old = TrackingOCP(mech, "tool", reduced=False, **kw).solve(paper.reference_position, x0)
    assert new.solver == "newton" and new.success and old.success
    assert new.objective > 1e-2 and new.tracking_error > 1e-4  # not a zero-residual problem
    assert abs(new.objective - old.objective) <= 1e-13 * old.objective
    assert np.abs(new.q_colloc - old.q_colloc).max() < 1e-10
    assert np.abs(new.tau - old.tau).max() < 1e-7
    assert _kkt(ocp, new, x0) <= min(_kkt(ocp, old, x0), 1e-8)
    data = mech.model.createData()  # the efforts are the model's inverse dynamics
    for q, v, a, tau in zip(new.q_colloc, new.v_colloc, new.a_colloc, new.tau):
        assert np.abs(pin.rnea(mech.model, data, q, v, a) - tau).max() < 1e-9


def test_a_guess_at_the_optimum_takes_no_step():
    ocp, mech = paper.build("rcm_two_mass", n_intervals=N, drive_limits=False)
    x0 = paper.initial_state(mech)
    guess = ocp.guess_from(paper.discrete_exact(ocp, mech).q, x0)
    res = ocp.solve(paper.reference_position, x0, guess=guess)
    assert res.success and res.iterations == 0
    np.testing.assert_array_equal(res.q_colloc, paper.discrete_exact(ocp, mech).q)


def test_binding_limits_reduced_ipopt_matches_the_full_nlp():
    """0.8 x the peak efforts (binding): IPOPT on the reduced NLP and on the full one reach
    the same KKT point (IPOPT's tol 1e-12 on the scaled KKT residual bounds the
    difference); the screening Newton solve is counted in the iterations."""
    ocp, mech = paper.build(n_intervals=N, lock_wrist=True)
    full, _ = paper.build(n_intervals=N, lock_wrist=True, reduced=False)
    lim = np.full(mech.nq, np.inf)
    lim[:3] = 0.8 * paper.peak_efforts(mech, 401)[:3]
    new = paper.solve(ocp, mech, effort_limits=lim)
    old = paper.solve(full, mech, effort_limits=lim, screen=False)
    free = paper.solve(paper.build(n_intervals=N, drive_limits=False, lock_wrist=True)[0], mech)
    assert new.solver == "ipopt" and new.success and old.success
    assert new.iterations > free.iterations  # Newton's screening, then IPOPT
    assert np.abs(new.tau).max(0)[:3] == pytest.approx(lim[:3], rel=1e-6)  # limits bind
    assert np.all(np.abs(new.tau) <= lim + 1e-7)  # as test_ocp_tracking: IPOPT ends at 2e-8
    assert abs(new.objective - old.objective) <= 1e-9 * old.objective
    assert np.abs(new.q_colloc - old.q_colloc).max() < 1e-9
    assert np.abs(new.tau - old.tau).max() < 1e-6
    assert abs(new.tracking_error - old.tracking_error) < 1e-9


def test_newton_leaving_a_joint_limit_falls_back_to_ipopt():
    """q3 capped at 0.17 m (the reference needs 0.186 m): Newton's minimiser leaves the
    limit, so IPOPT's bounded solution is returned; it keeps the limit and cannot track."""
    mech = rcm_pin.load("rcm_two_mass")
    lo, hi = paper.limits(mech, lock_wrist=False)
    hi[2] = 0.17
    ocp = TrackingOCP(mech, "tool", horizon=paper.HORIZON, n_intervals=N, lower=lo,
                      upper=hi, drive_limits=False)  # fmt: skip
    res = ocp.solve(paper.reference_position, paper.initial_state(mech))
    assert res.solver == "ipopt" and res.success
    assert res.q_colloc[:, 2].max() <= 0.17 + 1e-8 and res.q_colloc[:, 2].max() > 0.17 - 1e-6
    assert res.tracking_error > 1e-3


def test_legendre_collocation_keeps_the_full_nlp():
    ocp, mech = paper.build("rcm_two_mass", n_intervals=5, drive_limits=False)
    assert ocp.reduced
    leg = TrackingOCP(mech, "tool", horizon=1.0, n_intervals=5, scheme="legendre",
                      drive_limits=False)  # fmt: skip
    assert not leg.reduced
    res = leg.solve(paper.reference_position, paper.initial_state(mech), raise_on_failure=False)
    assert res.solver == "ipopt"
