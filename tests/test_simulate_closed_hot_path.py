"""The closed-mechanism right-hand side of ``simulate`` (rcm_pin.control.closed_hot_path)
against the public, validated functions of rcm_pin.dynamics.constrained and ComputedTorque.

One kinematics pass gives the numbers five passes give on the validated route: closure
rows, output rows, KKT forward dynamics and the computed-torque efforts agree to 1e-12
(relative to the largest entry: the same formulas, another LAPACK entry point).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import rcm_pin
from rcm_pin.control.closed_hot_path import ClosedLaw, ClosedPlant, KinematicsPass
from rcm_pin.control.computed_torque import ComputedTorque, DriveSwitching
from rcm_pin.control.scenario import run, scenarios
from rcm_pin.dynamics import constrained as cd

RTOL = 1e-12  # the same quantity by another route (rounding only)


def _close(a: np.ndarray, b: np.ndarray) -> None:
    scale = max(float(np.abs(b).max()), 1e-300)
    np.testing.assert_allclose(a, b, rtol=RTOL, atol=RTOL * scale)


@pytest.fixture(scope="module")
def rrr() -> tuple[rcm_pin.Mechanism, list[tuple[float, np.ndarray, np.ndarray]]]:
    """planar_3rrr and states of a short run of its circle scenario (v perturbed)."""
    mech = rcm_pin.load("planar_3rrr")
    res = run(mech, dataclasses.replace(scenarios(mech)["circle"], duration=0.05, samples=11))
    rng = np.random.default_rng(7)
    states = [
        (float(t), q, v + rng.normal(0.0, 0.2, v.shape)) for t, q, v in zip(res.t, res.q, res.v)
    ]
    return mech, states


def _random_states(mech: rcm_pin.Mechanism, seed: int, count: int = 6):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        yield rng.uniform(-1.0, 1.0, mech.model.nq), rng.normal(0.0, 1.0, mech.model.nv)


@pytest.mark.parametrize("name", ["planar_3rrr", "spherical_3rrr"])  # 3d and 6d closures
def test_one_pass_gives_the_closure_and_output_rows(name: str) -> None:
    mech = rcm_pin.load(name)
    kin = KinematicsPass(mech, mech.output)
    for q, v in _random_states(mech, 1):
        closure, task = kin.closure_and_task(q, v)
        for got, expected in zip(closure, cd.world_closure(mech, q, v)):
            _close(got, expected)
        for got, expected in zip(task, cd.output_motion(mech, q, v)):
            _close(got, expected)
        for got, expected in zip((kin.closure(q, v), kin.task(q, v)), (closure, task)):
            for a, b in zip(got, expected):
                np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("name", ["planar_3rrr", "spherical_3rrr"])
def test_plant_matches_the_constrained_forward_dynamics(name: str) -> None:
    mech = rcm_pin.load(name)
    plant = ClosedPlant(mech, (40.0, 0.8))
    rng = np.random.default_rng(3)
    for q, v in _random_states(mech, 2):
        tau = rng.normal(0.0, 0.3, mech.model.nv)
        _close(plant.accel(q, v, tau), cd.forward_dynamics(mech, q, v, tau, (40.0, 0.8))[0])


@pytest.mark.parametrize("limit", [None, 0.02])
def test_law_matches_the_public_effort(rrr, limit: float | None) -> None:
    mech, states = rrr
    sc = scenarios(mech)["circle"]
    ctrl = ComputedTorque(mech, sc.reference, sc.gains, limits=limit)
    law = ctrl.hot_path_law(mech)
    assert isinstance(law, ClosedLaw)
    saturated = 0
    for t, q, v in states:
        eff = ctrl.effort(t, q, v)
        _close(law.tau(t, q, v), eff.tau_full)
        saturated += eff.saturated
    assert (saturated > 0) == (limit is not None)
    t = np.array([s[0] for s in states])
    q, v = np.array([s[1] for s in states]), np.array([s[2] for s in states])
    got = law.samples(t, q, v)
    for i in range(len(t)):
        eff = ctrl.effort(float(t[i]), q[i], v[i])
        _close(got.tau[i], eff.tau_full)
        assert got.saturated[i] == eff.saturated
        xd = cd.output_drift(mech, q[i], v[i], ctrl.task_output)[0]
        _close(got.xd[i], xd)
        frame = mech.data.oMf[ctrl.task_output.frame_id]
        _close(got.x[i], ctrl.task_output.value(frame))
    assert not got.alternate.any() and np.isnan(got.measure).all()


def test_drive_switching_keeps_the_validated_effort() -> None:
    mech = rcm_pin.load("five_bar")
    sc = scenarios(mech)["crossing"]
    ctrl = ComputedTorque(mech, sc.reference, sc.gains, switching=DriveSwitching(0.2), limits=0.5)
    res = run(mech, dataclasses.replace(sc, duration=0.02))
    law = ctrl.hot_path_law(mech)
    got = law.samples(res.t, res.q, res.v)
    for i, (t, q, v) in enumerate(zip(res.t, res.q, res.v)):
        eff = ctrl.effort(float(t), q, v)
        np.testing.assert_array_equal(law.tau(float(t), q, v), eff.tau_full)
        np.testing.assert_array_equal(got.tau[i], eff.tau_full)
        assert got.measure[i] == eff.measure and got.alternate[i] == eff.alternate
