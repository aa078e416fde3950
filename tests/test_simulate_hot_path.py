"""The lean right-hand side of ``simulate`` (rcm_pin.control.hot_path) against independent routes.

* the plant's q̈ against Pinocchio's crba / nonLinearEffects called directly and a numpy
  solve of the symmetrised mass matrix, on random states (1e-12 relative: the same
  numbers by another linear solver);
* the law's τ against the public, validated ``ComputedTorque.effort`` and against
  ``pin.rnea`` called directly on ``ComputedTorque.acceleration`` (1e-12 relative);
* the efforts and task state at the output samples against the public law per sample;
* a whole run of ``simulate`` against ``solve_ivp`` integrating the public validated
  functions (``ComputedTorque.effort`` + ``dynamics.tree.forward_dynamics``) with the same
  method and tolerances: 1e-10 (both take the same steps; the right-hand sides differ by
  rounding only, amplified by the 2000-odd steps of a stable closed loop).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pinocchio as pin
import pytest
from scipy.integrate import solve_ivp

import rcm_pin
from rcm_pin.control.computed_torque import ComputedTorque, Gains, drive_limits
from rcm_pin.control.hot_path import (
    SerialLaw,
    SerialPlant,
    _to_pin,
    reference_function,
    reference_samples,
    solve,
)
from rcm_pin.control.references import TRAJECTORIES, CircleWithAngle
from rcm_pin.control.simulate import SimulationOptions, simulate
from rcm_pin.dynamics import tree
from rcm_pin.errors import SingularConfigurationError

RTOL = 1e-12  # the same quantity by another route (rounding only)


@pytest.fixture(scope="module")
def bevel() -> rcm_pin.Mechanism:
    return rcm_pin.load("rcm_bevel", q3_upper=0.3)


def _states(mech: rcm_pin.Mechanism, seed: int, count: int = 10):
    rng = np.random.default_rng(seed)
    lo, hi = mech.lower, mech.upper
    lo = np.where(np.isfinite(lo), lo, -1.0)
    hi = np.where(np.isfinite(hi), hi, 1.0)
    for _ in range(count):
        q = lo + (hi - lo) * rng.uniform(0.2, 0.8, mech.nq)
        yield q, rng.normal(0.0, 1.0, mech.nv), rng.normal(0.0, 2.0, mech.nv)


@pytest.mark.parametrize("name", ["rcm_bevel", "ur5", "panda"])
def test_plant_matches_pinocchio_called_directly(name: str) -> None:
    mech = rcm_pin.load(name)
    plant = SerialPlant(mech)
    model, data = mech.model, mech.model.createData()
    for q, v, tau in _states(mech, 1):
        qp, vp = mech.to_pin(q), mech.v_pin(v)
        M = np.asarray(pin.crba(model, data, qp, pin.Convention.WORLD))
        M = (np.triu(M) + np.triu(M, 1).T)[np.ix_(mech.v_index, mech.v_index)]
        b = np.asarray(pin.nonLinearEffects(model, data, qp, vp))[mech.v_index]
        expected = np.linalg.solve(M, tau - b)
        got = plant.accel(q, v, tau)
        np.testing.assert_allclose(got, expected, rtol=RTOL, atol=RTOL * np.abs(expected).max())
        np.testing.assert_allclose(
            got, tree.forward_dynamics(mech, q, v, tau), rtol=RTOL, atol=RTOL * np.abs(got).max()
        )


def test_mass_solves_read_one_triangle_and_refuse_an_indefinite_matrix() -> None:
    rng = np.random.default_rng(2)
    A = rng.normal(size=(6, 6))
    M = A @ A.T + 6 * np.eye(6)
    rhs = rng.normal(size=6)
    expected = np.linalg.solve(M, rhs)
    np.testing.assert_allclose(tree.solve_mass(np.tril(M), rhs), expected, rtol=RTOL)
    np.testing.assert_allclose(tree.solve_mass_upper(np.triu(M), rhs), expected, rtol=RTOL)
    for mass_solve in (tree.solve_mass, tree.solve_mass_upper):
        with pytest.raises(SingularConfigurationError, match=r"^mass matrix is not positive"):
            mass_solve(np.diag([1.0, -1.0]), np.ones(2))


def test_small_solve_is_numpys_and_refuses_a_singular_matrix() -> None:
    rng = np.random.default_rng(4)
    A, rhs = rng.normal(size=(5, 5)), rng.normal(size=5)
    np.testing.assert_allclose(solve(A, rhs), np.linalg.solve(A, rhs), rtol=RTOL)
    with pytest.raises(np.linalg.LinAlgError) as ours:
        solve(np.ones((2, 2)), np.ones(2))
    with pytest.raises(np.linalg.LinAlgError) as numpys:  # numpy's own error, its own words
        np.linalg.solve(np.ones((2, 2)), np.ones(2))
    assert str(ours.value) == str(numpys.value)


def test_pinocchio_order_maps_agree_with_the_mechanism(bevel: rcm_pin.Mechanism) -> None:
    # the copying branch (used when Pinocchio's order differs), forced on a real model
    stand_in = SimpleNamespace(
        identity_order=False,
        q_index=bevel.q_index,
        v_index=bevel.v_index,
        model=bevel.model,
        continuous=bevel.continuous,
    )
    q_pin, v_pin = _to_pin(stand_in)  # type: ignore[arg-type]
    q, v, _ = next(_states(bevel, 3))
    np.testing.assert_array_equal(q_pin(q), bevel.to_pin(q))
    np.testing.assert_array_equal(v_pin(v), bevel.v_pin(v))


def test_fast_reference_is_the_reference() -> None:
    for ref in TRAJECTORIES.values():
        fast = reference_function(ref)
        for t in (0.0, 0.123, 1.7):
            for a, b in zip(fast(t), ref.evaluate(t)):
                np.testing.assert_allclose(a, b, rtol=1e-15, atol=1e-17)
        x, xd, xdd = reference_samples(ref, np.array([0.0, 0.5]))
        np.testing.assert_allclose(xdd[1], ref.evaluate(0.5)[2], rtol=1e-15, atol=1e-17)
    other = CircleWithAngle()
    assert reference_function(other) == other.evaluate


def _controllers(mech: rcm_pin.Mechanism) -> list[ComputedTorque]:
    ref = TRAJECTORIES["paper000" if mech.family.name == "rcm" else "rig_circle"]
    out = [
        ComputedTorque(mech, ref, Gains(720.0, 12.0)),
        ComputedTorque(mech, ref, Gains(720.0, 12.0), limits=0.5 * drive_limits(mech)),
    ]
    if mech.family.name == "rcm":
        out.append(ComputedTorque(mech, ref, Gains(400.0, 30.0), space="joint", limits=0.2))
    return out


@pytest.mark.parametrize("name", ["rcm_bevel", "ur5", "panda"])
def test_law_matches_the_public_effort_and_rnea(name: str) -> None:
    mech = rcm_pin.load(name)
    model, data = mech.model, mech.model.createData()
    clipped = 0
    for k, ctrl in enumerate(_controllers(mech)):
        law = ctrl.hot_path_law(mech)
        assert isinstance(law, SerialLaw)
        for i, (q, v, _) in enumerate(_states(mech, 10 + k)):
            t = 0.37 * i
            tau = law.tau(t, q, v)
            eff = ctrl.effort(t, q, v)
            scale = np.abs(eff.tau_full).max()
            np.testing.assert_allclose(tau, eff.tau_full, rtol=RTOL, atol=RTOL * scale)
            acc = ctrl.acceleration(t, q, v)
            raw = np.asarray(pin.rnea(model, data, mech.to_pin(q), mech.v_pin(v), mech.v_pin(acc)))
            lim = np.inf if ctrl.limits is None else ctrl.limits
            direct = np.clip(raw[mech.v_index], -lim, lim)
            np.testing.assert_allclose(tau, direct, rtol=RTOL, atol=RTOL * scale)
            clipped += eff.saturated
    assert clipped > 0  # the limits were exercised


def test_samples_match_the_public_law_per_sample(bevel: rcm_pin.Mechanism) -> None:
    for ctrl in _controllers(bevel):
        law = ctrl.hot_path_law(bevel)
        states = list(_states(bevel, 20, 8))
        t = np.linspace(0.0, 1.0, len(states))
        q = np.array([s[0] for s in states])
        v = np.array([s[1] for s in states])
        got = law.samples(t, q, v)
        kin = ctrl.kinematics
        assert kin is not None
        for i in range(len(t)):
            eff = ctrl.effort(float(t[i]), q[i], v[i])
            scale = np.abs(eff.tau_full).max()
            np.testing.assert_allclose(got.tau[i], eff.tau_full, rtol=RTOL, atol=RTOL * scale)
            assert got.saturated[i] == eff.saturated
            np.testing.assert_allclose(got.x[i], kin.position(q[i]), rtol=RTOL)
            xd = kin.jacobian(q[i]) @ v[i, kin.joints]
            np.testing.assert_allclose(got.xd[i], xd, rtol=RTOL, atol=RTOL * np.abs(xd).max())
        assert not got.alternate.any() and np.isnan(got.measure).all()


def test_run_matches_an_integration_of_the_public_functions(bevel: rcm_pin.Mechanism) -> None:
    ctrl = ComputedTorque(
        bevel, TRAJECTORIES["paper000"], Gains(720.0, 12.0), limits=drive_limits(bevel)
    )
    duration, n = 0.3, bevel.nq
    res = simulate(bevel, ctrl, duration, options=SimulationOptions(samples=31))

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        q, v = y[:n], y[n:]
        tau = ctrl.effort(t, q, v).tau_full
        return np.concatenate([v, tree.forward_dynamics(bevel, q, v, tau)])

    y0 = np.concatenate([res.q[0], res.v[0]])
    ref = solve_ivp(rhs, (0.0, duration), y0, "DOP853", res.t, rtol=1e-10, atol=1e-12)
    assert res.completed and ref.status == 0
    assert res.nfev == ref.nfev  # the same steps
    np.testing.assert_allclose(res.q, ref.y[:n].T, rtol=0, atol=1e-10)
    np.testing.assert_allclose(res.v, ref.y[n:].T, rtol=0, atol=1e-10)
    taus = np.array([ctrl.effort(float(t), q, v).tau_full for t, q, v in zip(res.t, res.q, res.v)])
    np.testing.assert_allclose(res.tau, taus, rtol=0, atol=1e-12 * np.abs(taus).max())
