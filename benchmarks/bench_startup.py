"""Start-up time: ``import rcm_pin`` and ``rcm-pin fk`` against ``import pinocchio`` (on demand).

Prints a JSON document with the wall times [s] of fresh subprocesses, run interleaved (one
of each per round, so a busy machine slows all three alike; one warm-up round first, which
also fills the xacro render cache):

1. ``python -c "import pinocchio"``: the floor (Python, numpy and Pinocchio);
2. ``python -c "import rcm_pin"``: goal ≤ 1.5x the floor;
3. ``rcm-pin fk rcm_bevel --q=0.1,0.2,0.08,0,0.3,0`` (the console script beside
   ``sys.executable``, else ``python -m rcm_pin``): goal ≤ 2x the floor;

with the median, min and max of each, and the ratios of the medians to the floor against
the goals.

    python benchmarks/bench_startup.py [--repeats 11] [--module]
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

#: The fk call of the benchmark (rcm_bevel's six coordinates q1..q6 [rad, m]).
FK = ["fk", "rcm_bevel", "--q=0.1,0.2,0.08,0,0.3,0"]
#: Goals: ratio of the median to the ``import pinocchio`` floor.
GOALS = {"import rcm_pin": 1.5, "rcm-pin fk": 2.0}


def rcm_pin_command(module: bool = False) -> list[str]:
    """The installed ``rcm-pin`` console script, else (or with ``module``) ``python -m
    rcm_pin``."""
    script = Path(sys.executable).with_name("rcm-pin")
    return [str(script)] if script.exists() and not module else [sys.executable, "-m", "rcm_pin"]


def commands(module: bool = False) -> dict[str, list[str]]:
    """The three measured commands, by label."""
    return {
        "import pinocchio": [sys.executable, "-c", "import pinocchio"],
        "import rcm_pin": [sys.executable, "-c", "import rcm_pin"],
        "rcm-pin fk": [*rcm_pin_command(module), *FK],
    }


def wall(cmd: list[str]) -> float:
    """Wall time [s] of one subprocess (raises if it fails)."""
    start = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start


def main(argv: list[str] | None = None) -> dict[str, object]:
    """Run the rounds and print the JSON document."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=11, help="measured rounds (default 11)")
    ap.add_argument(
        "--module",
        action="store_true",
        help="run the CLI as python -m rcm_pin (e.g. a checkout in the working directory)",
    )
    args = ap.parse_args(argv)
    cmds = commands(args.module)
    for cmd in cmds.values():  # warm-up: bytecode and render caches
        wall(cmd)
    times: dict[str, list[float]] = {label: [] for label in cmds}
    for _ in range(args.repeats):
        for label, cmd in cmds.items():
            times[label].append(wall(cmd))
    medians = {label: statistics.median(t) for label, t in times.items()}
    floor = medians["import pinocchio"]
    doc: dict[str, object] = {
        "benchmark": "start-up (fresh subprocesses, interleaved, wall time)",
        "repeats": args.repeats,
        "command": " ".join(cmds["rcm-pin fk"]),
        "seconds": {
            label: {"median": medians[label], "min": min(t), "max": max(t)}
            for label, t in times.items()
        },
        "ratios": [
            {
                "measured": label,
                "baseline": "import pinocchio",
                "ratio": medians[label] / floor,
                "goal": goal,
                "met": medians[label] / floor <= goal,
            }
            for label, goal in GOALS.items()
        ],
    }
    print(json.dumps(doc, indent=2))
    return doc


if __name__ == "__main__":
    main()
