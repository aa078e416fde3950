"""Benchmarks of the closed-loop direct position solvers (run on demand, not in tests).

    /work/venv/bin/python benchmarks/bench_closed_loop.py

1. Per pose: Newton on Pinocchio's closure residual (``ClosedMechanism.solve_passive``)
   warm-started from the solution of the previous pose of a sweep; median time per pose.
2. Batched: vectorised planar Newton (``batch_solve_passive``) for 10^5 poses, each
   warm-started from its neighbour on a sweep; time per pose.
"""

from __future__ import annotations

import time

import numpy as np

from rcm_pin.closed_loop import load_closed
from rcm_pin.closed_loop import planar_3rrr as p3
from rcm_pin.closed_loop.batch import PlanarTree, batch_solve_passive


def sweep(g: p3.Geometry3RRR, n: int) -> tuple[np.ndarray, np.ndarray]:
    """A closed curve of poses (Lissajous, |φ| ≤ 0.3) and its drives in working mode +++."""
    s = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    poses = np.column_stack([0.06 * np.sin(s), 0.05 * np.sin(2 * s), 0.3 * np.sin(3 * s)])
    qs, ok = p3.inverse_position(g, poses)
    assert ok.all()
    return poses, qs[:, 0]


def main() -> None:
    m = load_closed("planar_3rrr")
    g = p3.Geometry3RRR.from_params(m.params)
    poses, qd = sweep(g, 2000)
    q_true = p3.full_q(g, poses, qd)
    times, iters, worst = [], [], 0.0
    q = q_true[0]
    for k in range(1, len(poses)):
        t0 = time.perf_counter()
        q, it, res = m.solve_passive(qd[k], q)
        times.append(time.perf_counter() - t0)
        iters.append(it)
        worst = max(worst, res)
    med = float(np.median(times)) * 1e6
    print(
        f"per-pose Newton (Pinocchio closures, warm start): median {med:.1f} µs, "
        f"mean iterations {np.mean(iters):.2f}, worst residual {worst:.1e} m "
        f"(target < 100 µs)"
    )

    tree = PlanarTree.from_mechanism(m)
    n = 100_000
    poses, qd = sweep(g, n)
    q_true = p3.full_q(g, poses, qd)
    guess = np.roll(q_true, 1, axis=0)  # each pose starts from its neighbour's solution
    batch_solve_passive(m, tree, qd[:100], guess[:100])  # warm-up
    best = np.inf
    for _ in range(3):
        t0 = time.perf_counter()
        q, norms = batch_solve_passive(m, tree, qd, guess)
        best = min(best, time.perf_counter() - t0)
    err = float(np.max(np.abs(tree.output(q) - poses)))
    print(
        f"batched vectorised Newton, {n} poses: {best / n * 1e6:.2f} µs/pose "
        f"(total {best * 1e3:.0f} ms), max residual {np.max(norms):.1e} m, "
        f"max pose error {err:.1e} (target < 2 µs/pose)"
    )


if __name__ == "__main__":
    main()
