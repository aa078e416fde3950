"""rcm-pin's tracking OCP against Crocoddyl on the same problem, timed in alternating rounds.

    python benchmarks/bench_tracking_vs_crocoddyl.py --peer-python /path/to/python --rounds 7

``--peer-python``: a Python with Crocoddyl and mim-solvers (it pins its own Pinocchio, so it
runs in a separate process: ``benchmarks/peers/crocoddyl_tracking.py``). The problem:
paper 000's reference on ``rcm_two_mass`` over one period, N = 100 (``ocp.paper000``; the
peer script writes the same cost for Crocoddyl). Cases: no limits, URDF drive limits
(inactive), 0.8 x the exact solution's peak efforts (binding). Each round solves every
rcm-pin configuration and case once, then runs the peer script once (each case: a warm-up
solve, then the median of 3); the
JSON gives per configuration and case the median times of the rounds, iterations, status,
tracking error, and the ratio to the peer's median from the same rounds (Crocoddyl's FDDP
without limits, BoxFDDP with them, and mim-solvers' CSQP on the binding case). Machine
load cancels in the ratios, not in the times.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from ocp import paper000 as paper

PEER = Path(__file__).resolve().parent / "peers" / "crocoddyl_tracking.py"
#: rcm-pin configurations: build and solve keyword arguments. ``before``: the default up to
#: issue 27 (the full NLP, IPOPT with the exact Hessian, screening by an unlimited IPOPT
#: solve); ``default``: the default since (the reduced problem: Newton's method, IPOPT with
#: the cost Hessian when limits bind); ``compiled``: the same with ``compile=True``.
CONFIGS: dict[str, dict[str, Any]] = {
    "before": {"reduced": False, "hessian": "exact"},
    "default": {},
    "compiled": {"compile": "-O1"},
}
#: Cases: drive-limit constraints present, limits kind, and the peer rows compared.
CASES = {
    "unlimited": (False, "none", ("unlimited/fddp",)),
    "urdf_limits": (True, "urdf", ("urdf_limits/boxfddp",)),
    "binding_limits": (True, "binding", ("binding_limits/boxfddp", "binding_limits/csqp")),
}


def _limits(mech: Any, kind: str) -> np.ndarray | None:
    if kind == "urdf":
        return np.asarray(mech.model.effortLimit, float).copy()
    if kind == "binding":
        return 0.8 * paper.peak_efforts(mech)
    return None


def _peer(python: str, n: int) -> dict[str, Any]:
    out = subprocess.run(
        [python, str(PEER), "--rounds", "3", "--n", str(n)], capture_output=True, text=True
    )
    if out.returncode:
        sys.exit(f"peer failed: {out.stderr[-2000:]}")
    return dict(json.loads(out.stdout))


def run(python: str, rounds: int, n: int, mechanism: str = "rcm_two_mass") -> dict[str, Any]:
    """Alternating rounds of rcm-pin and the peer; medians and ratios (see the module)."""
    built = {}
    for cname, kw in CONFIGS.items():
        for case, (limited, kind, _) in CASES.items():
            start = time.perf_counter()
            ocp, mech = paper.build(mechanism, n, drive_limits=limited, **kw)
            built[cname, case] = (ocp, mech, _limits(mech, kind), time.perf_counter() - start)
    ours: dict[tuple[str, str], list[Any]] = {key: [] for key in built}
    peers: list[dict[str, Any]] = []
    for _ in range(rounds):
        for key, (ocp, mech, lim, _) in built.items():
            ours[key].append(paper.solve(ocp, mech, effort_limits=lim, raise_on_failure=False))
        peers.append(_peer(python, n))
    out: dict[str, Any] = {"mechanism": mechanism, "n_intervals": n, "rounds": rounds}
    out["peer"] = {"versions": peers[0]["versions"]}
    for row in {r for _, _, rows in CASES.values() for r in rows}:
        last = peers[-1][row]
        out["peer"][row] = {
            "solve_ms": float(np.median([p[row]["solve_ms"] for p in peers])),
            **{k: last[k] for k in ("iterations", "converged", "tracking_error", "cost")},
        }
    for (cname, case), runs in ours.items():
        res, build_s = runs[-1], built[cname, case][3]
        ms = float(np.median([1e3 * r.solve_time for r in runs]))
        row = {
            "solve_ms": ms, "build_s": build_s, "solver": res.solver, "status": res.status,
            "iterations": res.iterations, "tracking_error": res.tracking_error,
            "objective": res.objective,
        }  # fmt: skip
        for peer_row in CASES[case][2]:
            row[f"ratio_vs_{peer_row}"] = ms / out["peer"][peer_row]["solve_ms"]
        out.setdefault(cname, {})[case] = row
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--peer-python", required=True, help="a Python with Crocoddyl")
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--n", type=int, default=100)
    parser.add_argument("--mechanism", default="rcm_two_mass")
    args = parser.parse_args()
    print(json.dumps(run(args.peer_python, args.rounds, args.n, args.mechanism), indent=2))


if __name__ == "__main__":
    main()
