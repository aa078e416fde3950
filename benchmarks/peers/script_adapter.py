"""A worker module for a standalone peer script with ``run(rounds) -> dict`` (a script
that times its own rounds and prints JSON; the rows' peers are worker modules now, e.g.
``rcm_ik_drake_worker.py``), so that a row can point at it:

    Contender("My peer", "script_adapter.py", "drake", True,
              {"script": "my_peer_script.py", "rounds_per_call": 1})

``setup`` imports ``case["script"]`` (a file of this folder, or a path); ``run_once``
calls ``run(case["rounds_per_call"])`` (default 1) and returns the numbers and strings at
the top level of its dict (and of its ``"accuracy"`` entry, when it has one) as the
accuracy figures. The timing then includes whatever ``run`` builds per call; a script that
also defines ``setup(case)`` and ``run_once(state)`` can be used directly instead."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from typing import Any


def setup(case: dict[str, Any]) -> dict[str, Any]:
    file = Path(case["script"])
    if not file.is_file():
        file = Path(__file__).resolve().parent / case["script"]
    spec = importlib.util.spec_from_file_location(f"peer_script_{file.stem}", file)
    if spec is None or spec.loader is None:
        raise ImportError(f"cannot load {file}")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return {"run": module.run, "rounds": int(case.get("rounds_per_call", 1))}


def _flat(doc: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in doc.items() if isinstance(v, (int, float, str, bool))}


def run_once(state: dict[str, Any]) -> Any:
    return state["run"](state["rounds"])


def accuracy(state: dict[str, Any], doc: Any) -> dict[str, Any]:
    if not isinstance(doc, dict):
        return {"result": str(doc)[:200]}
    nested = doc.get("accuracy")
    return {**_flat(doc), **(_flat(nested) if isinstance(nested, dict) else {})}
