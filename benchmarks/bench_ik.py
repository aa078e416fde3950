"""Inverse kinematics of rcm_bevel: vectorised analytic IK vs per-pose calls, in one run.

Prints a JSON document with per-pose times [ns] (medians over ``--repeat`` runs) of

* ``rcm_pin.mechanisms.rcm.analytic_ik.ik_pose`` on all ``--n`` poses at once (all 8
  branches; includes allocating the (n, 8, 6) result, 384 bytes per pose, and, unless
  ``--no-check``, the SO(3) screen);
* the same function called once per pose in a Python loop (``--n-loop`` poses): the
  scalar fast path of :mod:`rcm_pin.mechanisms.rcm.ik_scalar`, and the same poses as
  batches of one (the vectorised code);
* the generic ``rcm_pin.inverse(mech, T)`` once per pose (``--n-loop`` poses): it wraps the
  analytic IK, fits the branches into the joint limits and checks every branch by forward
  kinematics (the ``serial_branches`` kernel, compiled up front);

and the ratios loop / vectorised, inverse / loop and inverse / vectorised. Poses come from
the closed-form forward kinematics (q1, q2, q4, q5, q6 uniform in (−π, π], q3 uniform in
[0.05, 0.12] m). With ``--families N``, also ``rcm_pin.inverse`` and ``rcm_pin.forward``
of every catalogue mechanism divided by their floors (the analytic IK or the family's
candidates; one forward kinematics or the closure kernel's solve) on N targets each
(:mod:`position_floors`).

    python benchmarks/bench_ik.py [--n 1000000] [--n-loop 2000] [--wrist zyz] [--repeat 5]
    python benchmarks/bench_ik.py --n 20000 --n-loop 200 --repeat 3    # quick
    python benchmarks/bench_ik.py --n 2000 --n-loop 200 --families 50  # + every family
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable

import numpy as np
from position_floors import compile_now

import rcm_pin
from rcm_pin.mechanisms.rcm.analytic_ik import ik_pose
from rcm_pin.mechanisms.rcm.closed_form import tool_pose
from rcm_pin.model import serial_branches


def median_times(cases: dict[str, Callable[[], object]], repeat: int) -> dict[str, float]:
    """Median wall time [s] of ``repeat`` back-to-back calls of each case (after a warm-up).

    The repeats of a case run back to back, not interleaved with the other cases: a large
    batched call made after a pause of a second or more pays its page faults again (up to
    4x slower on a shared virtual machine), which is not what this measures.
    """
    times: dict[str, list[float]] = {}
    for name, fn in cases.items():
        fn()
        times[name] = []
        for _ in range(repeat):
            start = time.perf_counter()
            fn()
            times[name].append(time.perf_counter() - start)
    return {name: float(np.median(t)) for name, t in times.items()}


def ratio(measured: str, baseline: str, times: dict[str, float]) -> dict[str, object]:
    """A ratio with both sides named (same run, same poses)."""
    return {"measured": measured, "baseline": baseline,
            "ratio": times[measured] / times[baseline]}  # fmt: skip


def main(argv: list[str] | None = None) -> dict[str, object]:
    """Run the benchmark and print the JSON document."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1_000_000, help="poses for the vectorised IK")
    ap.add_argument("--n-loop", type=int, default=2000, help="poses for the per-pose calls")
    ap.add_argument("--wrist", choices=["zyz", "rpy"], default="zyz")
    ap.add_argument("--repeat", type=int, default=5, help="runs (median taken)")
    ap.add_argument("--no-check", action="store_true", help="skip the SO(3) screen")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--families", type=int, default=0, metavar="N",
                    help="also every catalogue mechanism on N targets (0: skip)")  # fmt: skip
    args = ap.parse_args(argv)

    rng = np.random.default_rng(args.seed)
    q = rng.uniform(-np.pi, np.pi, (args.n, 6))
    q[:, 2] = rng.uniform(0.05, 0.12, args.n)  # [m]
    poses = tool_pose(q, args.wrist)
    check = not args.no_check
    m = min(args.n_loop, args.n)
    mech = rcm_pin.load("rcm_bevel", wrist_type=args.wrist)
    compile_now(serial_branches.warm(mech))  # the steady state: the branch kernel compiled

    def vectorised() -> None:
        ik_pose(poses, args.wrist, check_rotation=check)

    def loop() -> None:
        for i in range(m):
            ik_pose(poses[i], args.wrist, check_rotation=check)

    def loop_batch() -> None:  # a batch of one pose skips the scalar fast path
        for i in range(m):
            ik_pose(poses[i : i + 1], args.wrist, check_rotation=check)

    def inverse() -> None:
        for i in range(m):
            rcm_pin.inverse(mech, poses[i])

    vec = "analytic_ik.ik_pose, vectorised"
    one = "analytic_ik.ik_pose, one pose per call (scalar fast path, rcm.ik_scalar)"
    batch1 = "analytic_ik.ik_pose, one pose per call as a batch of one (vectorised code)"
    inv = "rcm_pin.inverse(mech, T), one pose per call"
    cases = {vec: vectorised, one: loop, batch1: loop_batch, inv: inverse}
    runs = median_times(cases, args.repeat)
    times = {vec: runs[vec] / args.n, one: runs[one] / m, batch1: runs[batch1] / m}
    times[inv] = runs[inv] / m

    k = min(1000, args.n)
    err = np.abs(
        tool_pose(ik_pose(poses[:k], args.wrist).q.reshape(-1, 6), args.wrist)
        - np.repeat(poses[:k], 8, axis=0)
    ).max()
    counts = [rcm_pin.inverse(mech, poses[i]).count for i in range(min(100, m))]
    doc: dict[str, object] = {
        "benchmark": "inverse kinematics (rcm_bevel, all 8 branches)",
        "wrist": args.wrist,
        "check_rotation": check,
        "poses": {vec: args.n, one: m, batch1: m, inv: m},
        "repeat": args.repeat,
        "statistic": "median over back-to-back repeats of the time per pose",
        "per_pose_ns": {key: 1e9 * t for key, t in times.items()},
        "poses_per_s": {key: 1.0 / t for key, t in times.items()},
        "ratios": [
            ratio(one, vec, times),
            ratio(batch1, one, times),
            ratio(inv, one, times),
            ratio(inv, vec, times),
        ],
        "checks": {
            f"FK(IK) max error on {k} poses (all branches)": float(err),
            f"rcm_pin.inverse branch counts on {len(counts)} poses": sorted(set(counts)),
        },
    }
    if args.families:
        from position_floors import bench_families

        doc["families"] = bench_families(args.families, args.repeat, args.seed)
    print(json.dumps(doc, indent=2))
    return doc


if __name__ == "__main__":
    main()
