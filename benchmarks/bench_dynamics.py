"""Wall time per simulated second of ``rcm_pin.control.simulate.simulate`` (run on demand).

Prints a JSON document with two lines, each the median over ``--repeat`` runs:

* ``serial``: the six-DOF ``rcm_bevel`` (``q3_upper=0.3``) under ``ComputedTorque`` on
  paper 000's trajectory (Kn = 720, Kc = 12, URDF drive limits; DOP853, rtol 1e-10,
  atol 1e-12): wall time per simulated second, time per right-hand side against the bare
  Pinocchio calls one right-hand side needs (crba + nonLinearEffects for the plant, rnea
  for the controller, timed alone in the same run);
* ``closed``: the 3-RRR tracking scenario (``scenarios(load("planar_3rrr"))["circle"]``,
  paper 004's law, run by ``rcm_pin.control.scenario.run``; constrained KKT dynamics):
  wall time per simulated second, and its ratio to the serial line.

For both, one extra run under cProfile gives the share of time spent inside Pinocchio
calls (wrapped in Python functions named ``pin_*``, since Boost.Python functions are
invisible to cProfile) versus numpy / scipy / Python overhead.

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
from typing import Any

import numpy as np
import pinocchio as pin

import rcm_pin
from rcm_pin.control.computed_torque import ComputedTorque, Gains, drive_limits
from rcm_pin.control.references import TRAJECTORIES
from rcm_pin.control.result import SimulationResult
from rcm_pin.control.scenario import run, scenarios
from rcm_pin.control.simulate import simulate

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


def repeated(runs: dict[str, Callable[[], SimulationResult]],
             repeat: int) -> dict[str, tuple[float, SimulationResult]]:  # fmt: skip
    """Median total wall time [s] of each run over ``repeat`` rounds, and its last result.

    The runs are interleaved (one of each per round), so a slow drift of the machine load
    hits both lines alike and their ratio stays fair.
    """
    times: dict[str, list[float]] = {name: [] for name in runs}
    results: dict[str, SimulationResult] = {}
    for _ in range(repeat):
        for name, fn in runs.items():
            start = time.perf_counter()
            results[name] = fn()
            times[name].append(time.perf_counter() - start)
    return {name: (float(np.median(times[name])), results[name]) for name in runs}


def bare_rhs_us(mech: rcm_pin.Mechanism, repeat: int, n: int = 2000) -> float:
    """crba + nonLinearEffects + rnea at the home configuration [µs] (median of repeats)."""
    model, data = mech.model, mech.model.createData()
    q = mech.to_pin(mech.family.configurations(mech)["home"])
    v, a = np.ones(model.nv), np.ones(model.nv)
    times = []
    for _ in range(max(repeat, 3)):
        start = time.perf_counter()
        for _ in range(n):
            pin.crba(model, data, q, pin.Convention.WORLD)
            pin.nonLinearEffects(model, data, q, v)
            pin.rnea(model, data, q, v, a)
        times.append((time.perf_counter() - start) / n)
    return 1e6 * float(np.median(times))


def ratio(measured: str, baseline: str, value: float) -> dict[str, object]:
    """A ratio with both sides named (same run)."""
    return {"measured": measured, "baseline": baseline, "ratio": value}


def line(wall: float, duration: float, r: SimulationResult) -> dict[str, Any]:
    """The figures of one simulated run."""
    return {
        "simulated_s": duration,
        "status": r.status,
        "wall_s": wall,
        "integration_s": r.wall_time,
        "wall_per_simulated_s": wall / duration,
        "rhs_evaluations": r.nfev,
        "us_per_rhs": 1e6 * r.wall_time / r.nfev,
    }


def serial_case(duration: float) -> tuple[dict[str, Any], Callable[[], SimulationResult]]:
    """rcm_bevel (6 DOF) under computed torque on paper 000's trajectory (warmed up)."""
    mech = rcm_pin.load("rcm_bevel", q3_upper=0.3)
    ctrl = ComputedTorque(
        mech, TRAJECTORIES["paper000"], Gains(720.0, 12.0), limits=drive_limits(mech)
    )
    simulate(mech, ctrl, 0.05)  # warm-up
    info = {"mechanism": "rcm_bevel (6 DOF, q3_upper=0.3)",
            "controller": "ComputedTorque, paper000, Kn=720, Kc=12, drive limits",
            "bare_pinocchio_us_per_rhs": bare_rhs_us(mech, 5)}  # fmt: skip
    return info, lambda: simulate(mech, ctrl, duration)


def closed_case(duration: float | None) -> tuple[dict[str, Any], Callable[[], SimulationResult]]:
    """planar_3rrr, the ``circle`` tracking scenario (warmed up)."""
    mech = rcm_pin.load("planar_3rrr")
    sc = scenarios(mech)["circle"]
    if duration is not None:
        sc = dataclasses.replace(sc, duration=duration)
    run(mech, dataclasses.replace(sc, duration=0.02))  # warm-up
    info = {"mechanism": "planar_3rrr", "scenario": f"circle: {sc.description}",
            "simulated_s": sc.duration}  # fmt: skip
    return info, lambda: run(mech, sc)


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Run both lines and print the JSON document."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=2.0, help="serial: simulated time [s]")
    ap.add_argument("--closed-duration", type=float, default=None,
                    help="3-RRR: simulated time [s] (default: the scenario's)")  # fmt: skip
    ap.add_argument("--repeat", type=int, default=3, help="runs (median taken)")
    args = ap.parse_args(argv)
    s_info, s_run = serial_case(args.duration)
    c_info, c_run = closed_case(args.closed_duration)
    timed = repeated({"serial": s_run, "closed": c_run}, args.repeat)
    serial = {**s_info, **line(timed["serial"][0], args.duration, timed["serial"][1])}
    bare = serial["bare_pinocchio_us_per_rhs"]
    serial["ratios"] = [ratio("us per right-hand side (simulate)",
                              "crba + nonLinearEffects + rnea alone",
                              serial["us_per_rhs"] / bare)]  # fmt: skip
    closed = {**c_info, **line(timed["closed"][0], c_info["simulated_s"], timed["closed"][1])}
    serial["profile"] = pinocchio_share(s_run)
    closed["profile"] = pinocchio_share(c_run)
    doc = {
        "benchmark": "simulate (wall time per simulated second)",
        "repeat": args.repeat,
        "statistic": "median over interleaved repeats of the total wall time of simulate / run",
        "serial": serial,
        "closed": closed,
        "ratios": [
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
