"""Type-2 verdicts of a closed mechanism that names no output (a LAAS sidecar).

Without an output there is no type 1 (it is about the output's rates); type 2 (the drives
held, the passive joints still move to first order) is a property of the closures alone:
with J_c reduced to its independent rows (:func:`.loop_velocity.closure_jacobian`), the
passive columns J_c,p are square when the mobility nv − rank J_c equals the number of
drives, and the measure is

    μ₂ = σ_min(J_c,p D) / σ_max(J_c,p D),   D = diag(1 for angles, 1/L for lengths),

a type-2 singularity where μ₂ < tol (L: the loops' length scale [m]).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rcm_pin.analysis.loop_velocity import SINGULAR_TOL, closure_jacobian
from rcm_pin.errors import InvalidInputError
from rcm_pin.model.mechanism import Mechanism


def passive_measure(mech: Mechanism, q: np.ndarray) -> tuple[float, np.ndarray]:
    """(μ₂, singular values of J_c,p D) at a closed configuration q (module docstring).

    Raises:
        InvalidInputError: the mobility nv − rank J_c is not the number of drives (a
            self-motion, or too few closures); the message gives both numbers.
    """
    loops = mech.require_loops()
    jc = closure_jacobian(mech, mech.check_q(q))
    mobility = mech.nv - jc.shape[0]
    if mobility != loops.dof:
        raise InvalidInputError(
            f"{mech.name}: mobility nv − rank J_c = {mobility} but {loops.dof} drives; type 2 "
            "needs them equal (a larger mobility is a self-motion of the passive joints)"
        )
    revolute = np.zeros(mech.model.nv, dtype=bool)
    revolute[loops.revolute_q] = True  # euclidean layouts: q and v indices agree
    scale = np.where(revolute, 1.0, 1.0 / loops.length_scale)[loops.passive_v]
    sv = np.linalg.svd(jc[:, loops.passive_v] * scale[None, :], compute_uv=False)
    return (float(sv[-1] / sv[0]) if sv.size and sv[0] > 0 else 0.0), sv


def passive_report(
    mech: Mechanism, q: np.ndarray, tol: float = SINGULAR_TOL, label: str = ""
) -> dict[str, Any]:
    """The type-2 verdict at one closed configuration of a mechanism without output."""
    measure, sv = passive_measure(mech, q)
    return {
        "mode": label,
        "q": q,
        "residual": float(np.linalg.norm(mech.closure_residual(mech.q_pin(q)))),
        "sigma_passive": sv,
        "measure_type1": None,
        "measure_type2": measure,
        "type1": None,
        "type2": bool(measure < tol),
        "verdict": "type 2" if measure < tol else "regular (type 2 only: no output)",
    }


__all__ = ["passive_measure", "passive_report"]
