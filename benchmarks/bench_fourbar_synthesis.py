"""Four-bar synthesis from the two extreme rocker positions on random targets, every valid
root checked on the Pinocchio closed loop (issue 15's acceptance run).

Draws (φ, γ, l2, l3) uniformly: φ, γ in [−60°, 80°] with φ + γ ≥ 1°, l2, l3 in
[0.01, 0.2] m (seeded). For each target it counts the real roots of the two dead-centre
equations and the valid crank–rocker roots, checks every root's residuals and, for every
valid root, drives the catalogue's planar four-bar with those lengths through a full crank
turn on Pinocchio and compares the swing reached with the target. Prints one JSON document.

    python benchmarks/bench_fourbar_synthesis.py [--n 1000] [--seed 0] [--samples 121]
"""

from __future__ import annotations

import argparse
import json
import math
import time
from collections import Counter

import numpy as np

import rcm_pin
from rcm_pin.errors import UnreachablePoseError
from rcm_pin.linkage.synthesis import LAYOUTS, synthesize
from rcm_pin.studies.four_bar_turn import crank_turn


def main() -> None:
    """Run the draws and print the counts and the largest errors."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--samples", type=int, default=121)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    counts: Counter[str] = Counter()
    worst: dict[str, float] = {
        "residual_rel": 0.0,
        "swing_rad": 0.0,
        "time_ratio_rel": 0.0,
        "closure_m": 0.0,
    }
    start = time.perf_counter()
    while counts["targets"] < args.n:
        up, down = np.radians(rng.uniform(-60.0, 80.0, 2))
        if up + down < math.radians(1.0):
            continue
        l2, l3 = rng.uniform(0.01, 0.2, 2)
        counts["targets"] += 1
        try:
            roots = synthesize(up, down, l2, l3)
        except UnreachablePoseError:
            counts["no_real_root"] += 1
            continue
        counts["real_roots"] += len(roots)
        valid = [r for r in roots if r.valid]
        counts[f"targets_with_{len(valid)}_valid"] += 1
        for r in roots:
            scale = max(l2, l3, r.frame) ** 2
            worst["residual_rel"] = max(
                worst["residual_rel"], abs(r.residual_up) / scale, abs(r.residual_down) / scale
            )
        for r in valid:
            counts["valid_roots"] += 1
            counts[r.layout] += 1
            p = r.performance
            assert p is not None and p.time_ratio is not None
            g = p.linkage
            m = rcm_pin.load("four_bar", frame=g.l0, crank=g.l1, coupler=g.l2, rocker=g.l3)
            t = crank_turn(m, m.home, args.samples)
            towards, away = t.psi_max - math.pi / 2, math.pi / 2 - t.psi_min
            swing = (towards, away) if r.layout == LAYOUTS[0] else (away, towards)
            err = max(abs(swing[0] - up), abs(swing[1] - down))
            worst["swing_rad"] = max(worst["swing_rad"], float(err))
            worst["time_ratio_rel"] = max(
                worst["time_ratio_rel"], abs(t.time_ratio - p.time_ratio) / p.time_ratio
            )
            worst["closure_m"] = max(worst["closure_m"], t.max_closure_residual)
            counts["simulated_within_1e-9"] += int(err <= 1e-9)
    print(
        json.dumps(
            {
                "seed": args.seed,
                "counts": dict(counts),
                "worst": worst,
                "wall_time_s": time.perf_counter() - start,
            },
            indent=2,
        )
    )


if __name__ == "__main__":
    main()
