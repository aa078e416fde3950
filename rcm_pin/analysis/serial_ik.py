"""Numeric inverse kinematics of a serial mechanism without a closed form (e.g. arms).

Multistart bounded nonlinear least squares on the output error of
:mod:`rcm_pin.model.output`,

    e(q) = [p − p_t; log₃(R R_tᵀ)],   min ½ |e(q)|²  with  lower ≤ q ≤ upper,

by SciPy's trust-region reflective ``least_squares`` (``method="trf"``), J the
LOCAL_WORLD_ALIGNED frame Jacobian rows of the output coordinates. Starts: the middle of
the joint box, then seeded uniform samples. Converged solutions (max |e| < :data:`TOL`)
are deduplicated; redundant arms have infinitely many, this returns the distinct ones it
finds. The CasADi layer (``ocp.ik``, a compiled projected Levenberg–Marquardt) is the
alternative with general constraints.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from rcm_pin.model.family import Branch
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output

#: Accepted output error [m, rad].
TOL = 1e-11
#: A run stops where a step lowers ½|e|² by less than this fraction (a local minimum with
#: e ≠ 0: the next start is tried; a zero-residual solve never slows down that much).
FTOL = 1e-10


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
    """One bounded least-squares run from q0 (clipped to the box, at most ``max_iter``
    residual evaluations); returns (q, max |e|)."""
    lo, hi = _finite_box(mech)
    cache: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}

    def evaluate(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        key = q.tobytes()
        if key not in cache:  # the Jacobian is asked for at the q of the last residual
            cache.clear()
            cache[key] = _error_and_jacobian(mech, q, target, output)
        return cache[key]

    x0 = np.clip(np.asarray(q0, dtype=float), lo, hi)
    e0 = evaluate(x0)[0]
    if float(np.max(np.abs(e0), initial=0.0)) < TOL:  # already there
        return x0, float(np.max(np.abs(e0), initial=0.0))
    from scipy.optimize import least_squares  # lazy: `import rcm_pin` stays without scipy

    res = least_squares(
        lambda q: evaluate(q)[0],
        x0,
        jac=lambda q: evaluate(q)[1],
        bounds=(lo, hi),
        method="trf",
        # the dense trust-region solver stalls where J has more columns than rows (a
        # redundant arm, or a coordinate the output does not depend on): LSMR there
        tr_solver="exact" if len(e0) >= len(x0) else "lsmr",
        ftol=FTOL,
        xtol=1e-15,
        gtol=1e-15,
        max_nfev=max_iter,
    )
    q = np.clip(res.x, lo, hi)
    e = evaluate(q)[0]
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
