"""Workspace maps: a reachability test against the full inverse problem (run on demand).

Prints a JSON document: for the planar 3-RRR (catalogue defaults) on an ``--n`` × ``--n``
grid at ``--orientations`` values of φ in [−30°, 30°], the median time [ms] over
``--repeat`` runs of

* ``closed_form.reachable`` (|l1 − l2| ≤ |A_i C_i| ≤ l1 + l2 per leg, no angle): what the
  constant-orientation and total-orientation maps call, and
* ``closed_form.inverse_position`` (all 8 working modes per cell; its mask is the same),

the ratio, and whether the two masks agree cell for cell (they must: the same 1e-12 band on
the cosine).

    python benchmarks/bench_workspace.py [--n 241] [--orientations 61] [--repeat 5]
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable

import numpy as np

import rcm_pin
from rcm_pin.mechanisms.planar_3rrr import closed_form as p3
from rcm_pin.mechanisms.planar_3rrr import geometry
from rcm_pin.mechanisms.planar_3rrr.workspace import Grid


def median_ms(fn: Callable[[], object], repeat: int) -> float:
    """Median wall time [ms] of ``repeat`` calls after a warm-up."""
    fn()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return 1e3 * float(np.median(times))


def main(argv: list[str] | None = None) -> dict[str, object]:
    """Run the benchmark and print the JSON document."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=241, help="grid points per axis")
    ap.add_argument("--orientations", type=int, default=61, help="phi samples")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    g = geometry(rcm_pin.load("planar_3rrr"))
    grid = Grid.around(g, args.n)
    phis = np.radians(np.linspace(-30.0, 30.0, args.orientations))
    poses = [grid.poses(float(phi)) for phi in phis]

    def reach() -> list[np.ndarray]:
        return [p3.reachable(g, p) for p in poses]

    def full() -> list[np.ndarray]:
        return [p3.inverse_position(g, p)[1] for p in poses]

    agree = all(np.array_equal(a, b) for a, b in zip(reach(), full()))
    t_reach, t_full = median_ms(reach, args.repeat), median_ms(full, args.repeat)
    cells = args.n * args.n * args.orientations
    doc: dict[str, object] = {
        "benchmark": "planar_3rrr workspace maps: reachability test vs full inverse",
        "grid": [args.n, args.n],
        "orientations": args.orientations,
        "cells": cells,
        "repeat": args.repeat,
        "statistic": "median wall time over repeats",
        "ms": {"closed_form.reachable": t_reach, "closed_form.inverse_position": t_full},
        "ns_per_cell": {
            "closed_form.reachable": 1e6 * t_reach / cells,
            "closed_form.inverse_position": 1e6 * t_full / cells,
        },
        "ratio": {
            "measured": "closed_form.reachable",
            "baseline": "closed_form.inverse_position (the full 8-mode inverse per cell)",
            "speed_up": t_full / t_reach,
        },
        "masks_identical": agree,
    }
    print(json.dumps(doc, indent=2))
    return doc


if __name__ == "__main__":
    main()
