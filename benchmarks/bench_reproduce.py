"""``rcm-pin reproduce``: sequential, parallel and cached runs side by side (run on demand).

Prints a JSON document with the wall times [s] of three runs of the installed command into
one fresh output folder, in this order:

1. ``--jobs 1 --no-cache``: every section in one process (the sequential baseline);
2. ``--jobs N --no-cache`` (``--jobs``, default the number of cores): sections in N processes;
3. ``--jobs N`` again: the unchanged rerun, every section reused from the cache (goal
   ≤ 2 s);

and the ratios sequential / parallel and the cached rerun against the 2 s goal. Each run
is a subprocess, so the times include Python's start-up and the imports. A run takes
minutes (every paper's results are regenerated twice).

    python benchmarks/bench_reproduce.py [--jobs 2] [--only WORD ...]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def run(out: Path, jobs: int, cache: bool, only: list[str]) -> float:
    """Wall time [s] of one ``rcm-pin reproduce`` (raises if it fails)."""
    cmd = [sys.executable, "-m", "rcm_pin", "reproduce", "--json", "--out", str(out)]
    cmd += ["--jobs", str(jobs)] + ([] if cache else ["--no-cache"])
    for word in only:
        cmd += ["--only", word]
    start = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start


def main(argv: list[str] | None = None) -> dict[str, object]:
    """Run the three reproductions and print the JSON document."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--only", action="append", default=[], help="sections matching a word")
    args = ap.parse_args(argv)
    out = Path(tempfile.mkdtemp(prefix="bench_reproduce_"))
    try:
        sequential = run(out, 1, False, args.only)
        parallel = run(out, args.jobs, False, args.only)
        cached = run(out, args.jobs, True, args.only)
        sections = len(list((out / ".cache").glob("*.json")))
    finally:
        shutil.rmtree(out, ignore_errors=True)
    doc: dict[str, object] = {
        "benchmark": "rcm-pin reproduce (subprocess wall time, imports included)",
        "sections": sections,
        "jobs": args.jobs,
        "cores": os.cpu_count(),
        "seconds": {
            "--jobs 1 --no-cache (sequential)": sequential,
            f"--jobs {args.jobs} --no-cache (parallel)": parallel,
            f"--jobs {args.jobs}, unchanged rerun (cached)": cached,
        },
        "ratios": [
            {"measured": "parallel", "baseline": "sequential", "speed_up": sequential / parallel},
            {"measured": "cached rerun", "goal_s": 2.0, "met": cached <= 2.0},
        ],
    }
    print(json.dumps(doc, indent=2))
    return doc


if __name__ == "__main__":
    main()
