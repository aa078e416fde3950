"""Numeric inverse kinematics of a serial mechanism without a closed form (e.g. arms).

Multistart Levenberg–Marquardt on the output error of :mod:`rcm_pin.model.output`,

    e(q) = [p − p_t; log₃(R R_tᵀ)],   δq = −(JᵀJ + λI)⁻¹ Jᵀ e,

with J the LOCAL_WORLD_ALIGNED frame Jacobian rows of the output coordinates, the iterate
kept inside the joint limits (projection), λ raised on a failed step and lowered on a good
one. Starts: the middle of the joint box, then seeded uniform samples. Converged solutions
(max |e| < :data:`TOL`) are deduplicated; redundant arms have infinitely many, this
returns the distinct ones it finds. The CasADi layer (``ocp.ik``) is the alternative with
general constraints.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from rcm_pin.model.family import Branch
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output

#: Accepted output error [m, rad].
TOL = 1e-11


def _finite_box(mech: Mechanism) -> tuple[np.ndarray, np.ndarray]:
    lo = np.where(np.isfinite(mech.lower), mech.lower, -np.pi)
    hi = np.where(np.isfinite(mech.upper), mech.upper, np.pi)
    return lo, hi


def _error_and_jacobian(
    mech: Mechanism, q: np.ndarray, target: np.ndarray, output: Output
) -> tuple[np.ndarray, np.ndarray]:
    model, data = mech.model, mech.data
    pin.computeJointJacobians(model, data, mech.to_pin(q))
    oMf = pin.updateFramePlacement(model, data, output.frame_id)
    e = output.error(output.value(oMf), target)
    jac = pin.getFrameJacobian(model, data, output.frame_id, pin.LOCAL_WORLD_ALIGNED)
    return e, np.asarray(jac)[output.rows][:, mech.v_index]


def solve_one(
    mech: Mechanism, target: np.ndarray, output: Output, q0: np.ndarray, max_iter: int = 200
) -> tuple[np.ndarray, float]:
    """One LM run from q0; returns (q, max |e|)."""
    lo, hi = _finite_box(mech)
    q = np.clip(np.asarray(q0, dtype=float), lo, hi)
    lam = 1e-3
    e, jac = _error_and_jacobian(mech, q, target, output)
    cost = float(e @ e)
    for _ in range(max_iter):
        if float(np.max(np.abs(e), initial=0.0)) < TOL:
            break
        h = jac.T @ jac
        step = -np.linalg.solve(h + lam * (np.diag(np.diag(h)) + 1e-12 * np.eye(len(q))), jac.T @ e)
        q_new = np.clip(q + step, lo, hi)
        e_new, jac_new = _error_and_jacobian(mech, q_new, target, output)
        cost_new = float(e_new @ e_new)
        if cost_new < cost:
            q, e, jac, cost, lam = q_new, e_new, jac_new, cost_new, max(lam / 3.0, 1e-12)
        else:
            lam *= 4.0
            if lam > 1e8:
                break
    return q, float(np.max(np.abs(e), initial=0.0))


def numeric_branches(
    mech: Mechanism, target: np.ndarray, output: Output, n_starts: int = 16, seed: int = 0
) -> list[Branch]:
    """Distinct converged solutions from the box middle and seeded random starts."""
    from rcm_pin.analysis.closed_position import same

    lo, hi = _finite_box(mech)
    rng = np.random.default_rng(seed)
    starts = [0.5 * (lo + hi), *rng.uniform(lo, hi, size=(n_starts - 1, mech.nq))]
    found: list[np.ndarray] = []
    for q0 in starts:
        q, err = solve_one(mech, target, output, q0)
        if err < TOL and not any(same(mech, q, f) for f in found):
            found.append(q)
    return [Branch(q, f"numeric_{i}") for i, q in enumerate(found)]


__all__ = ["TOL", "numeric_branches", "solve_one"]
