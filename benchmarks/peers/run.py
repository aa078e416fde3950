"""rcm-pin against the tools users would pick instead, each in its own venv (README.md).

    PYTHONPATH=. python benchmarks/peers/run.py --venvs "$VENVS" --json peers.json
    PYTHONPATH=. python benchmarks/peers/run.py --rows sim,inverse --rounds 3
    PYTHONPATH=. python benchmarks/peers/run.py --list

Every contender runs as a long-lived worker (``worker.py``) in its venv's python; the
rows of ``rows.py`` run one after the other, the contenders of a row in interleaved rounds
(``harness.py``). Prints a Markdown table (time per operation: median [min–max];
accuracy; ratio rcm-pin ÷ peer) and writes the JSON document atomically with ``--json``.
A venv that is missing gives "peer not installed" and the command that makes it.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from harness import UNITS, Row, run_rows

from rcm_pin.processes import atomic_write

#: Where the peers' venvs live by default (``--venvs``, or this variable).
VENVS_ENV = "RCM_PIN_PEERS_VENVS"


def _num(x: Any) -> str:
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        return str(x)
    if isinstance(x, int):
        return str(x)
    return f"{x:.3g}" if 1e-2 <= abs(x) < 1e4 or x == 0 else f"{x:.1e}"


def _time(info: dict[str, Any], unit: str) -> str:
    med = info[f"median_{unit}_per_op"]
    lo, hi = info[f"range_{unit}_per_op"]
    return f"{_num(med)} [{_num(lo)}–{_num(hi)}] {unit}"


def markdown(doc: dict[str, Any]) -> str:
    """The table of a run's document: one line per contender."""
    lines = [
        "| row | contender | time per op, median [min–max] | accuracy | ratio rcm-pin ÷ peer |",
        "| --- | --- | --- | --- | --- |",
    ]
    for row in doc["rows"].values():
        title = row["title"]
        for label, info in row["contenders"].items():
            if info["status"] == "ok":
                cell = _time(info, row["unit"])
                acc = ", ".join(f"{k} {_num(v)}" for k, v in info.get("accuracy", {}).items())
            elif info["status"] == "peer not installed":
                cell, acc = "peer not installed", f"`{info['install']}`"
            else:
                cell, acc = "failed", str(info.get("error", "")).replace("|", "/")[:160]
            ratios = [
                (f"**{_num(r['ratio'])}×** vs {r['baseline']}" if r["ratio"] is not None
                 else f"– vs {r['baseline']} ({r['note']})")
                for r in row["ratios"] if r["measured"] == label
            ]  # fmt: skip
            lines.append(f"| {title} | {label} | {cell} | {acc} | {'; '.join(ratios)} |")
            title = ""
    return "\n".join(lines)


def _select(rows: list[Row], keys: str | None) -> list[Row]:
    if keys is None:
        return rows
    wanted = [k.strip() for k in keys.split(",") if k.strip()]
    known = {r.key: r for r in rows}
    unknown = [k for k in wanted if k not in known]
    if unknown:
        raise SystemExit(f"--rows: unknown {', '.join(unknown)}; valid: {', '.join(known)}")
    return [known[k] for k in wanted]


def main(
    argv: list[str] | None = None,
    rows: list[Row] | None = None,
    installs: dict[str, str] | None = None,
) -> dict[str, Any]:
    """Run the rows (default: ``rows.ROWS``); print the table; return the document."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    default = os.environ.get(VENVS_ENV, str(Path(__file__).resolve().parent / ".venvs"))
    ap.add_argument("--venvs", type=Path, default=Path(default),
                    help=f"the peers' venvs (default ${VENVS_ENV}, else ./.venvs)")  # fmt: skip
    ap.add_argument("--rows", help="comma-separated row keys (default: all; see --list)")
    ap.add_argument("--rounds", type=int, default=5, help="timed interleaved rounds")
    ap.add_argument("--warmup", type=int, default=1, help="untimed rounds after setup")
    ap.add_argument("--json", type=Path, help="write the JSON document here (atomically)")
    ap.add_argument("--list", action="store_true", help="list the rows and exit")
    args = ap.parse_args(argv)
    if rows is None or installs is None:
        import rows as registry

        rows = registry.ROWS if rows is None else rows
        installs = registry.INSTALLS if installs is None else installs
    if args.list:
        for r in rows:
            who = ", ".join(f"{c.label} [{c.venv}]" for c in r.contenders)
            print(f"{r.key}: {r.title} — {who}")
        return {}
    if args.rounds < 1 or args.warmup < 0:
        ap.error("--rounds >= 1 and --warmup >= 0")
    selected = _select(rows, args.rows)
    bad = sorted({r.unit for r in selected} - set(UNITS))
    if bad:
        ap.error(f"unknown units {bad}")
    with tempfile.TemporaryDirectory(prefix="rcm-pin-peers-") as scratch:
        doc = run_rows(
            selected, args.rounds, args.warmup, args.venvs, installs, Path(scratch),
            progress=lambda key: print(f"[peers] {key}", file=sys.stderr, flush=True),
        )  # fmt: skip
    if args.json is not None:
        atomic_write(args.json, (json.dumps(doc, indent=2) + "\n").encode())
    print(markdown(doc))
    return doc


if __name__ == "__main__":
    main()
