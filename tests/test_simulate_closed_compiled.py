"""``simulate(..., backend="compiled")`` on closed plants: the closed right-hand side as one
compiled CasADi function (``ocp.kernels.closed_rhs``, ``rcm_pin.control.closed_backend``).

* the kernel against the Python hot path (``ClosedLaw`` / ``ClosedPlant``) and the public
  ``ComputedTorque.effort`` / ``constrained.forward_dynamics`` on seeded random states of
  the 3-RRR and the five-bar (with saturating limits, and a plant whose masses differ
  from the controller's model);
* whole runs of both backends: the same trajectory at the integration tolerance; the
  output samples from the kernel equal the Python hot path's on the same states;
* the declining path: near a rank loss of the closure rows a call declines and the
  Python right-hand side answers from the same inputs;
* the unsupported cases: typed errors naming why.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import rcm_pin
from ocp.kernels.closed_rhs import closed_rhs as build_kernel
from rcm_pin.control.backends import COVERS, compiled_rhs
from rcm_pin.control.closed_backend import samples_of
from rcm_pin.control.closed_hot_path import ClosedLaw, ClosedPlant
from rcm_pin.control.scenario import controller, run, scenarios, start_state
from rcm_pin.control.simulate import simulate
from rcm_pin.dynamics import constrained as cd
from rcm_pin.dynamics.tree import mass_matrix_pin
from rcm_pin.errors import InvalidInputError
from rcm_pin.model import kernels
from rcm_pin.model.newton import constraint_rank

#: The same quantities by another route (rounding only): the law's efforts are two small
#: square solves and one RNEA (measured ≤ 2e-14 relative); q̈ is checked against
#: 1e-15·cond(KKT) (two backward-stable solves of one system differ by up to cond·ε).
RTOL = 1e-12
#: Trajectories of the two backends (DOP853, rtol 1e-10, atol 1e-12): DOP853 keeps each
#: step's local error below rtol·|y| + atol (|q̇| ≤ 3 here: 3e-10) and the tracking loop
#: (error time constant 1/√Kn) does not let it grow; the right-hand sides differ by
#: rounding, so the runs may take other steps and differ by the sum of two global errors.
#: Measured: 4e-15 in q, 1e-13 in q̇ (the step sequences coincided). Bounds: 1e-9 in q,
#: 1e-8 in q̇, as the serial backend's (tests/test_simulate_compiled.py).
Q_TOL, V_TOL = 1e-9, 1e-8
BAUMGARTE = (50.0, 1.0)
CASES = [  # (mechanism, scenario, plant's xacro arguments, limits scale)
    ("planar_3rrr", "circle", {}, None),
    ("planar_3rrr", "circle", {}, 0.05),  # x drive limits: clips in most states
    ("five_bar", "home_circle", {}, None),
    ("five_bar", "home_circle", {"m_output": 0.9}, None),  # the plant differs from the model
]


def _pair(name: str, scenario: str, plant_args: dict, scale: float | None):
    model = rcm_pin.load(name)
    plant = rcm_pin.load(name, **plant_args) if plant_args else model
    sc = scenarios(model)[scenario]
    ctrl = controller(model, sc)
    if scale is not None:
        ctrl = dataclasses.replace(ctrl, limits=scale * np.asarray(ctrl.limits))
    return model, plant, sc, ctrl


@pytest.mark.parametrize(("name", "scenario", "plant_args", "scale"), CASES)
def test_the_kernel_equals_the_python_hot_path(
    name: str, scenario: str, plant_args: dict, scale: float | None
) -> None:
    model, plant, sc, ctrl = _pair(name, scenario, plant_args, scale)
    kernel = build_kernel(plant, ctrl)
    assert kernel is not None and kernel.compiled
    bound = kernel.bind(BAUMGARTE)
    law, py_plant = ClosedLaw(ctrl, plant), ClosedPlant(plant, BAUMGARTE)
    q0, _ = start_state(model, sc)
    rng, clipped = np.random.default_rng(7), 0
    for _ in range(8):
        q, v = q0 + rng.uniform(-0.05, 0.05, plant.nq), rng.normal(0.0, 1.0, plant.nv)
        t = float(rng.uniform(0.0, sc.duration))
        y, r = np.concatenate([q, v]), np.concatenate(law.reference(t))
        ydot, tau_d, raw, x, xd, guard = bound.outputs(y, r)
        tau = law.tau(t, q, v)
        scale_tau = np.abs(tau).max()
        np.testing.assert_allclose(tau_d, tau[law.drive_v], rtol=RTOL, atol=RTOL * scale_tau)
        effort = ctrl.effort(t, q, v)  # the public, validated law itself
        np.testing.assert_allclose(tau_d, effort.tau, rtol=RTOL, atol=RTOL * scale_tau)
        assert bool(np.any(tau_d != raw)) == effort.saturated
        clipped += int(effort.saturated)
        np.testing.assert_array_equal(ydot[: plant.nv], v)
        acc, lam = cd.forward_dynamics(plant, q, v, tau, BAUMGARTE)  # the public route
        _, jc, _ = cd.world_closure(plant, q, v)
        mass = mass_matrix_pin(plant.model, plant.model.createData(), q)
        kkt = np.block([[mass, -jc.T], [jc, np.zeros((len(jc), len(jc)))]])
        bound_acc = 1e-15 * np.linalg.cond(kkt) * np.abs(acc).max()
        np.testing.assert_allclose(ydot[plant.nv :], acc, rtol=0, atol=bound_acc)
        np.testing.assert_allclose(ydot[plant.nv :], py_plant.accel(q, v, tau), atol=bound_acc)
        x_py, xd_py = law.plant_kin.task(q, v)[:2]
        np.testing.assert_allclose(x, x_py, rtol=0, atol=RTOL)
        np.testing.assert_allclose(xd, xd_py, rtol=0, atol=RTOL * np.abs(xd_py).max())
        assert 1.0 <= guard[0] < 1e3  # ‖R‖‖R⁻¹‖ ≥ 1: far from a rank loss here
    assert clipped > 0 if scale is not None else clipped == 0


def _runs(name: str, scenario: str, duration: float):
    mech = rcm_pin.load(name)
    sc = dataclasses.replace(scenarios(mech)[scenario], duration=duration, samples=101)
    return run(mech, sc), run(mech, sc, backend="compiled")


@pytest.mark.parametrize(("name", "scenario"), [("planar_3rrr", "circle"),
                                                ("five_bar", "home_circle")])  # fmt: skip
def test_a_compiled_run_is_the_python_run_at_the_integration_tolerance(
    name: str, scenario: str
) -> None:
    py, fast = _runs(name, scenario, 0.3)
    assert py.status == fast.status == "completed"
    np.testing.assert_array_equal(fast.t, py.t)
    np.testing.assert_allclose(fast.q, py.q, rtol=0, atol=Q_TOL)
    np.testing.assert_allclose(fast.v, py.v, rtol=0, atol=V_TOL)
    np.testing.assert_allclose(fast.x, py.x, rtol=0, atol=Q_TOL)


def test_the_kernel_samples_are_the_python_samples() -> None:
    mech = rcm_pin.load("planar_3rrr")
    sc = dataclasses.replace(scenarios(mech)["circle"], duration=0.2, samples=41)
    ctrl = dataclasses.replace(controller(mech, sc), limits=0.15)  # [N·m]: clips part of the run
    res = simulate(mech, ctrl, sc.duration, *start_state(mech, sc),
                   options=sc.simulation_options(mech, backend="compiled"))  # fmt: skip
    law = ClosedLaw(ctrl, mech)
    rhs = compiled_rhs(mech, ctrl, BAUMGARTE)
    got, expected = samples_of(rhs, law, res.t, res.q, res.v), law.samples(res.t, res.q, res.v)
    assert got is not expected and expected.saturated.any()  # the kernel's, with clipping
    scale = np.abs(expected.tau).max()
    np.testing.assert_allclose(got.tau, expected.tau, rtol=RTOL, atol=RTOL * scale)
    np.testing.assert_array_equal(got.saturated, expected.saturated)
    np.testing.assert_array_equal(got.alternate, expected.alternate)
    np.testing.assert_array_equal(np.isnan(got.measure), np.isnan(expected.measure))
    np.testing.assert_allclose(got.x, expected.x, rtol=0, atol=RTOL)
    np.testing.assert_allclose(got.xd, expected.xd, rtol=0, atol=RTOL * np.abs(expected.xd).max())
    np.testing.assert_allclose(res.tau, expected.tau, rtol=RTOL, atol=RTOL * scale)  # simulate's
    assert samples_of(None, law, res.t, res.q, res.v).tau.shape == expected.tau.shape


def test_a_call_near_a_rank_loss_declines_and_python_answers() -> None:
    mech = rcm_pin.load("five_bar")
    ctrl = controller(mech, scenarios(mech)["home_circle"])
    kernel = kernels.closed_rhs(mech, ctrl)
    assert kernel is not None
    loops = mech.loops
    assert loops is not None
    q = np.zeros(mech.nq)  # both legs stretched along the same line: J_c of rank 1
    q[loops.drive_q] = (-np.pi, 0.0)
    q[loops.passive_q] = (0.0, np.pi)
    v = np.full(mech.nv, 0.1)
    assert constraint_rank(cd.world_closure(mech, q, v)[1]) < loops.n_rows
    law = ClosedLaw(ctrl, mech)
    y, r = np.concatenate([q, v]), np.concatenate(law.reference(0.2))
    bound = kernel.bind(BAUMGARTE)
    assert bound(y, r) is None and bound.declined == 1
    calls: list[float] = []

    def python_rhs(t: float, y: np.ndarray) -> np.ndarray:
        calls.append(t)
        return np.full(len(y), 3.5)

    rhs = compiled_rhs(mech, ctrl, BAUMGARTE, python_rhs)
    np.testing.assert_array_equal(rhs(0.2, y), np.full(len(y), 3.5))  # the fallback's
    assert calls == [0.2]
    q_ok = start_state(mech, scenarios(mech)["home_circle"])[0]
    y_ok = np.concatenate([q_ok, v])
    assert rhs(0.2, y_ok)[0] == 0.1 and calls == [0.2]  # a regular state: the kernel's
    no_fallback = compiled_rhs(mech, ctrl, BAUMGARTE)  # declined without one: NaN
    assert np.isnan(no_fallback(0.2, y)).all() and np.isfinite(no_fallback(0.2, y_ok)).all()


def _message(name: str, why: str) -> str:
    return f"backend 'compiled' is not available for {name}: {why}; valid: {COVERS}"


def test_unsupported_closed_cases_raise_and_name_why() -> None:
    five = rcm_pin.load("five_bar")
    crossing = scenarios(five)["crossing"]  # drive switching
    with pytest.raises(InvalidInputError) as err:
        run(five, crossing, backend="compiled")
    assert str(err.value) == _message("five_bar", "drive switching is not supported")
    ppa = rcm_pin.load("translational_3ppapa")
    with pytest.raises(InvalidInputError) as err:
        compiled_rhs(ppa, controller(ppa, scenarios(ppa)["home_circle"]))
    assert str(err.value) == _message(ppa.name, "mimic joints are not supported")
    mech = rcm_pin.load("planar_3rrr")
    sc = dataclasses.replace(scenarios(mech)["circle"], duration=0.01)
    with kernels.disabled(), pytest.raises(InvalidInputError) as err:
        run(mech, sc, backend="compiled")
    why = "kernels are disabled ($RCM_PIN_NO_KERNELS or kernels.set_enabled(False))"
    assert str(err.value) == _message("planar_3rrr", why)


def test_one_kernel_per_pair_and_the_vm_computes_the_same() -> None:
    mech = rcm_pin.load("planar_3rrr")
    sc = scenarios(mech)["circle"]
    a, b = controller(mech, sc), controller(mech, sc, feedforward=False)
    ka, kb = kernels.closed_rhs(mech, a), kernels.closed_rhs(mech, b)
    assert ka is kernels.closed_rhs(mech, a) and ka is not kb and ka is not None
    assert ka.function.name() == kb.function.name()  # type: ignore[union-attr]
    vm = build_kernel(mech, b, vm=True)  # CasADi's VM: the same operations
    assert vm is not None and not vm.compiled
    q0, v0 = start_state(mech, sc)
    y, r = np.concatenate([q0, v0]), np.concatenate(ClosedLaw(b, mech).reference(0.4))
    fast, slow = kb.bind(BAUMGARTE)(y, r), vm.bind(BAUMGARTE)(y, r)  # type: ignore[union-attr]
    assert fast is not None and slow is not None
    np.testing.assert_allclose(fast, slow, rtol=1e-13, atol=1e-13 * np.abs(slow).max())
    with kernels.disabled():
        assert kernels.closed_rhs(mech, a) is None


def test_cli_backend_flag_on_a_closed_plant(capsys: pytest.CaptureFixture[str]) -> None:
    import json

    from rcm_pin.cli import main

    base = ["simulate", "planar_3rrr", "--duration", "0.1", "--json"]
    assert main([*base, "--backend", "compiled"]) == 0
    fast = json.loads(capsys.readouterr().out)["runs"][0]
    assert main(base) == 0
    py = json.loads(capsys.readouterr().out)["runs"][0]
    assert fast["status"] == py["status"] == "completed"
    # the same trajectory at the integration tolerance (Q_TOL): the task error likewise
    assert abs(fast["rms_error"] - py["rms_error"]) <= Q_TOL
    assert (
        main(["simulate", "five_bar", "--duration", "0.1", "--json", "--backend", "compiled"]) == 2
    )
    error = json.loads(capsys.readouterr().out)["error"]
    why = _message("five_bar", "drive switching is not supported")
    assert error == {"type": "InvalidInputError", "message": why}
