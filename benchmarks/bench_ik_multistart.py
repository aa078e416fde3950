"""Numeric inverse kinematics of a redundant arm: poses found against the starts budget.

On example-robot-data baxter (17 coordinates; tool frame ``--frame``, default
``left_gripper``), ``--n`` poses come from forward kinematics of seeded random in-limit
configurations (with ``--at-limits F``, a fraction F of the coordinates of each drawn at
one of its limits instead: harder poses, where the budget matters); each is solved by
:func:`rcm_pin.inverse` with every ``--starts`` budget.
Prints a JSON document: per budget the poses found, the ones reported
``SolutionNotFoundError`` / ``UnreachablePoseError`` (the latter would be a lie: every
pose is reachable) and the median time per pose [s]; and, for a pose ``--far`` m from the
base, which error it gets (the reach bound proves it outside the workspace).

    python benchmarks/bench_ik_multistart.py                     # 100 poses, about 2 min
    python benchmarks/bench_ik_multistart.py --n 20 --starts 1 4 16   # quick
    python benchmarks/bench_ik_multistart.py --n 20 --starts 4 16 --at-limits 0.4 --seed 5
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

import rcm_pin
from rcm_pin.analysis.reach import reach_bound
from rcm_pin.errors import SolutionNotFoundError, UnreachablePoseError
from rcm_pin.mechanisms.arms import robots_dir


def run(
    n: int, budgets: list[int], frame: str, far: float, seed: int, at_limits: float = 0.0
) -> dict[str, object]:
    """The JSON document (module docstring)."""
    mech = rcm_pin.load(robots_dir() / "baxter_description/urdf/baxter.urdf", tool_frame=frame)
    rng = np.random.default_rng(seed)
    poses = []
    for _ in range(n):
        q = rng.uniform(mech.lower, mech.upper)
        mask = rng.random(mech.nq) < at_limits
        q[mask] = np.where(rng.random(mask.sum()) < 0.5, mech.lower[mask], mech.upper[mask])
        poses.append(rcm_pin.forward(mech, q).solutions[0].output)
    out: dict[str, object] = {"mechanism": mech.name, "nq": mech.nq, "frame": frame, "n": n}
    out.update(seed=seed, at_limits=at_limits)
    rows = []
    for starts in budgets:
        found = not_found = unreachable = 0
        times = []
        for pose in poses:
            t0 = time.perf_counter()
            try:
                rcm_pin.inverse(mech, pose, starts=starts)
                found += 1
            except SolutionNotFoundError:
                not_found += 1
            except UnreachablePoseError:
                unreachable += 1
            times.append(time.perf_counter() - t0)
        rows.append(
            {"starts": starts, "found": found, "not_found": not_found,
             "unreachable": unreachable, "time_median": float(np.median(times))}
        )  # fmt: skip
    out["budgets"] = rows
    try:
        rcm_pin.inverse(mech, [far, 0.0, 0.5], ("x", "y", "z"), starts=2)
        verdict = "found"
    except (SolutionNotFoundError, UnreachablePoseError) as exc:
        verdict = type(exc).__name__
    out["far"] = {"distance": far, "reach_bound": reach_bound(mech, frame), "error": verdict}
    return out


def main() -> None:
    """Parse the options and print the document."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100, help="poses (100)")
    parser.add_argument("--starts", type=int, nargs="+", default=[1, 2, 4, 8, 16])
    parser.add_argument("--frame", default="left_gripper", help="tool frame (left_gripper)")
    parser.add_argument("--far", type=float, default=3.0, help="distance of the far pose [m]")
    parser.add_argument("--seed", type=int, default=0, help="seed of the poses (0)")
    parser.add_argument("--at-limits", type=float, default=0.0, help="fraction at a limit (0)")
    args = parser.parse_args()
    doc = run(args.n, args.starts, args.frame, args.far, args.seed, args.at_limits)
    print(json.dumps(doc, indent=2))


if __name__ == "__main__":
    main()
