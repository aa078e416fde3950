"""Computed-torque tracking: linear error dynamics, gains, printed sign, limits."""

from __future__ import annotations

import numpy as np
import pytest

import rcm_pin
from rcm_pin.control.capabilities import pinocchio_task
from rcm_pin.control.computed_torque import ComputedTorque, Gains, drive_limits
from rcm_pin.control.linear import linear_error
from rcm_pin.control.plots import plot_deviation, plot_efforts, plot_phase
from rcm_pin.control.references import TRAJECTORIES, get_trajectory
from rcm_pin.control.simulate import SimulationOptions, simulate
from rcm_pin.control.task import task_kinematics, task_output
from rcm_pin.dynamics.tree import with_gravity
from rcm_pin.errors import InvalidInputError, JointLimitError, SingularConfigurationError
from rcm_pin.mechanisms.rcm.point import (
    joint_reference,
    point_bias,
    point_ik,
    point_jacobian,
    point_position,
)

PAPER = TRAJECTORIES["paper000"]
GAINS = Gains(720.0, 12.0)


@pytest.fixture(scope="module")
def two_mass():
    from rcm_pin.mechanisms.rcm.two_mass import two_mass_args

    return rcm_pin.load("rcm_two_mass", **two_mass_args(), q3_upper=0.3)


@pytest.mark.parametrize("feedforward", [True, False])
@pytest.mark.parametrize("name", ["rcm_two_mass", "rcm_bevel"])
def test_perfect_model_matches_linear_error_dynamics(name, feedforward):
    mech = rcm_pin.load(name, q3_upper=0.3)
    ctrl = ComputedTorque(mech, PAPER, GAINS, feedforward=feedforward, limits=drive_limits(mech))
    r = simulate(mech, ctrl, 0.5, options=SimulationOptions(samples=251))
    assert r.status == "completed" and not r.saturated.any()
    pred = linear_error(GAINS, r.error[0], r.error_rate[0], r.t, None if feedforward else PAPER)
    assert np.abs(pred - r.error).max() < 1e-6


def test_joint_space_converges(two_mass):
    ctrl = ComputedTorque(two_mass, PAPER, GAINS, space="joint")
    r = simulate(two_mass, ctrl, 1.5, options=SimulationOptions(samples=301))
    assert r.status == "completed"
    assert np.abs(r.steady_error(1.2)).max() < 2e-4


def test_printed_sign_diverges(two_mass):
    ctrl = ComputedTorque(two_mass, PAPER, GAINS, printed_sign=True)
    with pytest.raises(JointLimitError, match=r"^rcm_two_mass leaves its joint range at t = "):
        simulate(two_mass, ctrl, 1.0, options=SimulationOptions(samples=101))
    r = simulate(
        two_mass, ctrl, 1.0, options=SimulationOptions(samples=101, allow_outside_limits=True)
    )
    assert r.status.startswith("stopped")
    assert r.t[-1] < 0.5 and r.outside_limits


def test_saturation_is_reported(two_mass):
    ctrl = ComputedTorque(two_mass, PAPER, GAINS, limits=np.array([0.5, 0.5, 5.0]))
    r = simulate(
        two_mass, ctrl, 0.3, options=SimulationOptions(samples=61, allow_outside_limits=True)
    )  # q1 leaves
    assert r.saturated.any()
    assert np.abs(r.tau).max(axis=0) == pytest.approx([0.5, 0.5, 5.0])


def test_gains_tau_zeta():
    g = Gains.from_tau_zeta(0.02, 0.7)
    assert g.kn == pytest.approx(2500.0) and g.kc == pytest.approx(70.0)
    assert g.tau == pytest.approx(0.02) and g.zeta == pytest.approx(0.7)
    with pytest.raises(InvalidInputError, match=r"^tau=0.0, zeta=1.0 are invalid; valid: tau > 0"):
        Gains.from_tau_zeta(0.0, 1.0)
    with pytest.raises(InvalidInputError, match=r"^gains Kn=-1.0, Kc=1.0 are invalid"):
        Gains(-1.0, 1.0)


def test_point_kinematics_and_reference():
    rng = np.random.default_rng(2)
    mech = rcm_pin.load("rcm_bevel_4dof")
    from rcm_pin.analysis.kinematics import tool_pose

    for _ in range(20):
        q = np.array([*rng.uniform(-1, 1, 2), rng.uniform(0.05, 0.12), 0.0])
        v, a = rng.normal(size=4), rng.normal(size=4)
        np.testing.assert_allclose(point_position(q), tool_pose(mech, q)[:3, 3], atol=1e-12)
        np.testing.assert_allclose(point_ik(point_position(q)), q[:3], atol=1e-12)
        h = 1e-6
        pdd = (
            point_position(q + h * v + 0.5 * h**2 * a)
            - 2 * point_position(q)
            + point_position(q - h * v + 0.5 * h**2 * a)
        ) / h**2
        np.testing.assert_allclose(point_jacobian(q) @ a[:3] + point_bias(q, v), pdd, atol=1e-3)
    q, qd, qdd = joint_reference(PAPER, 0.3)
    np.testing.assert_allclose(point_position(q), PAPER.position(0.3), atol=1e-14)
    np.testing.assert_allclose(point_jacobian(q) @ qd, PAPER.velocity(0.3), atol=1e-14)


def test_errors(two_mass):
    with pytest.raises(
        InvalidInputError, match=r"^space 'cartesian' is invalid; valid: task, joint"
    ):
        ComputedTorque(two_mass, PAPER, GAINS, space="cartesian")
    with pytest.raises(
        InvalidInputError, match=r"^unknown trajectory 'circle'; valid: paper000, rig_circle"
    ):
        get_trajectory("circle")
    with pytest.raises(SingularConfigurationError, match=r"^tool centre \[0. 0. 0.\] is at A"):
        point_ik(np.zeros(3))
    with pytest.raises(InvalidInputError, match=r"^duration 0.0 is invalid; valid: >= 1e-09 \[s\]"):
        simulate(two_mass, None, 0.0, q0=np.array([0, 0, 0.1]))
    with pytest.raises(InvalidInputError, match=r"^q0 is required without a controller"):
        simulate(two_mass, None, 1.0)


def test_plots(tmp_path, two_mass):
    mech = with_gravity(two_mass, None)
    r = simulate(
        mech, ComputedTorque(mech, PAPER, GAINS), 0.2, options=SimulationOptions(samples=41)
    )
    for fn in (plot_deviation, plot_phase, plot_efforts):
        path = fn(r, tmp_path / f"{fn.__name__}.png")
        assert path.stat().st_size > 1000
    assert set(r.summary()) >= {"status", "rms_error", "steady_error", "peak_effort"}


@pytest.mark.parametrize("name", ["rcm_bevel", "rcm_two_mass"])
def test_closed_form_task_equals_pinocchio_task(name):
    """The family's closed-form task kinematics (p = q3 e4) against Pinocchio's frame route."""
    mech = rcm_pin.load(name)
    task = task_output(mech, None)
    closed, pino = task_kinematics(mech, task), pinocchio_task(mech, task)
    assert closed is not pino and list(closed.joints) == [0, 1, 2]
    rng = np.random.default_rng(5)
    for _ in range(200):
        q = rng.uniform(mech.lower, mech.upper)
        v = rng.normal(size=mech.nv)
        np.testing.assert_allclose(closed.position(q), pino.position(q), atol=1e-12)
        np.testing.assert_allclose(closed.jacobian(q), pino.jacobian(q)[:, :3], atol=1e-12)
        np.testing.assert_allclose(pino.jacobian(q)[:, 3:], 0.0, atol=1e-12)
        np.testing.assert_allclose(closed.bias(q, v), pino.bias(q, v), atol=1e-12)


def test_redundant_arm_tracks_with_the_pinocchio_task():
    """panda (7 joints + finger, task x, y, z): minimum-norm law, error dynamics hold."""
    from rcm_pin.control.scenario import home_circle, run

    mech = with_gravity(rcm_pin.load("panda"), None)
    sc = home_circle(mech)
    r = run(mech, sc)
    assert r.status == "completed"
    pred = linear_error(sc.gains, r.error[0], r.error_rate[0], r.t)
    assert np.abs(pred - r.error).max() < 1e-6


@pytest.mark.parametrize("name", ["rcm_bevel", "rcm_belt"])
def test_point_jacobian_and_bias_equal_pinocchio(name):
    """The closed forms J, h = J̇ q̇ of p = q3 e4 against Pinocchio's frame Jacobian and its
    time variation (LOCAL_WORLD_ALIGNED, mimic gears included) on random states."""
    from rcm_pin.analysis.jacobians import jacobian_derivative, tool_jacobian

    mech = rcm_pin.load(name)
    rng = np.random.default_rng(7)
    for _ in range(25):
        q = rng.uniform(mech.lower, mech.upper)
        v = rng.normal(size=mech.nv)
        np.testing.assert_allclose(point_jacobian(q), tool_jacobian(mech, q)[:3, :3], atol=1e-12)
        h = jacobian_derivative(mech, q, v)[:3] @ v
        np.testing.assert_allclose(point_bias(q, v), h, atol=1e-12)


def test_point_kinematics_batch_equals_the_one_state_functions():
    """The vectorised p, J, h of the output samples against the one-state closed forms."""
    from rcm_pin.mechanisms.rcm.point import point_kinematics

    rng = np.random.default_rng(11)
    q, v = rng.uniform(-3, 3, (500, 6)), rng.uniform(-5, 5, (500, 6))
    p, J, h = point_kinematics(q, v)
    np.testing.assert_array_equal(p, [point_position(qi) for qi in q])
    np.testing.assert_array_equal(J, [point_jacobian(qi) for qi in q])
    expected = np.array([point_bias(qi, vi) for qi, vi in zip(q, v)])
    np.testing.assert_allclose(h, expected, rtol=1e-14, atol=1e-14 * np.abs(expected).max())
