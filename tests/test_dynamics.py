"""Dynamics on mimic models against the no-mimic projection and RNEA columns."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import rcm_pin
from rcm_pin.control.simulate import SimulationOptions, simulate
from rcm_pin.dynamics import tree as dy
from rcm_pin.errors import InvalidInputError, SingularConfigurationError

NAMES = ("rcm_bevel", "rcm_bevel_4dof", "rcm_belt", "rcm_two_mass")
N_STATES = 1000
TOL = 1e-10


@pytest.fixture(scope="module", params=NAMES)
def mech(request):
    return rcm_pin.load(request.param)


def _states(mech, n, seed=0):
    rng = np.random.default_rng(seed)
    q = rng.uniform(mech.lower, mech.upper, size=(n, mech.nq))
    v = rng.normal(scale=2.0, size=(n, mech.nq))
    a = rng.normal(scale=20.0, size=(n, mech.nq))
    return q, v, a


def test_against_projection_and_rnea_columns(mech):
    """M, RNEA, g, b, C, T, V over 10^3 random states (shared Data: repeated calls)."""
    model_full = mech.model_full
    data_full = model_full.createData()
    c = mech.coupling
    n = mech.nq
    eye = np.eye(n)
    zero = np.zeros(n)
    worst = dict.fromkeys(["M", "Mcol", "tau", "g", "b", "C", "T", "V", "fd"], 0.0)
    for q, v, a in zip(*_states(mech, N_STATES)):
        qf, vf, af = c.q_full(q), c.v_full(v), c.v_full(a)
        M = dy.mass_matrix(mech, q)
        Mf = np.asarray(pin.crba(model_full, data_full, qf))
        Mf = np.triu(Mf) + np.triu(Mf, 1).T
        g = dy.gravity(mech, q)
        cols = np.column_stack([dy.inverse_dynamics(mech, q, zero, eye[i]) - g for i in range(n)])
        tau = dy.inverse_dynamics(mech, q, v, a)
        tau_f = c.Gv.T @ pin.rnea(model_full, data_full, qf, vf, af)
        g_f = c.Gv.T @ pin.computeGeneralizedGravity(model_full, data_full, qf)
        b = dy.nonlinear_effects(mech, q, v)
        b_f = c.Gv.T @ pin.nonLinearEffects(model_full, data_full, qf, vf)
        T_f = pin.computeKineticEnergy(model_full, data_full, qf, vf)
        V_f = pin.computePotentialEnergy(model_full, data_full, qf)
        worst["M"] = max(worst["M"], np.abs(M - c.Gv.T @ Mf @ c.Gv).max())
        worst["Mcol"] = max(worst["Mcol"], np.abs(M - cols).max())
        worst["tau"] = max(worst["tau"], np.abs(tau - tau_f).max(), np.abs(tau - M @ a - b).max())
        worst["g"] = max(
            worst["g"],
            np.abs(g - g_f).max(),
            np.abs(g - dy.inverse_dynamics(mech, q, zero, zero)).max(),
        )
        worst["b"] = max(
            worst["b"],
            np.abs(b - b_f).max(),
            np.abs(b - dy.inverse_dynamics(mech, q, v, zero)).max(),
        )
        worst["C"] = max(worst["C"], np.abs(dy.coriolis_matrix(mech, q, v) @ v + g - b).max())
        worst["T"] = max(worst["T"], abs(dy.kinetic_energy(mech, q, v) - T_f))
        worst["V"] = max(worst["V"], abs(dy.potential_energy(mech, q) - V_f))
        worst["fd"] = max(
            worst["fd"], np.abs(M @ dy.forward_dynamics(mech, q, v, tau) - M @ a).max()
        )
    assert max(worst.values()) < TOL, worst


def test_default_crba_accumulates_on_mimic_models():
    """Documents the Pinocchio 4.1 behaviour that makes rcm-pin use Convention.WORLD."""
    mech = rcm_pin.load("rcm_bevel")
    q = np.array([0.2, -0.3, 0.08, 0.1, 0.2, 0.3])
    data = mech.model.createData()
    first = np.array(pin.crba(mech.model, data, q))
    second = np.array(pin.crba(mech.model, data, q))
    world = np.array(pin.crba(mech.model, data, q, pin.Convention.WORLD))
    np.testing.assert_allclose(np.triu(world), np.triu(first), atol=1e-15)
    if pin.__version__.startswith("4.1"):
        assert np.abs(second - first).max() > 1e-3
    for _ in range(3):
        np.testing.assert_allclose(
            dy.mass_matrix(mech, q), dy.full_mass_matrix(mech, q), atol=1e-15
        )


def test_pinocchio_refuses_mimic_in_energy_functions():
    mech = rcm_pin.load("rcm_bevel")
    q, v = np.zeros(6), np.ones(6)
    for fn, args in [
        ("aba", (q, v, v)),
        ("computeKineticEnergy", (q, v)),
        ("computePotentialEnergy", (q,)),
        ("computeAllTerms", (q, v)),
    ]:
        # Pinocchio's refusal names the mimic joints; its exact wording is Pinocchio's
        with pytest.raises(RuntimeError, match=r"(?i)\bmimic\b"):
            getattr(pin, fn)(mech.model, mech.model.createData(), *args)


def test_coriolis_skew_symmetry():
    mech = rcm_pin.load("rcm_belt")
    q, v, _ = _states(mech, 1, seed=3)
    q, v = q[0], v[0]
    h = 1e-6
    Mdot = (dy.mass_matrix(mech, q + h * v) - dy.mass_matrix(mech, q - h * v)) / (2 * h)
    S = Mdot - 2 * dy.coriolis_matrix(mech, q, v)
    np.testing.assert_allclose(S, -S.T, atol=1e-8)


@pytest.mark.parametrize("g", [None, (0.0, 0.0, -9.81)])
def test_free_motion_conserves_energy(g):
    mech = dy.with_gravity(rcm_pin.load("rcm_bevel"), g)
    q0 = np.array([np.pi - 0.3, -0.2, 0.09, 0.5, 0.4, -0.3])  # tool hanging below A
    v0 = np.array([1.0, -1.0, 0.1, 2.0, -1.0, 1.0])
    options = SimulationOptions(rtol=1e-12, atol=1e-12, allow_outside_limits=True)
    r = simulate(mech, None, 1.0, q0=q0, v0=v0, options=options)
    assert r.status == "completed"  # a physics check: q1 = pi - 0.3 is outside its limits
    E = np.array([dy.total_energy(mech, q, v) for q, v in zip(r.q, r.v)])
    assert np.abs(E - E[0]).max() <= 1e-8 * abs(E[0])


def test_with_gravity_leaves_original():
    mech = rcm_pin.load("rcm_bevel_4dof")
    free = dy.with_gravity(mech)
    q = np.array([0.1, 0.2, 0.08, 0.0])
    assert np.abs(dy.gravity(free, q)).max() == 0.0
    assert np.abs(dy.gravity(mech, q)).max() > 0.1
    with pytest.raises(InvalidInputError, match=r"^gravity \[1, 2\] is invalid; valid: 3 finite"):
        dy.with_gravity(mech, [1, 2])


def test_errors():
    mech = rcm_pin.load("rcm_bevel_4dof")
    with pytest.raises(
        InvalidInputError, match=r"^v has shape \(3,\); valid: \(4,\) for rcm_bevel_4dof"
    ):
        dy.nonlinear_effects(mech, np.zeros(4), np.zeros(3))
    with pytest.raises(InvalidInputError, match=r"^tau has NaN or infinite entries"):
        dy.forward_dynamics(mech, np.zeros(4), np.zeros(4), np.array([0, 0, np.nan, 0]))
    with pytest.raises(SingularConfigurationError, match=r"^mass matrix is not positive definite"):
        dy.solve_mass(np.diag([1.0, 0.0]), np.ones(2))


def test_pinocchio_coriolis_matrix_wrong_on_mimic_models():
    """Documents why coriolis_matrix projects the no-mimic C (Pinocchio 4.1)."""
    mech = rcm_pin.load("rcm_bevel")
    q, v, _ = _states(mech, 1, seed=0)
    q, v = q[0], v[0]
    C_pin = np.asarray(pin.computeCoriolisMatrix(mech.model, mech.model.createData(), q, v))
    b, g = dy.nonlinear_effects(mech, q, v), dy.gravity(mech, q)
    if pin.__version__.startswith("4.1"):
        assert np.abs(C_pin @ v + g - b).max() > 1e-3
    assert np.abs(dy.coriolis_matrix(mech, q, v) @ v + g - b).max() < 1e-12
