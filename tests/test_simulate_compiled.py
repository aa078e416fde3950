"""``simulate(..., backend="compiled")``: the right-hand side as one compiled CasADi function.

* the compiled right-hand side against the Python hot path (``rcm_pin.control.hot_path``)
  and the public ``ComputedTorque.effort`` on random states: the efforts to 1e-12
  relative (the same law, rounding only), the
  accelerations by their residual in Pinocchio's own M q̈ = τ − b (1e-12 relative, an
  independent route) and against the hot path's q̈ to 1e-15·cond(M) relative (two
  backward-stable solves of one matrix differ by up to cond(M)·ε; cond(M) ≈ 1e7 here);
  with and without saturating limits, other gains / signs, a plant that differs from the
  controller's model;
* a whole run of both backends: the same trajectory at the integration tolerance
  (below), and both as close to a tight-tolerance run (rtol 1e-12);
* the unsupported cases and the option: typed errors, exact messages.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import rcm_pin
from ocp.kernels.serial_rhs import serial_rhs as build_kernel
from rcm_pin.cli import main
from rcm_pin.control.backends import COVERS, compiled_rhs, stacked_reference
from rcm_pin.control.computed_torque import ComputedTorque, Gains, drive_limits
from rcm_pin.control.hot_path import SerialPlant, reference_function
from rcm_pin.control.references import TRAJECTORIES, CircleWithAngle
from rcm_pin.control.simulate import SimulationOptions, simulate
from rcm_pin.errors import InvalidInputError
from rcm_pin.model import kernels

RTOL = 1e-12  # the same quantity by another route (rounding only)
#: Trajectories of the two backends (rtol 1e-10, atol 1e-12): each run is within its
#: own global error of the exact solution; DOP853 keeps the local error of a step below
#: rtol·|y| + atol (|q̇| ≤ 2.8 here: 3e-10), and the stable closed loop (error time
#: constant 1/√Kn = 37 ms) does not let it grow over the run; the runs take different
#: steps (the right-hand sides differ by rounding), so they differ by the sum of two
#: global errors. Measured: 2e-11 [m, rad] in q, 8e-10 in q̇, each run as far from a
#: rtol 1e-12 run. Bounds: 1e-9 in q, 1e-8 in q̇ (about 30x the local bound).
Q_TOL, V_TOL = 1e-9, 1e-8
REF = TRAJECTORIES["paper000"]


def _load(name: str, **args: float) -> rcm_pin.Mechanism:
    return rcm_pin.load(name, **({"q3_upper": 0.3} if name == "rcm_bevel" else {}), **args)


def _states(mech: rcm_pin.Mechanism, seed: int, count: int = 12):
    rng = np.random.default_rng(seed)
    lo = np.where(np.isfinite(mech.lower), mech.lower, -1.0)
    hi = np.where(np.isfinite(mech.upper), mech.upper, 1.0)
    for _ in range(count):
        q = lo + (hi - lo) * rng.uniform(0.2, 0.8, mech.nq)
        yield q, rng.normal(0.0, 1.0, mech.nv), float(rng.uniform(0.0, 2.0))


CASES = [
    ("rcm_bevel", {}, dict(limits=None)),
    ("rcm_bevel", {}, dict(limits=0.3)),  # x drive_limits: clips in most states
    ("rcm_bevel", {"m_gear": 0.02}, dict(limits=None, printed_sign=True, feedforward=False)),
    ("rcm_belt", {}, dict(limits=None)),
    ("rcm_belt", {}, dict(limits=0.3)),
    ("rcm_two_mass", {}, dict(limits=0.3, gains=Gains(400.0, 30.0))),
]


@pytest.mark.parametrize(("name", "plant_args", "law"), CASES)
def test_compiled_rhs_equals_the_python_hot_path(name: str, plant_args: dict, law: dict) -> None:
    model = _load(name)
    plant = _load(name, **plant_args) if plant_args else model
    limits = None if law["limits"] is None else law["limits"] * drive_limits(model)
    options = {k: v for k, v in law.items() if k not in ("limits", "gains")}
    ctrl = ComputedTorque(
        model, REF, law.get("gains", Gains(720.0, 12.0)), limits=limits, **options
    )
    kernel = build_kernel(plant, ctrl)
    assert kernel is not None and kernel.compiled
    py_law, py_plant = ctrl.hot_path_law(plant), SerialPlant(plant)
    data, clipped = plant.model.createData(), 0
    for q, v, t in _states(plant, 7):
        y, ref = np.concatenate([q, v]), py_law.reference(t)
        tau = py_law.tau(t, q, v)  # type: ignore[union-attr]
        raw = py_law.rnea(q, v, py_law.accel(t, q, v, *ref)[0])  # type: ignore[union-attr]
        clipped += int(np.any(tau != raw))
        np.testing.assert_allclose(
            kernel.tau(y, np.concatenate(ref)), tau, rtol=RTOL, atol=RTOL * np.abs(tau).max()
        )
        effort = ctrl.effort(t, q, v).tau_full  # the public, validated law itself
        np.testing.assert_allclose(
            kernel.tau(y, np.concatenate(ref)), effort, rtol=RTOL, atol=RTOL * np.abs(tau).max()
        )
        ydot = kernel(y, np.concatenate(ref))
        np.testing.assert_array_equal(ydot[: plant.nq], v)
        acc, expected = ydot[plant.nq :], py_plant.accel(q, v, tau)
        M = np.asarray(pin.crba(plant.model, data, plant.to_pin(q), pin.Convention.WORLD))
        M = (np.triu(M) + np.triu(M, 1).T)[np.ix_(plant.v_index, plant.v_index)]
        b = np.asarray(pin.nonLinearEffects(plant.model, data, plant.to_pin(q), plant.v_pin(v)))
        rhs = tau - b[plant.v_index]
        residual = np.abs(M @ acc - rhs).max()
        assert residual <= RTOL * (np.abs(M).max() * np.abs(acc).max() + np.abs(rhs).max())
        bound = 1e-15 * np.linalg.cond(M) * np.abs(expected).max()
        np.testing.assert_allclose(acc, expected, rtol=0, atol=bound)
    assert clipped > 0 if law["limits"] is not None else clipped == 0


def test_the_stacked_reference_is_the_reference() -> None:
    for ref in [*TRAJECTORIES.values(), CircleWithAngle()]:
        fast, slow = stacked_reference(ref), reference_function(ref)
        for t in (0.0, 0.123, 1.7, 40.3):
            expected = np.concatenate(slow(t))
            # math.sin / numpy.sin: the same to an ulp or two (2e-16 relative)
            np.testing.assert_allclose(fast(t), expected, rtol=1e-15, atol=1e-15)


def test_one_library_per_structure_and_one_kernel_per_pair() -> None:
    mech = _load("rcm_bevel")
    a = ComputedTorque(mech, REF, Gains(720.0, 12.0))
    b = ComputedTorque(mech, REF, Gains(100.0, 20.0), limits=1.0)
    ka, kb = kernels.serial_rhs(mech, a), kernels.serial_rhs(mech, b)
    assert ka is kernels.serial_rhs(mech, a) and ka is not kb
    assert ka.function.name() == kb.function.name()  # type: ignore[union-attr]
    vm = build_kernel(mech, b, vm=True)  # CasADi's VM: the same operations
    assert vm is not None and not vm.compiled
    y, r = np.linspace(0.05, 0.3, 12), np.concatenate(reference_function(REF)(0.4))
    np.testing.assert_allclose(vm(y, r), kb(y, r), rtol=1e-14)  # type: ignore[union-attr]
    with kernels.disabled():
        assert kernels.serial_rhs(mech, a) is None


def _bevel_run(backend: str, rtol: float = 1e-10, atol: float = 1e-12):
    mech = _load("rcm_bevel")
    ctrl = ComputedTorque(mech, REF, Gains(720.0, 12.0), limits=drive_limits(mech))
    options = SimulationOptions(samples=201, rtol=rtol, atol=atol, backend=backend)
    return simulate(mech, ctrl, 2.0, options=options)


def test_a_compiled_run_is_the_python_run_at_the_integration_tolerance() -> None:
    py, fast = _bevel_run("python"), _bevel_run("compiled")
    tight = _bevel_run("python", rtol=1e-12, atol=1e-14)
    assert py.status == fast.status == "completed"
    for other in (py, tight):
        np.testing.assert_allclose(fast.q, other.q, rtol=0, atol=Q_TOL)
        np.testing.assert_allclose(fast.v, other.v, rtol=0, atol=V_TOL)
    np.testing.assert_allclose(py.q, tight.q, rtol=0, atol=Q_TOL)
    # the samples are recomputed by the Python hot path from the states of either run
    np.testing.assert_array_equal(fast.t, py.t)
    np.testing.assert_allclose(fast.x, py.x, rtol=0, atol=Q_TOL)
    # the runs may take other steps (the right-hand sides differ by rounding): hence the
    # integration tolerances above, not bitwise equality, and no claim on nfev either way


def test_the_backend_option_is_validated() -> None:
    with pytest.raises(InvalidInputError) as err:
        _bevel_run("fast")
    assert str(err.value) == "backend 'fast' is invalid; valid: python, compiled"


def _message(name: str, why: str) -> str:
    return f"backend 'compiled' is not available for {name}: {why}; valid: {COVERS}"


def test_unsupported_cases_raise_and_name_why() -> None:
    ur5 = rcm_pin.load("ur5")
    bevel = _load("rcm_bevel")
    closed = rcm_pin.load("planar_3rrr")
    cases = [
        (ur5, ComputedTorque(ur5, TRAJECTORIES["rig_circle"], Gains(720.0, 12.0)),
         "a redundant task (3 rows, 6 coordinates) is not supported"),
        (bevel, ComputedTorque(bevel, REF, Gains(400.0, 30.0), space="joint"),
         "joint-space control is not supported"),
        (bevel, ComputedTorque(closed, TRAJECTORIES["rig_circle"], Gains(720.0, 12.0)),
         "closed mechanisms are not supported"),  # a serial plant, a closed model
        (bevel, None, "it needs a ComputedTorque controller"),
    ]  # fmt: skip
    for mech, ctrl, why in cases:
        with pytest.raises(InvalidInputError) as err:
            compiled_rhs(mech, ctrl)
        assert str(err.value) == _message(mech.name, why)
    with pytest.raises(InvalidInputError) as err:  # through simulate
        simulate(ur5, cases[0][1], 0.1, np.zeros(6), options=SimulationOptions(backend="compiled"))
    assert str(err.value) == _message("ur5", cases[0][2])
    with kernels.disabled(), pytest.raises(InvalidInputError) as err:
        _bevel_run("compiled")
    why = "kernels are disabled ($RCM_PIN_NO_KERNELS or kernels.set_enabled(False))"
    assert str(err.value) == _message("rcm_bevel", why)


def test_cli_backend_flag(capsys: pytest.CaptureFixture[str]) -> None:
    import json

    base = ["simulate", "rcm_bevel", "--arg", "q3_upper=0.3", "--duration", "0.2", "--json"]
    assert main([*base, "--backend", "compiled"]) == 0
    fast = json.loads(capsys.readouterr().out)["runs"][0]
    assert main(base) == 0
    py = json.loads(capsys.readouterr().out)["runs"][0]
    assert fast["status"] == py["status"] == "completed"
    np.testing.assert_allclose(fast["rms_error"], py["rms_error"], rtol=1e-6)
    assert main([*base, "--backend", "fast"]) == 2
    error = json.loads(capsys.readouterr().out)["error"]
    assert error == {"type": "InvalidInputError",
                     "message": "backend 'fast' is invalid; valid: python, compiled"}  # fmt: skip
