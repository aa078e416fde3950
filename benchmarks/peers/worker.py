"""One contender of benchmarks/peers/run.py: a long-lived process speaking JSON lines.

    <venv>/bin/python benchmarks/peers/worker.py <module.py>

The module (a file of this folder, or any path) defines ``setup(case) -> state`` and
``run_once(state) -> dict`` (the accuracy figures of that run: floats, ints, strings,
booleans), or ``run_once(state) -> result`` and ``accuracy(state, result) -> dict`` where
checking the result costs time. Only ``run_once`` is timed (``time.perf_counter``);
``setup`` runs once per distinct case and is cached.

Protocol, one JSON object per line:

* request ``{"case": {...}, "rounds": k}`` → reply ``{"times": [k floats, s],
  "stamps": [k wall-clock starts, s], "accuracy": {...} (the last run's), "setup_s": float
  (0 when cached)}``; an exception → ``{"error": "<traceback>"}`` (the worker goes on);
* request ``{"quit": true}`` (or end of input) → the worker exits.

Only the standard library is imported here, so that every peer's venv runs it. The worker
dies with the harness: the harness starts it in its own session with the kernel's parent
death signal (``PR_SET_PDEATHSIG``, armed between fork and exec), and the worker exits at once
when its parent is not the PID in ``RCM_PIN_PEERS_PARENT`` (the harness died before the
signal was armed). The module's own prints go to stderr: the protocol has a private copy
of stdout.
"""

from __future__ import annotations

import importlib.util
import json
import os
import sys
import time
import traceback
from pathlib import Path
from typing import Any


def _load(path: str) -> Any:
    file = Path(path)
    if not file.is_file():
        file = Path(__file__).resolve().parent / path
    sys.path.insert(0, str(file.parent))
    spec = importlib.util.spec_from_file_location(f"peer_{file.stem}", file)
    if spec is None or spec.loader is None:
        raise ImportError(f"cannot load {file}")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


#: Distributions whose versions a worker reports when its module imported them.
PACKAGES = {"pinocchio": "pin", "crocoddyl": "crocoddyl", "mim_solvers": "mim-solvers",
            "pydrake": "drake", "mujoco": "mujoco", "casadi": "casadi", "scipy": "scipy",
            "numpy": "numpy", "pink": "pin-pink", "rcm_pin": "rcm-pin"}  # fmt: skip


def versions() -> dict[str, str]:
    """Versions of the packages of :data:`PACKAGES` this process has imported."""
    from importlib.metadata import PackageNotFoundError, version

    out = {}
    for module, dist in PACKAGES.items():
        if module in sys.modules:
            try:
                out[dist] = version(dist)
            except PackageNotFoundError:
                out[dist] = "?"
    return out


def _rounds(module: Any, states: dict[str, Any], request: dict[str, Any]) -> dict[str, Any]:
    case = request.get("case", {})
    key = json.dumps(case, sort_keys=True)
    setup_s = 0.0
    if key not in states:
        start = time.perf_counter()
        states[key] = module.setup(case)
        setup_s = time.perf_counter() - start
    state = states[key]
    times, stamps, result = [], [], None
    for _ in range(int(request.get("rounds", 1))):
        stamps.append(time.time())
        start = time.perf_counter()
        result = module.run_once(state)
        times.append(time.perf_counter() - start)
    check = getattr(module, "accuracy", None)
    accuracy = result if check is None else check(state, result)
    return {"times": times, "stamps": stamps, "accuracy": accuracy, "setup_s": setup_s}


def main(argv: list[str]) -> int:
    parent = os.environ.get("RCM_PIN_PEERS_PARENT")
    if parent is not None and os.getppid() != int(parent):
        return 1  # the harness is gone already
    out = os.fdopen(os.dup(1), "w", buffering=1)
    os.dup2(2, 1)  # prints of the libraries (IPOPT's banner, ...) go to stderr
    sys.stdout = sys.stderr
    try:
        module = _load(argv[1])
    except BaseException:
        out.write(json.dumps({"error": traceback.format_exc()}) + "\n")
        return 2
    hello = {"ready": True, "python": sys.version.split()[0], "versions": versions()}
    out.write(json.dumps(hello) + "\n")
    states: dict[str, Any] = {}
    for line in sys.stdin:
        if not line.strip():
            continue
        request = json.loads(line)
        if request.get("quit"):
            break
        try:
            reply = _rounds(module, states, request)
        except Exception:
            reply = {"error": traceback.format_exc()}
        out.write(json.dumps(reply) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
