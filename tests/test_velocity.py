"""Velocity/acceleration problems: Pinocchio vs closed form vs finite differences."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import rcm_pin
from rcm_pin.analysis import jacobians as jac
from rcm_pin.analysis import velocity as vel
from rcm_pin.errors import InvalidInputError, SingularConfigurationError
from rcm_pin.mechanisms.rcm import velocity as rvel
from rcm_pin.mechanisms.rcm.closed_form import wrist_type
from rcm_pin.rotations import rpy_to_matrix

NAMES = ("rcm_bevel", "rcm_bevel_4dof", "rcm_belt", "rcm_bevel_rpy")
TOL = 1e-9


def _load(name):
    if name == "rcm_bevel_rpy":
        return rcm_pin.load("rcm_bevel", wrist_type="rpy")
    return rcm_pin.load(name)


def _states(mech, n, seed):
    rng = np.random.default_rng(seed)
    q = rng.uniform(mech.lower, mech.upper, size=(n, mech.nq))
    if mech.nq == 6:  # keep away from the wrist singularity (zyz: sin q5 = 0)
        q[:, 4] = rng.choice([-1, 1], n) * rng.uniform(0.2, 1.3, n)
    return q, rng.normal(size=(n, mech.nq)), rng.normal(size=(n, mech.nq))


@pytest.fixture(scope="module", params=NAMES)
def mech(request):
    return _load(request.param)


def test_forward_pinocchio_equals_closed_form(mech):
    qs, qds, qdds = _states(mech, 1000, 1)
    cf = rvel.closed_form_forward(qs, qds, qdds, wrist_type(mech))
    Jc = rvel.closed_form_jacobian(qs, wrist_type(mech))
    for k in range(len(qs)):
        m = vel.forward(mech, qs[k], qds[k], qdds[k])
        got = np.r_[m.v, m.omega, m.a, m.epsilon]
        want = np.r_[cf.v[k], cf.omega[k], cf.a[k], cf.epsilon[k]]
        assert np.abs(got - want).max() < TOL
        assert np.abs(jac.tool_jacobian(mech, qs[k]) - Jc[k]).max() < TOL


def test_inverse_both_routes_recover_rates(mech):
    qs, qds, qdds = _states(mech, 1000, 2)
    for k in range(len(qs)):
        m = vel.forward(mech, qs[k], qds[k], qdds[k])
        for route in (vel, rvel):  # Pinocchio, and the papers' closed form
            qd = route.inverse_velocity(mech, qs[k], m.v, m.omega)
            qdd = route.inverse_acceleration(mech, qs[k], qd, m.a, m.epsilon)
            assert np.abs(qd - qds[k]).max() < TOL
            assert np.abs(qdd - qdds[k]).max() < TOL


def test_mimic_jacobians_equal_projected_full_model(mech):
    """J and J̇ (WORLD route) of the mimic model equal the no-mimic model's times Gv."""
    qs, qds, _ = _states(mech, 50, 3)
    mf, df = mech.model_full, mech.model_full.createData()
    fid, Gv = mf.getFrameId("tool"), mech.coupling.Gv
    for q, qd in zip(qs, qds):
        qf, vf = mech.coupling.q_full(mech.to_pin(q)), Gv @ qd
        pin.computeJointJacobiansTimeVariation(mf, df, qf, vf)
        pin.updateFramePlacements(mf, df)
        J = pin.getFrameJacobian(mf, df, fid, jac.LWA) @ Gv
        dJ = pin.getFrameJacobianTimeVariation(mf, df, fid, jac.LWA) @ Gv
        assert np.abs(jac.tool_jacobian(mech, q) - J).max() < 1e-12
        assert np.abs(jac.jacobian_derivative(mech, q, qd) - dJ).max() < 1e-12
        m = vel.forward(mech, q, qd)
        assert np.abs(dJ @ qd - np.r_[m.a, m.epsilon]).max() < 1e-12


def test_finite_differences_of_fk(mech):
    qs, qds, qdds = _states(mech, 30, 4)
    h = 1e-4
    for q, qd, qdd in zip(qs, qds, qdds):

        def pose(t, q=q, qd=qd, qdd=qdd):
            return rcm_pin.tool_pose(mech, q + t * qd + 0.5 * t * t * qdd)

        Tm, T0, Tp = pose(-h), pose(0.0), pose(h)
        v = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
        a = (Tp[:3, 3] - 2 * T0[:3, 3] + Tm[:3, 3]) / h**2
        W = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ T0[:3, :3].T
        w = np.array([W[2, 1], W[0, 2], W[1, 0]])
        wp = vel.forward(mech, q + h * qd + 0.5 * h * h * qdd, qd + h * qdd).omega
        wm = vel.forward(mech, q - h * qd + 0.5 * h * h * qdd, qd - h * qdd).omega
        m = vel.forward(mech, q, qd, qdd)
        assert np.abs(m.v - v).max() < 1e-6
        assert np.abs(m.omega - w).max() < 1e-6
        assert np.abs(m.a - a).max() < 1e-6
        assert np.abs(m.epsilon - (wp - wm) / (2 * h)).max() < 1e-6
        dJ = (jac.tool_jacobian(mech, q + h * qd) - jac.tool_jacobian(mech, q - h * qd)) / (2 * h)
        assert np.abs(jac.jacobian_derivative(mech, q, qd) - dJ).max() < 1e-6


def test_omega_from_angle_rates_matches_finite_differences():
    rng = np.random.default_rng(5)
    for _ in range(20):
        ang, rate, acc = rng.normal(size=3), rng.normal(size=3), rng.normal(size=3)
        w, e = vel.omega_from_angle_rates(ang, rate, acc)
        h = 1e-5

        def omega_at(t, ang=ang, rate=rate, acc=acc, h=h):
            R = lambda s: rpy_to_matrix(*(ang + s * rate + 0.5 * s * s * acc))  # noqa: E731
            W = (R(t + h) - R(t - h)) / (2 * h) @ R(t).T
            return np.array([W[2, 1], W[0, 2], W[1, 0]])

        assert np.abs(w - omega_at(0.0)).max() < 1e-8
        assert np.abs(e - (omega_at(h) - omega_at(-h)) / (2 * h)).max() < 1e-5


def test_paper_example_rpy():
    mech = rcm_pin.load("rcm_bevel", q3_lower=-0.2, wrist_type="rpy")
    q = np.array([0, 0, -0.1, 0, 0, 0.0])
    qd = vel.inverse_velocity(mech, q, [1, 1, 1], [0.52] * 3)
    np.testing.assert_allclose(qd, [10, -10, 1, 0.52, 10.52, -9.48], atol=1e-12)
    np.testing.assert_allclose(
        rvel.coupling_terms(q, qd, "rpy"), [-10.6704, -10.1296, 10.1296], atol=1e-12
    )
    qdd = vel.inverse_acceleration(mech, q, qd, [0.2] * 3, [1, 1, 1])
    np.testing.assert_allclose(qdd, [202, -202, -19.8, -9.1296, 213.1296, -190.3296], atol=1e-9)


def test_paper_example_zyz_is_singular():
    mech = rcm_pin.load("rcm_bevel", q3_lower=-0.2)
    q = np.array([0, 0, -0.1, 0, 0, 0.0])
    with pytest.raises(SingularConfigurationError) as exc:
        vel.inverse_velocity(mech, q, [1, 1, 1], [0.52] * 3)
    assert str(exc.value) == (
        "rcm_bevel is singular at q = [0.0, 0.0, -0.1, 0.0, 0.0, 0.0]: Jacobian rank 5 < 6 "
        "(sigma_min/sigma_max = 0 <= 1e-09); cause: wrist axes e6 and e4 aligned: q4 and q6 "
        "turn the tool about the same axis (sin q5 = 0)"
    )
    # the position rows alone are regular: the first three rates do not depend on the wrist
    np.testing.assert_allclose(
        vel.inverse_velocity(mech, q, [1, 1, 1]), [10, -10, 1, 0, 0, 0], atol=1e-12
    )


def test_singular_position_message():
    mech = rcm_pin.load("rcm_bevel_4dof")
    with pytest.raises(SingularConfigurationError, match=r"cause: tool centre at the remote"):
        vel.inverse_velocity(mech, [0.1, 0.2, 0.0, 0.0], [0, 0, 1])


def test_bad_inputs():
    mech = rcm_pin.load("rcm_bevel_4dof")
    q = np.array([0.1, 0.2, 0.08, 0.3])
    with pytest.raises(InvalidInputError) as exc:
        vel.inverse_velocity(mech, q, [0, 0, 1], [1, 1, 1])
    assert str(exc.value).startswith(
        "the requested tool motion is not realisable by rcm_bevel_4dof (4 DOF)"
    )
    with pytest.raises(InvalidInputError) as exc:
        rvel.inverse_velocity(rcm_pin.load("five_bar"), np.zeros(4), [0, 0, 1])
    assert str(exc.value).startswith("the closed form needs an RCM mechanism, got five_bar")
    with pytest.raises(InvalidInputError) as exc:
        vel.inverse_velocity(mech, q, [0, 1])
    assert str(exc.value) == "v must have shape (..., 3), got (2,)"
    # a realisable ω for the 4-DOF tool: forward result
    m = vel.forward(mech, q, [0.1, -0.2, 0.3, 0.4])
    np.testing.assert_allclose(
        vel.inverse_velocity(mech, q, m.v, m.omega), [0.1, -0.2, 0.3, 0.4], atol=1e-12
    )


@pytest.mark.filterwarnings("error")
def test_inverse_velocity_of_a_huge_rate_is_refused_without_an_overflow_warning():
    mech = rcm_pin.load("rcm_bevel")
    q = np.array([0.1, 0.2, 0.08, 0.1, 0.2, 0.3])
    with pytest.raises(InvalidInputError) as exc:
        vel.inverse_velocity(mech, q, [1e300, 0.0, 0.0])
    assert str(exc.value) == (
        "v has an entry of magnitude 1e+300; valid: |value| <= 1e+06 (larger values are "
        "meaningless for a mechanism)"
    )
