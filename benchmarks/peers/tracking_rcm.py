"""Rows ``tracking_*``, rcm-pin: paper 000's tracking OCP (``ocp.paper000.build`` on the
case's mechanism, N intervals, Radau d = 3, tol 1e-12) solved from the exact initial state
with the case's effort limits, by today's default route (:mod:`ocp.tracking`,
``reduced=True``, ``hessian="cost"``): Newton's method on the reduced problem, its
solution returned when it keeps every limit (no limits, inactive limits), else IPOPT on
the reduced NLP (binding limits; the iterations count both). ``case["config"]``:
``default`` (CasADi VM) or ``compiled`` (``compile=True``: the stage functions compiled
through the disk cache). Built (and compiled) in ``setup``; ``run_once`` times
``TrackingOCP.solve`` (cold: the "hold" initial guess every time). Accuracy: the tracking
error at the nodes, the peak effort (over the limit, the largest excess), the iterations,
the route (``solver``: newton | ipopt) and its status."""

from __future__ import annotations

from typing import Any

import numpy as np
import pinocchio as pin
from common import reference

from ocp import paper000 as paper

CONFIGS: dict[str, dict[str, Any]] = {"default": {}, "compiled": {"compile": True}}


def setup(case: dict[str, Any]) -> dict[str, Any]:
    limited = case["effort_limits"] is not None
    ocp, mech = paper.build(case["mechanism"], case["n_intervals"], drive_limits=limited,
                            **CONFIGS[case["config"]])  # fmt: skip
    lim = None if not limited else np.asarray(case["effort_limits"])
    return {"ocp": ocp, "mech": mech, "lim": lim, "x0": np.asarray(case["x0"]), "case": case}


def run_once(state: dict[str, Any]) -> Any:
    return state["ocp"].solve(paper.reference_position, state["x0"],
                              effort_limits=state["lim"], raise_on_failure=False)  # fmt: skip


def node_errors(model: pin.Model, frame: str, q: np.ndarray, case: dict[str, Any],
                t: np.ndarray) -> float:  # fmt: skip
    """max over the nodes of |p(q_k) − p_ref(t_k)| [m] (Pinocchio FK)."""
    data, fid = model.createData(), model.getFrameId(frame)
    p_ref = reference(case["traj"], t)[0]
    err = 0.0
    for qk, pk in zip(q, p_ref):
        pin.framesForwardKinematics(model, data, qk)
        err = max(err, float(np.linalg.norm(data.oMf[fid].translation - pk)))
    return err


def effort_figures(tau: np.ndarray, lim: np.ndarray | None) -> dict[str, float]:
    """Peak |τ| over the limit (≤ 1: kept) and the largest excess [N·m, N]."""
    if lim is None:
        return {"peak_effort_Nm": float(np.abs(tau).max())}
    ratio = np.abs(tau) / lim
    return {"peak_effort_over_limit": float(ratio.max()),
            "limit_excess": float(np.maximum(np.abs(tau) - lim, 0.0).max())}  # fmt: skip


def accuracy(state: dict[str, Any], r: Any) -> dict[str, Any]:
    case, mech = state["case"], state["mech"]
    return {"node_tracking_error_m": node_errors(mech.model, case["frame"], r.q, case, r.t),
            **effort_figures(r.tau, state["lim"]), "objective": float(r.objective),
            "iterations": int(r.iterations), "solver": r.solver, "status": r.status}  # fmt: skip
