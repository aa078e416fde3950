"""Closed-loop direct position solvers (run on demand, never in the test suite).

Prints a JSON document (per-call times [µs] are medians over every timed call of
``--repeat`` passes):

1. ``sweep``: planar_3rrr, drives of working mode +++ along a closed Lissajous sweep of the
   platform (|φ| ≤ 0.3); each pose solved from the previous pose's solution by

   * ``rcm_pin.analysis.closed_position.solve_drives`` (Newton on Pinocchio's closure
     residual; the baseline), and
   * ``rcm_pin.forward(mech, drives, q_guess=...)`` (the same Newton behind the public
     API: validation, output value, limits flag);

2. ``batched``: the vectorised planar Newton (``rcm_pin.analysis.batch_planar``) on
   ``--n-batch`` poses at once, each warm-started from its neighbour on the sweep (time
   per pose, median of batched runs), against the per-pose ``solve_drives``;
3. ``all_modes``: ``rcm_pin.forward(mech, drives, all_modes=True)`` (the family's
   closed-form seeds, a Newton polish of each, deduplication) for planar_3rrr, five_bar and
   four_bar at drive values near the home configuration, against one warm ``solve_drives``
   from home and against the family's closed-form seeds alone.

    python benchmarks/bench_closed_loop.py                # about 15 s
    python benchmarks/bench_closed_loop.py --n-sweep 200 --n-batch 2000 --n-drives 10 \\
        --repeat 2                                        # quick
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

import rcm_pin
from rcm_pin.analysis.batch_planar import PlanarTree, batch_solve_passive
from rcm_pin.analysis.closed_position import solve_drives
from rcm_pin.mechanisms.planar_3rrr import closed_form as p3
from rcm_pin.mechanisms.planar_3rrr import geometry

#: Mechanisms of the ``all_modes`` part.
ALL_MODES = ("planar_3rrr", "five_bar", "four_bar")


def sweep(g: p3.Geometry3RRR, n: int) -> tuple[np.ndarray, np.ndarray]:
    """A closed curve of poses (Lissajous, |φ| ≤ 0.3) and its drives in working mode +++."""
    s = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    poses = np.column_stack([0.06 * np.sin(s), 0.05 * np.sin(2 * s), 0.3 * np.sin(3 * s)])
    qs, ok = p3.inverse_position(g, poses)
    assert ok.all()
    return poses, qs[:, 0]


def timed(cases: dict[str, Callable[[Any], Any]], args: Sequence[Any],
          repeat: int) -> tuple[dict[str, float], dict[str, list]]:  # fmt: skip
    """Median time per call [µs] of each case over ``repeat`` passes over ``args``, and
    each case's results of the last pass.

    The passes are interleaved (one pass of each case per round), so a slow drift of the
    machine load hits every case alike and the ratios stay fair.
    """
    for fn in cases.values():  # warm-up
        fn(args[0])
    times: dict[str, list[float]] = {name: [] for name in cases}
    out: dict[str, list] = {}
    for _ in range(repeat):
        for name, fn in cases.items():
            out[name] = []
            for a in args:
                start = time.perf_counter()
                out[name].append(fn(a))
                times[name].append(time.perf_counter() - start)
    return {name: 1e6 * float(np.median(t)) for name, t in times.items()}, out


def ratio(measured: str, baseline: str, times: dict[str, float]) -> dict[str, object]:
    """A ratio with both sides named (same run)."""
    return {"measured": measured, "baseline": baseline,
            "ratio": times[measured] / times[baseline]}  # fmt: skip


def bench_sweep(mech: rcm_pin.Mechanism, n: int, repeat: int) -> dict[str, object]:
    """Per-pose warm-started direct solves along the sweep (part 1)."""
    g = geometry(mech)
    poses, qd = sweep(g, n)
    q_true = p3.full_q(g, poses, qd)
    # each pose k starts from the solution of pose k − 1 (the exact one: repeatable passes)
    cases = [(qd[k], q_true[k - 1]) for k in range(1, n)]
    base, direct = "solve_drives (warm start)", "rcm_pin.forward(q_guess=...)"
    times, out = timed({base: lambda c: solve_drives(mech, c[0], c[1]),
                        direct: lambda c: rcm_pin.forward(mech, c[0], q_guess=c[1])},
                       cases, repeat)  # fmt: skip
    res, sols = out[base], out[direct]
    values = np.array([s.solutions[0].output for s in sols])
    return {
        "mechanism": mech.name,
        "poses": n - 1,
        "per_call_us": times,
        "ratios": [ratio(direct, base, times)],
        "mean_iterations": float(np.mean([r[1] for r in res])),
        "worst_residual_m": float(max(r[2] for r in res)),
        "max_output_error": float(np.max(np.abs(values - poses[1:]))),
        "target": "< 100 us per pose",
    }


def bench_batched(mech: rcm_pin.Mechanism, n: int, repeat: int, per_pose_us: float) -> dict:
    """The vectorised planar Newton on n poses at once (part 2)."""
    g = geometry(mech)
    tree = PlanarTree.from_mechanism(mech)
    poses, qd = sweep(g, n)
    guess = np.roll(p3.full_q(g, poses, qd), 1, axis=0)  # start from the neighbour's solution
    batch_solve_passive(mech, tree, qd, guess)  # warm-up (first touch of the big arrays)
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        q, norms = batch_solve_passive(mech, tree, qd, guess)
        times.append(time.perf_counter() - start)
    batched, base = "batch_solve_passive (per pose)", "solve_drives (warm start, per pose)"
    per = {batched: 1e6 * float(np.median(times)) / n, base: per_pose_us}
    return {
        "mechanism": mech.name,
        "poses": n,
        "per_pose_us": per,
        "total_ms": 1e3 * float(np.median(times)),
        "ratios": [ratio(base, batched, per)],
        "max_residual_m": float(np.max(norms)),
        "max_output_error": float(np.max(np.abs(tree.output(q) - poses))),
        "target": "< 2 us per pose",
    }


def bench_all_modes(name: str, n: int, repeat: int, seed: int) -> dict[str, object]:
    """``forward(all_modes=True)`` near the home configuration (part 3)."""
    mech = rcm_pin.load(name)
    loops = mech.loops
    assert loops is not None
    home = mech.family.configurations(mech)["home"]
    rng = np.random.default_rng(seed)
    drives = home[loops.drive_q] + rng.uniform(-0.05, 0.05, (n, loops.dof))
    full = "rcm_pin.forward(all_modes=True)"
    warm = "solve_drives (warm start from home)"
    seeds = "family.direct_position (closed-form seeds only)"
    times, out = timed({full: lambda d: rcm_pin.forward(mech, d, all_modes=True),
                        warm: lambda d: solve_drives(mech, d, home),
                        seeds: lambda d: mech.family.direct_position(mech, d)},
                       list(drives), repeat)  # fmt: skip
    results = out[full]
    counts = sorted({r.count for r in results})
    return {
        "mechanism": name,
        "drive_sets": n,
        "method": results[0].method,
        "assembly_modes": counts,
        "per_call_us": times,
        "ratios": [ratio(full, warm, times), ratio(full, seeds, times)],
        "worst_residual_m": float(max(s.residual for r in results for s in r.solutions)),
    }


def main(argv: list[str] | None = None) -> dict[str, object]:
    """Run the three parts and print the JSON document."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n-sweep", type=int, default=2000, help="poses of the per-pose sweep")
    ap.add_argument("--n-batch", type=int, default=100_000, help="poses of the batched solve")
    ap.add_argument("--n-drives", type=int, default=200, help="drive sets per mechanism "
                    "(all_modes)")  # fmt: skip
    ap.add_argument("--repeat", type=int, default=3, help="passes (median taken)")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)

    mech = rcm_pin.load("planar_3rrr")
    part1 = bench_sweep(mech, args.n_sweep, args.repeat)
    per_pose = part1["per_call_us"]["solve_drives (warm start)"]  # type: ignore[index]
    doc: dict[str, object] = {
        "benchmark": "closed-loop direct position",
        "repeat": args.repeat,
        "statistic": "median over every timed call of interleaved passes "
        "(batched: median run / poses)",
        "sweep": part1,
        "batched": bench_batched(mech, args.n_batch, args.repeat, per_pose),
        "all_modes": [
            bench_all_modes(nm, args.n_drives, args.repeat, args.seed) for nm in ALL_MODES
        ],
    }
    print(json.dumps(doc, indent=2))
    return doc


if __name__ == "__main__":
    main()
