"""Row ``closed_sim``, rcm-pin: the 3-RRR ``circle`` tracking scenario
(``rcm_pin.control.scenario``: paper 004's law, constrained KKT dynamics, DOP853) for the
case's simulated time, by the case's ``backend`` (``"python"``, the default, or
``"compiled"``: the ``closed_rhs`` kernel); accuracy: closure drift and task error of the run."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

import rcm_pin
from rcm_pin.control.scenario import run, scenarios


def setup(case: dict[str, Any]) -> dict[str, Any]:
    mech = rcm_pin.load(case["mechanism"])
    sc = dataclasses.replace(scenarios(mech)[case["scenario"]], duration=case["duration"])
    return {"mech": mech, "scenario": sc, "backend": case.get("backend", "python")}


def run_once(state: dict[str, Any]) -> Any:
    return run(state["mech"], state["scenario"], backend=state["backend"])


def accuracy(state: dict[str, Any], r: Any) -> dict[str, Any]:
    mech = state["mech"]
    drift = max(float(np.abs(mech.closure_residual(q)).max()) for q in r.q)
    err = float(np.nanmax(np.linalg.norm(r.x - r.x_ref, axis=1)))
    return {"rhs_evaluations": int(r.nfev), "closure_drift_max": drift,
            "task_error_max": err, "status": r.status}  # fmt: skip
