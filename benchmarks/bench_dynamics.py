"""Wall time per simulated second of the six-DOF ``rcm_bevel`` under computed torque.

Run: ``/work/venv/bin/python benchmarks/bench_dynamics.py [--duration 2]``. Reports the
wall time per simulated second (paper 000 trajectory, Kn = 720, Kc = 12, DOP853,
rtol 1e-10, atol 1e-12) and, with cProfile, the share of time spent inside Pinocchio
calls (crba, nonLinearEffects, rnea) versus numpy / scipy / Python overhead.
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
import time

import pinocchio as pin

import rcm_pin
from rcm_pin.control import ComputedTorque, Gains, drive_limits
from rcm_pin.simulation import simulate
from rcm_pin.trajectories import TRAJECTORIES


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--duration", type=float, default=2.0, help="simulated time [s]")
    args = parser.parse_args()
    mech = rcm_pin.load("rcm_bevel", q3_upper=0.3)
    ctrl = ComputedTorque(
        mech, TRAJECTORIES["paper000"], Gains(720.0, 12.0), limits=drive_limits(mech)
    )
    simulate(mech, ctrl, 0.05)  # warm-up
    start = time.perf_counter()
    r = simulate(mech, ctrl, args.duration)
    wall = time.perf_counter() - start
    print(
        f"rcm_bevel (6 DOF), {args.duration:g} s simulated: total {wall:.3f} s "
        f"(integration {r.wall_time:.3f} s, {r.nfev} RHS evaluations, "
        f"{1e6 * r.wall_time / r.nfev:.1f} us per evaluation)"
    )
    print(f"wall time per simulated second: {wall / args.duration:.3f} s")
    # Boost.Python functions are invisible to cProfile: wrap them in Python functions
    # (named pin_*) whose cumulative time is the time spent inside Pinocchio.
    wrapped = {}
    for name in PIN_CALLS:
        original = getattr(pin, name)
        wrapper = _wrap(original, name)
        wrapped[name] = original
        setattr(pin, name, wrapper)
    prof = cProfile.Profile()
    try:
        prof.enable()
        simulate(mech, ctrl, args.duration)
        prof.disable()
    finally:
        for name, original in wrapped.items():
            setattr(pin, name, original)
    stats = pstats.Stats(prof)
    total = stats.total_tt  # type: ignore[attr-defined]
    pin_time, calls = 0.0, 0
    for (_, _, func), (_, nc, _, ct, _) in stats.stats.items():  # type: ignore[attr-defined]
        if func.startswith("pin_"):
            pin_time += ct
            calls += nc
    print(
        f"profiled total {total:.3f} s; Pinocchio calls ({calls}) {pin_time:.3f} s "
        f"({100 * pin_time / total:.1f} %); Python/numpy/scipy overhead "
        f"{100 * (1 - pin_time / total):.1f} %"
    )
    stats.sort_stats("tottime").print_stats(10)


PIN_CALLS = ("crba", "nonLinearEffects", "rnea")


def _wrap(fn, name):
    def wrapper(*a, **k):
        return fn(*a, **k)

    wrapper.__name__ = wrapper.__qualname__ = f"pin_{name}"
    wrapper.__code__ = wrapper.__code__.replace(co_name=f"pin_{name}", co_qualname=f"pin_{name}")
    return wrapper


if __name__ == "__main__":
    main()
