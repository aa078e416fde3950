"""The corpus, long form: every example-robot-data URDF through every command.

For each robot (loaded by path, the last link as the tool; see ``tests/corpus.py``) runs,
each in a fresh subprocess so that a crash of one robot cannot hide the others:

* ``fk``, ``ik`` (API) and ``fk`` (CLI) against plain Pinocchio, the mass matrix with them;
* ``singularities --q`` and ``workspace --samples 2000`` (CLI, ``--json``);
* ``view --html`` and ``view --png`` (CLI, ``--json``);

and prints one row per robot (``ok``, ``refused: <error type>`` or ``FAILED: ...``) and the
counts. Exit status 1 when any check failed (a traceback, a crash or a wrong pose).

    python benchmarks/corpus.py [--only SUBSTRING] [--markdown]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
import corpus  # noqa: E402

CHECKS = ["fk", "ik", "cli_fk", "singularities", "workspace", "html", "png"]

ONE = """
import json, sys
from pathlib import Path
sys.path.insert(0, {tests!r})
import corpus
path, name, out = Path(sys.argv[1]), sys.argv[2], sys.argv[3]
view = ["view", "{{path}}", "--tool-frame", "{{tool}}"]
checks = {{"fk": corpus.check_fk, "ik": corpus.check_ik, "cli_fk": corpus.check_cli_fk,
          **corpus.COMMANDS,
          "html": corpus.check_cli([*view, "--html", out + ".html"]),
          "png": corpus.check_cli([*view, "--png", out + ".png"])}}
o = corpus.run(checks[name], path)
print(json.dumps([o.status, o.detail]))
"""


def run_one(path: Path, check: str, folder: Path, timeout: float) -> tuple[str, str]:
    code = ONE.format(tests=str(ROOT / "tests"))
    out = str(folder / f"{corpus.robot_id(path).replace('/', '_')}")
    try:
        done = subprocess.run(
            [sys.executable, "-c", code, str(path), check, out],
            capture_output=True,
            text=True,
            timeout=timeout,
        )
    except subprocess.TimeoutExpired:
        return "failed", f"no answer within {timeout:.0f} s"
    if done.returncode != 0:
        last = (done.stderr.strip().splitlines() or ["(no output)"])[-1]
        return "failed", f"exit {done.returncode}: {last}"
    status, detail = json.loads(done.stdout.strip().splitlines()[-1])
    return status, detail


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", default="", help="robots whose id contains this")
    parser.add_argument("--timeout", type=float, default=300.0, help="per check [s]")
    parser.add_argument("--markdown", action="store_true", help="print a Markdown table")
    args = parser.parse_args()
    robots = [p for p in corpus.corpus() if args.only in corpus.robot_id(p)]
    counts: Counter[str] = Counter()
    failed = False
    if args.markdown:
        print("| robot | " + " | ".join(CHECKS) + " |")
        print("| --- " * (len(CHECKS) + 1) + "|")
    with tempfile.TemporaryDirectory() as tmp:
        for path in robots:
            cells, notes = [], []
            for check in CHECKS:
                status, detail = run_one(path, check, Path(tmp), args.timeout)
                counts[f"{check} {status}"] += 1
                failed |= status == "failed"
                if status == "ok":
                    cells.append("ok")
                elif status == "refused":
                    cells.append("refused: " + detail.split(":")[0].split(" ")[-1])
                    notes.append(f"{check}: {detail[:160]}")
                else:
                    cells.append("FAILED")
                    notes.append(f"{check}: {detail[:160]}")
            rid = corpus.robot_id(path)
            if args.markdown:
                print(f"| {rid} | " + " | ".join(cells) + " |")
            else:
                print(f"{rid:50s} " + " ".join(f"{c:>10s}" for c in cells), flush=True)
                for note in notes:
                    print(f"    {note}")
    print(json.dumps(dict(sorted(counts.items())), indent=1))
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())
