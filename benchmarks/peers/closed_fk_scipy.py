"""Rows ``closed_fk_*``, the peer: ``scipy.optimize.root`` (MINPACK hybrj, analytic
Jacobian) on the same closures (the mechanism's Pinocchio closure residual and its
Jacobian restricted to the passive coordinates, the drives fixed), along the same path,
warm-started the same way; xtol 1e-13 so that the residuals match rcm-pin's Newton."""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.optimize import root

import rcm_pin


def setup(case: dict[str, Any]) -> dict[str, Any]:
    mech = rcm_pin.load(case["mechanism"])
    return {"mech": mech, "drives": np.asarray(case["drives"]), "home": np.asarray(
        case["q_home"]), "q_ref": np.asarray(case["q_ref"])}  # fmt: skip


def run_once(state: dict[str, Any]) -> tuple[np.ndarray, int]:
    mech = state["mech"]
    assert mech.loops is not None
    dq, pq, pv = mech.loops.drive_q, mech.loops.passive_q, mech.loops.passive_v
    q, out, calls = state["home"].copy(), [], 0
    for d in state["drives"]:
        q = q.copy()
        q[dq] = d

        def fun(x: np.ndarray, q: np.ndarray = q) -> tuple[np.ndarray, np.ndarray]:
            q[pq] = x
            r, J = mech.residual_and_jacobian(q)
            return r, J[:, pv]

        sol = root(fun, q[pq], jac=True, method="hybr", options={"xtol": 1e-13})
        q[pq] = sol.x
        calls += int(sol.nfev)
        out.append(q.copy())
    return np.array(out), calls


def accuracy(state: dict[str, Any], result: Any) -> dict[str, Any]:
    mech, (qs, calls) = state["mech"], result
    res = max(float(np.abs(mech.closure_residual(x)).max()) for x in qs)
    return {"dq_max": float(np.abs(qs - state["q_ref"]).max()), "residual_max": res,
            "evaluations": calls}  # fmt: skip
