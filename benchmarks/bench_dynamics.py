"""Wall time per simulated second of ``rcm_pin.control.simulate.simulate`` against its floors.

Prints a JSON document; every figure is the median over ``--repeat`` rounds in which the
simulations and the floors run interleaved (one of each per round):

* ``serial``: the six-DOF ``rcm_bevel`` (``q3_upper=0.3``) under ``ComputedTorque`` on
  paper 000's trajectory (Kn = 720, Kc = 12, URDF drive limits; DOP853, rtol 1e-10,
  atol 1e-12, 1001 output samples);
* ``serial_compiled``: the same run with ``backend="compiled"`` (the right-hand side as one
  compiled CasADi function, ``rcm_pin.control.backends``), with its build / compile / load
  times, the per-call time of both right-hand sides alone and its trajectory differences
  to the ``serial`` line (and of both to a tight-tolerance run, rtol 1e-12, atol 1e-14);
* ``closed``: the 3-RRR tracking scenario (``scenarios(load("planar_3rrr"))["circle"]``,
  paper 004's law, run by ``rcm_pin.control.scenario.run``; constrained KKT dynamics);
* ``closed_compiled``: the same run with ``backend="compiled"`` (the closed right-hand
  side as one compiled CasADi function, ``rcm_pin.control.closed_backend``), with its
  trajectory differences to the ``closed`` line.

Each line: wall time per simulated second (``wall``: simulate as called, output samples
included; ``integration``: its ``solve_ivp`` part) and per right-hand side, and its ratios
to two floors times the run's right-hand-side count:

* the *Pinocchio floor*: the Pinocchio calls one right-hand side makes, timed alone on
  states of the run (serial: crba + nonLinearEffects for the plant, rnea for the law;
  closed: see :func:`closed_pin`);
* the *integrator floor*: ``solve_ivp`` DOP853 with the same tolerances, number of states
  and output samples on a trivial y' = A y, per evaluation, that right-hand side's own
  time subtracted.

One extra run of each under cProfile gives the share of time inside Pinocchio calls
(wrapped in Python functions named ``pin_*``; Boost.Python functions are invisible to
cProfile) versus numpy / scipy / Python overhead.

    python benchmarks/bench_dynamics.py [--duration 2] [--closed-duration 1] [--repeat 3]
    python benchmarks/bench_dynamics.py --duration 0.2 --closed-duration 0.1 --repeat 1
"""

from __future__ import annotations

import argparse
import cProfile
import dataclasses
import json
import pstats
import time
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np
import pinocchio as pin
from scipy.integrate import solve_ivp

import rcm_pin
from rcm_pin.control.computed_torque import ComputedTorque, Gains, drive_limits
from rcm_pin.control.references import TRAJECTORIES
from rcm_pin.control.result import SimulationResult
from rcm_pin.control.scenario import run, scenarios
from rcm_pin.control.simulate import SimulationOptions, simulate

#: Pinocchio functions counted as "inside Pinocchio" (those the plants and laws call).
PIN_CALLS = (
    "crba", "nonLinearEffects", "rnea", "forwardKinematics", "computeJointJacobians",
    "updateFramePlacements", "updateFramePlacement", "getFrameJacobian",
    "getFrameClassicalAcceleration", "integrate", "log3",
)  # fmt: skip


def _wrap(fn: Callable[..., Any], name: str) -> Callable[..., Any]:
    def wrapper(*a: Any, **k: Any) -> Any:
        return fn(*a, **k)

    wrapper.__name__ = wrapper.__qualname__ = f"pin_{name}"
    wrapper.__code__ = wrapper.__code__.replace(co_name=f"pin_{name}", co_qualname=f"pin_{name}")
    return wrapper


def pinocchio_share(fn: Callable[[], object]) -> dict[str, Any]:
    """Run ``fn`` once under cProfile with the Pinocchio calls wrapped; their share."""
    originals = {nm: getattr(pin, nm) for nm in PIN_CALLS if hasattr(pin, nm)}
    prof = cProfile.Profile()
    try:
        for nm, original in originals.items():
            setattr(pin, nm, _wrap(original, nm))
        prof.enable()
        fn()
        prof.disable()
    finally:
        for nm, original in originals.items():
            setattr(pin, nm, original)
    stats = pstats.Stats(prof)
    total = stats.total_tt  # type: ignore[attr-defined]
    by_call: dict[str, dict[str, float]] = {}
    for (_, _, func), (_, nc, _, ct, _) in stats.stats.items():  # type: ignore[attr-defined]
        if func.startswith("pin_"):
            by_call[func[4:]] = {"calls": nc, "s": ct}
    pin_time = sum(v["s"] for v in by_call.values())
    return {
        "profiled_total_s": total,
        "pinocchio_s": pin_time,
        "pinocchio_calls": int(sum(v["calls"] for v in by_call.values())),
        "pinocchio_share": pin_time / total,
        "overhead_share": 1.0 - pin_time / total,
        "by_function": dict(sorted(by_call.items(), key=lambda kv: -kv[1]["s"])),
    }


class Timed(NamedTuple):
    """Medians over the rounds of one callable, and its last result."""

    wall: float  # median wall time of the call [s]
    result: Any  # the last result
    inner: float  # median ``result.wall_time`` (simulate's solve_ivp part) [s]; NaN if none


def repeated(runs: dict[str, Callable[[], Any]], repeat: int) -> dict[str, Timed]:
    """Median wall time [s] of each callable over ``repeat`` rounds, and its last result.

    The callables (simulations and floors) are interleaved (one of each per round), so a
    slow drift of the machine load hits every figure alike and their ratios stay fair.
    """
    times: dict[str, list[float]] = {name: [] for name in runs}
    inner: dict[str, list[float]] = {name: [] for name in runs}
    results: dict[str, Any] = {}
    for _ in range(repeat):
        for name, fn in runs.items():
            start = time.perf_counter()
            results[name] = fn()
            times[name].append(time.perf_counter() - start)
            inner[name].append(getattr(results[name], "wall_time", np.nan))
    return {
        name: Timed(float(np.median(times[name])), results[name], float(np.median(inner[name])))
        for name in runs
    }


def _states(r: SimulationResult, count: int = 10) -> list[tuple[np.ndarray, np.ndarray]]:
    step = max(len(r.t) // count, 1)
    return list(zip(r.q[::step], r.v[::step]))


def serial_pin(mech: rcm_pin.Mechanism, r: SimulationResult, n: int) -> Callable[[], int]:
    """crba + nonLinearEffects (plant) and rnea (law) on states of a run, ``n`` times;
    returns the number of right-hand sides' worth of calls made."""
    model, data = mech.model, mech.model.createData()
    states = [(mech.to_pin(q), mech.v_pin(v)) for q, v in _states(r)]
    a = np.ones(model.nv)

    def calls() -> int:
        for _ in range(n):
            for q, v in states:
                pin.crba(model, data, q, pin.Convention.WORLD)
                pin.nonLinearEffects(model, data, q, v)
                pin.rnea(model, data, q, v, a)
        return n * len(states)

    return calls


def closed_pin(mech: rcm_pin.Mechanism, r: SimulationResult, n: int) -> Callable[[], int]:
    """The Pinocchio calls of one closed right-hand side (``control.closed_hot_path``: per
    model one kinematics pass, two frames per closure and the output frame read; rnea for
    the law, crba + nonLinearEffects for the plant) on states of a run, ``n`` times."""
    model, data, states = mech.model, mech.model.createData(), _states(r)
    assert mech.loops is not None
    frames = [f for c in mech.loops.closures for f in (c.frame_a_id, c.frame_b_id)]
    lwa, z = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED, np.zeros(model.nv)

    def calls() -> int:
        for _ in range(n):
            for q, v in states:
                for fs in ([*frames, mech.output.frame_id], frames):  # law, plant
                    pin.forwardKinematics(model, data, q, v, z)
                    pin.computeJointJacobians(model, data, q)
                    pin.updateFramePlacements(model, data)
                    for f in fs:
                        pin.getFrameJacobian(model, data, f, lwa)
                        pin.getFrameClassicalAcceleration(model, data, f, lwa)
                pin.rnea(model, data, q, v, z)
                pin.crba(model, data, q)
                pin.nonLinearEffects(model, data, q, v)
        return n * len(states)

    return calls


def integrator(
    states: int, duration: float, samples: int | None, tol: tuple[float, float]
) -> tuple[Callable[[], int], Callable[[], int]]:
    """solve_ivp DOP853 with tolerances ``tol`` (rtol, atol) and ``samples`` output samples
    on a trivial right-hand side y' = A y (a damped oscillator per coordinate, one matrix
    product), and that right-hand side alone 2000 times; both return their call counts."""
    n = states // 2
    w, zeta = np.linspace(20.0, 40.0, n), 0.5  # [rad/s], [-]
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.diag(w**2), -np.diag(2 * zeta * w)]])
    y0 = np.concatenate([np.full(n, 0.1), np.zeros(n)])
    t_eval = None if samples is None else np.linspace(0.0, duration, samples)

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        return A @ y

    def solve() -> int:
        sol = solve_ivp(rhs, (0.0, duration), y0, "DOP853", t_eval, rtol=tol[0], atol=tol[1])
        return int(sol.nfev)

    def alone() -> int:
        for _ in range(2000):
            rhs(0.0, y0)
        return 2000

    return solve, alone


def ratio(measured: str, baseline: str, value: float) -> dict[str, object]:
    """A ratio with both sides named (same run)."""
    return {"measured": measured, "baseline": baseline, "ratio": value}


def line(timed: Timed, duration: float) -> dict[str, Any]:
    """The figures of one simulated run (medians over the rounds)."""
    wall, r, integration = timed
    return {
        "simulated_s": duration,
        "status": r.status,
        "wall_s": wall,
        "integration_s": integration,
        "output_samples_s": wall - integration,
        "wall_per_simulated_s": wall / duration,
        "rhs_evaluations": r.nfev,
        "us_per_rhs": 1e6 * integration / r.nfev,
        "wall_us_per_rhs": 1e6 * wall / r.nfev,
    }


Case = tuple[dict[str, Any], Callable[[], SimulationResult], rcm_pin.Mechanism]


def serial_case(duration: float, backend: str = "python") -> Case:
    """rcm_bevel (6 DOF) under computed torque on paper 000's trajectory (warmed up)."""
    mech = rcm_pin.load("rcm_bevel", q3_upper=0.3)
    ctrl = ComputedTorque(
        mech, TRAJECTORIES["paper000"], Gains(720.0, 12.0), limits=drive_limits(mech)
    )
    info = {"mechanism": "rcm_bevel (6 DOF, q3_upper=0.3)",
            "controller": "ComputedTorque, paper000, Kn=720, Kc=12, drive limits",
            "tolerances": [1e-10, 1e-12], "samples": 1001, "backend": backend}  # fmt: skip
    return (
        info,
        lambda: simulate(mech, ctrl, duration, options=SimulationOptions(backend=backend)),
        mech,
    )


def compiled_costs(duration: float) -> dict[str, Any]:
    """Build / compile / load times of the compiled right-hand side (an empty cache in a
    temporary directory, then that cache, then CasADi's VM) and the per-call time of the
    compiled and the Python right-hand sides alone on states of a run [µs]."""
    import os
    import tempfile

    from ocp.kernels.serial_rhs import serial_rhs
    from rcm_pin.control.backends import compiled_rhs
    from rcm_pin.control.hot_path import SerialPlant

    mech = rcm_pin.load("rcm_bevel", q3_upper=0.3)
    ctrl = ComputedTorque(
        mech, TRAJECTORIES["paper000"], Gains(720.0, 12.0), limits=drive_limits(mech)
    )
    previous = os.environ.get("RCM_PIN_CACHE")
    with tempfile.TemporaryDirectory() as tmp:
        os.environ["RCM_PIN_CACHE"] = tmp
        try:
            fresh, hit = serial_rhs(mech, ctrl), serial_rhs(mech, ctrl)
        finally:
            os.environ.pop("RCM_PIN_CACHE") if previous is None else os.environ.update(
                RCM_PIN_CACHE=previous
            )
    vm = serial_rhs(mech, ctrl, vm=True)
    assert fresh is not None and hit is not None and vm is not None
    r = simulate(mech, ctrl, duration, options=SimulationOptions(samples=11))
    ys = [np.concatenate([q, v]) for q, v in _states(r)]
    law, plant, fast = ctrl.hot_path_law(mech), SerialPlant(mech), compiled_rhs(mech, ctrl)

    def python_rhs() -> int:
        for _ in range(200):
            for y in ys:
                q, v = y[: mech.nq], y[mech.nq :]
                np.concatenate((v, plant.accel(q, v, law.tau(0.3, q, v))))  # type: ignore[union-attr]
        return 200 * len(ys)

    def compiled() -> int:
        for _ in range(200):
            for y in ys:
                fast(0.3, y)
        return 200 * len(ys)

    timed = repeated({"python": python_rhs, "compiled": compiled}, 5)
    return {
        "build_and_compile_s (empty cache, -O1)": fresh.seconds,
        "load_from_cache_s": hit.seconds,
        "build_vm_s": vm.seconds,
        "instructions": int(vm.function.n_instructions()),
        "python_rhs_us": per_call_us(timed, "python"),
        "compiled_rhs_us (reference in Python included)": per_call_us(timed, "compiled"),
    }


def differences(a: SimulationResult, b: SimulationResult) -> dict[str, float]:
    """Largest differences of two runs on the same samples [rad, m; /s; N·m, N]."""
    return {"q": float(np.abs(a.q - b.q).max()), "v": float(np.abs(a.v - b.v).max()),
            "tau": float(np.abs(a.tau - b.tau).max())}  # fmt: skip


def _tight(duration: float) -> SimulationResult:
    """The serial run with rtol 1e-12, atol 1e-14 (python backend): a near-exact trajectory
    (at rtol 1e-13 the python backend's step size collapses: 237k evaluations for 2 s)."""
    mech = rcm_pin.load("rcm_bevel", q3_upper=0.3)
    ctrl = ComputedTorque(
        mech, TRAJECTORIES["paper000"], Gains(720.0, 12.0), limits=drive_limits(mech)
    )
    return simulate(mech, ctrl, duration, options=SimulationOptions(rtol=1e-12, atol=1e-14))


def floors(line: dict[str, Any], pin_us: float, integ: dict[str, Any]) -> dict[str, Any]:
    """The floors of a line (per simulated second) and its ratios to them: ``wall`` is
    simulate's wall time (output samples included), ``integration`` its solve_ivp part."""
    per_s = 1e-6 * line["rhs_evaluations"] / line["simulated_s"]
    i_us = integ["us_per_rhs"]
    both = pin_us + i_us
    out: dict[str, Any] = {
        "pinocchio_floor_per_simulated_s": pin_us * per_s,
        "integrator_floor_per_simulated_s": i_us * per_s,
        "pinocchio_plus_integrator_floor_per_simulated_s": both * per_s,
    }
    out["ratios"] = [
        ratio(f"simulate {what} per simulated second", name, line[key] / floor)
        for what, key in (("wall", "wall_us_per_rhs"), ("integration", "us_per_rhs"))
        for name, floor in (
            ("Pinocchio floor", pin_us),
            ("Pinocchio + integrator floor", both),
            ("integrator floor (DOP853 per evaluation)", i_us),
        )
    ]
    return out


def closed_case(duration: float | None, backend: str = "python") -> Case:
    """planar_3rrr, the ``circle`` tracking scenario."""
    mech = rcm_pin.load("planar_3rrr")
    sc = scenarios(mech)["circle"]
    if duration is not None:
        sc = dataclasses.replace(sc, duration=duration)
    info = {"mechanism": "planar_3rrr", "scenario": f"circle: {sc.description}",
            "simulated_s": sc.duration, "tolerances": [sc.rtol, sc.atol],
            "samples": sc.samples, "backend": backend}  # fmt: skip
    return info, lambda: run(mech, sc, backend=backend), mech


def per_call_us(timed: dict[str, Timed], name: str) -> float:
    """Median time of a callable divided by the count it returned [µs]."""
    return 1e6 * timed[name].wall / timed[name].result


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Run both lines and print the JSON document."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=2.0, help="serial: simulated time [s]")
    ap.add_argument("--closed-duration", type=float, default=None,
                    help="3-RRR: simulated time [s] (default: the scenario's)")  # fmt: skip
    ap.add_argument("--repeat", type=int, default=3, help="runs (median taken)")
    args = ap.parse_args(argv)
    s_info, s_run, s_mech = serial_case(args.duration)
    k_info, k_run, _ = serial_case(args.duration, "compiled")
    k_warm = k_run()  # builds (or loads) the compiled function
    c_info, c_run, c_mech = closed_case(args.closed_duration)
    kc_info, kc_run, _ = closed_case(args.closed_duration, "compiled")
    kc_warm = kc_run()  # builds (or loads) the compiled function
    s_warm, c_warm = s_run(), c_run()  # warm-up; states for the Pinocchio floors
    s_solve, s_alone = integrator(
        2 * s_warm.q.shape[1], args.duration, s_info["samples"], tuple(s_info["tolerances"])
    )
    c_solve, c_alone = integrator(
        2 * c_warm.q.shape[1], c_info["simulated_s"], c_info["samples"],
        tuple(c_info["tolerances"]),
    )  # fmt: skip
    timed = repeated(
        {"serial": s_run, "serial_compiled": k_run, "closed": c_run, "closed_compiled": kc_run,
         "serial_pin": serial_pin(s_mech, s_warm, 30),
         "closed_pin": closed_pin(c_mech, c_warm, 50),
         "serial_dop853": s_solve, "serial_rhs": s_alone,
         "closed_dop853": c_solve, "closed_rhs": c_alone},
        args.repeat,
    )  # fmt: skip
    lines = {}
    cases = (("serial", s_info), ("serial_compiled", k_info), ("closed", c_info),
             ("closed_compiled", kc_info))  # fmt: skip
    for name, info in cases:
        ln = {**info, **line(timed[name], info.get("simulated_s", args.duration))}
        base = name.split("_")[0]  # the compiled line has the serial line's floors
        ln["pinocchio_us_per_rhs"] = per_call_us(timed, f"{base}_pin")
        trivial = per_call_us(timed, f"{base}_rhs")
        ln["integrator"] = {
            "rhs_evaluations": timed[f"{base}_dop853"].result,
            "trivial_rhs_us": trivial,
            "us_per_rhs_with_trivial_rhs": per_call_us(timed, f"{base}_dop853"),
            "us_per_rhs": per_call_us(timed, f"{base}_dop853") - trivial,
        }
        ln.update(floors(ln, ln["pinocchio_us_per_rhs"], ln["integrator"]))
        if not name.endswith("_compiled"):  # (cProfile cannot see inside the compiled call)
            ln["profile"] = pinocchio_share(s_run if name == "serial" else c_run)
        lines[name] = ln
    serial, closed, compiled = lines["serial"], lines["closed"], lines["serial_compiled"]
    tight = _tight(args.duration)
    compiled["max_difference_to_python_backend"] = differences(
        timed["serial_compiled"].result, timed["serial"].result
    )
    compiled["max_difference_to_tight_run"] = differences(timed["serial_compiled"].result, tight)
    serial["max_difference_to_tight_run"] = differences(timed["serial"].result, tight)
    compiled["costs"] = compiled_costs(args.duration)
    compiled["warm_up_status"] = k_warm.status
    closed_compiled = lines["closed_compiled"]
    closed_compiled["max_difference_to_python_backend"] = differences(
        timed["closed_compiled"].result, timed["closed"].result
    )
    closed_compiled["warm_up_status"] = kc_warm.status
    doc = {
        "benchmark": "simulate (wall time per simulated second) against its floors",
        "repeat": args.repeat,
        "statistic": "median over interleaved repeats (simulations and floors alike)",
        "serial": serial,
        "serial_compiled": compiled,
        "closed": closed,
        "closed_compiled": closed_compiled,
        "ratios": [
            ratio("rcm_bevel computed torque, compiled backend, wall per simulated second",
                  "the same, python backend",
                  compiled["wall_per_simulated_s"] / serial["wall_per_simulated_s"]),
            ratio("planar_3rrr circle, compiled backend, wall per simulated second",
                  "the same, python backend",
                  closed_compiled["wall_per_simulated_s"] / closed["wall_per_simulated_s"]),
            ratio("planar_3rrr circle, wall per simulated second",
                  "rcm_bevel computed torque, wall per simulated second",
                  closed["wall_per_simulated_s"] / serial["wall_per_simulated_s"]),
            ratio("planar_3rrr circle, us per right-hand side",
                  "rcm_bevel computed torque, us per right-hand side",
                  closed["us_per_rhs"] / serial["us_per_rhs"]),
        ],
    }  # fmt: skip
    print(json.dumps(doc, indent=2))
    return doc


if __name__ == "__main__":
    main()
