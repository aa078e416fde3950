"""Numeric inverse kinematics of a serial mechanism without a closed form (e.g. arms).

Multistart bounded nonlinear least squares on the output error of
:mod:`rcm_pin.model.output`,

    e(q) = [p − p_t; log₃(R R_tᵀ)],   min ½ |e(q)|²  with  lower ≤ q ≤ upper,

by SciPy's trust-region reflective ``least_squares`` (``method="trf"``), J the
LOCAL_WORLD_ALIGNED frame Jacobian rows of the output coordinates. Starts (the budget,
:data:`N_STARTS` by default, ``starts=`` of :func:`rcm_pin.inverse`, ``rcm-pin ik
--starts``): the middle of the joint box, then uniform samples of a generator seeded with
``seed`` (0), so a result repeats. Converged solutions (max |e| < :data:`TOL`) are
deduplicated; redundant arms have infinitely many, this returns the distinct ones it
finds. Where none converges, :func:`numeric_inverse` tells the two cases apart: a target
beyond the proven reach bound (:mod:`.reach`) is outside the workspace
(:class:`~rcm_pin.errors.UnreachablePoseError`); any other is only not found within the
starts (:class:`~rcm_pin.errors.SolutionNotFoundError`). The CasADi layer (``ocp.ik``, a
compiled projected Levenberg–Marquardt) is the alternative with general constraints.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from rcm_pin.analysis.reach import reach_bound
from rcm_pin.errors import InvalidInputError, SolutionNotFoundError, UnreachablePoseError
from rcm_pin.model.family import Branch
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output

#: Accepted output error [m, rad].
TOL = 1e-11
#: A run stops where a step lowers ½|e|² by less than this fraction (a local minimum with
#: e ≠ 0: the next start is tried; a zero-residual solve never slows down that much).
FTOL = 1e-10
#: Default number of starts of the multistart (the box middle + N_STARTS − 1 random ones).
N_STARTS = 16


def search_box(mech: Mechanism) -> tuple[np.ndarray, np.ndarray]:
    """The box searched and sampled [rad, m]: the limits, one turn [-π, π] for a revolute
    coordinate whose limits span a turn or more (every angle is there; some files write
    1e16 for "none"), and [-π, π] for any other unbounded coordinate."""
    lo, hi = np.array(mech.lower, dtype=float), np.array(mech.upper, dtype=float)
    turn = np.asarray(mech.revolute, dtype=bool) & ((hi - lo) >= 2 * np.pi)
    lo[turn], hi[turn] = -np.pi, np.pi
    return np.where(np.isfinite(lo), lo, -np.pi), np.where(np.isfinite(hi), hi, np.pi)


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
    lo, hi = search_box(mech)
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
    free = hi > lo  # a coordinate with equal limits is held there, not searched
    if not free.any():
        return x0, float(np.max(np.abs(e0), initial=0.0))
    from scipy.optimize import least_squares  # lazy: `import rcm_pin` stays without scipy

    def full(x: np.ndarray) -> np.ndarray:
        q = x0.copy()
        q[free] = x
        return q

    res = least_squares(
        lambda x: evaluate(full(x))[0],
        x0[free],
        jac=lambda x: evaluate(full(x))[1][:, free],
        bounds=(lo[free], hi[free]),
        method="trf",
        # the dense trust-region solver stalls where J has more columns than rows (a
        # redundant arm, or a coordinate the output does not depend on): LSMR there
        tr_solver="exact" if len(e0) >= int(free.sum()) else "lsmr",
        ftol=FTOL,
        xtol=1e-15,
        gtol=1e-15,
        max_nfev=max_iter,
    )
    q = np.clip(full(res.x), lo, hi)
    e = evaluate(q)[0]
    return q, float(np.max(np.abs(e), initial=0.0))


def numeric_branches(
    mech: Mechanism, target: np.ndarray, output: Output, n_starts: int = N_STARTS, seed: int = 0
) -> list[Branch]:
    """Distinct converged solutions from the box middle and seeded random starts."""
    from rcm_pin.analysis.closed_position import same

    lo, hi = search_box(mech)
    rng = np.random.default_rng(seed)
    starts = [0.5 * (lo + hi), *rng.uniform(lo, hi, size=(n_starts - 1, mech.nq))]
    found: list[np.ndarray] = []
    for q0 in starts:
        q, err = solve_one(mech, target, output, q0)
        if err < TOL and not any(same(mech, q, f) for f in found):
            found.append(q)
    return [Branch(q, f"numeric_{i}") for i, q in enumerate(found)]


def check_starts(starts: object) -> int:
    """``starts`` as a count of starts.

    Raises:
        InvalidInputError: not an integer >= 1.
    """
    if isinstance(starts, bool) or not isinstance(starts, (int, np.integer)) or starts < 1:
        raise InvalidInputError(f"starts {starts!r} is not a count; valid: an integer >= 1")
    return int(starts)


def numeric_inverse(
    mech: Mechanism, target: np.ndarray, output: Output, starts: int = N_STARTS, seed: int = 0
) -> list[Branch]:
    """:func:`numeric_branches`, and where none converges the reason (module docstring).

    Raises:
        InvalidInputError: ``starts`` not an integer >= 1.
        UnreachablePoseError: the target position lies beyond the reach bound (proved).
        SolutionNotFoundError: no solution within ``starts`` starts, none proved impossible.
    """
    starts = check_starts(starts)
    found = numeric_branches(mech, target, output, starts, seed)
    if found:
        return found
    text = ", ".join(
        f"{k}={v:.6g}" if isinstance(v, float) else k
        for k, v in output.to_json(target).items()
        if k != "angles"
    )
    bound = reach_bound(mech, output.frame)
    rows = [i for i, c in enumerate(output.coords) if c in ("x", "y", "z")]  # value index
    k = [sum(9 if c == "rotation" else 1 for c in output.coords[:i]) for i in rows]
    dist = float(np.linalg.norm(np.asarray(target)[k])) if k else 0.0
    if dist > bound + TOL:
        raise UnreachablePoseError(
            f"{mech.name}: target {text} is outside the workspace: its position is "
            f"{dist:.6g} m from the base, beyond the reach of frame {output.frame} "
            f"({bound:.6g} m: the link offsets and prismatic travels along the chain); "
            f"valid: a position within {bound:.6g} m of the base"
        )
    reason = f"{dist:.6g} m from the base, within the reach bound {bound:.6g} m"
    if not k or not np.isfinite(bound):
        reason = "no position" if not k else "the chain has no finite reach bound"
    raise SolutionNotFoundError(
        f"{mech.name}: no solution of target {text} found within {starts} starts of the "
        f"multistart least squares (seed {seed}); not proved unreachable ({reason}); valid: "
        "more starts (inverse(..., starts=N), rcm-pin ik --starts N) or another target"
    )


def solve_near(mech: Mechanism, target: np.ndarray, output: Output, q0: np.ndarray) -> np.ndarray:
    """The solution one least-squares run from ``q0`` converges to (continuation: a path's
    next sample from the previous one, a nearby solution on a redundant mechanism).

    Raises:
        SolutionNotFoundError: the run from ``q0`` ends with max |e| >= :data:`TOL`.
    """
    q, err = solve_one(mech, target, output, q0)
    if err >= TOL:
        raise SolutionNotFoundError(
            f"{mech.name}: target {np.round(target, 6).tolist()} of frame {output.frame} not "
            f"reached from q = {np.round(q0, 6).tolist()} (error {err:.2e} >= {TOL:g}); "
            "valid: a target near the last one reached"
        )
    return q


__all__ = [
    "N_STARTS",
    "TOL",
    "check_starts",
    "numeric_branches",
    "numeric_inverse",
    "search_box",
    "solve_near",
    "solve_one",
]
