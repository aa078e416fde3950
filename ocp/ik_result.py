"""What one IK solve returns (:class:`IKResult`) and the typed error of a failed one.

A target that leaves a residual above ``reach_tol`` at a stationary point raises
:class:`~rcm_pin.errors.UnreachablePoseError`; a solver that stops for another reason
raises :class:`~rcm_pin.errors.SolverError`. Both carry the :class:`IKResult` as
``err.result``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rcm_pin.errors import SolverError, UnreachablePoseError

#: Statuses of a solver that stopped at a stationary point (not a solver failure).
STUCK = (
    "stationary",
    "converged",
    "Solve_Succeeded",
    "Infeasible_Problem_Detected",
    "Solved_To_Acceptable_Level",
)


@dataclass(frozen=True)
class IKResult:
    """Solution and diagnostics of one IK solve.

    Attributes:
        q: Pinocchio configuration (nq,) [rad, m].
        success: residual, constraints and closures within their tolerances.
        status: ``"converged"``, ``"stationary"``, ``"max_iter"`` or the NLP's status.
        solver: ``"lm"``, ``"ipopt"`` or ``"sqpmethod"``.
        iterations: summed over the restarts.
        residual_norm: |r(q)| (weighted).
        position_error: |p − p_t| [m] (output mode: over the translation coordinates).
        orientation_error: rotation angle between R and R_t [rad] (output mode: the
            largest angle error); NaN without orientation.
        constraint_violation: general constraints and closures (0 without).
        closure_residual: largest kept closure row [m, rad] (0 for a serial model).
    """

    q: np.ndarray
    success: bool
    status: str
    solver: str
    iterations: int
    residual_norm: float
    position_error: float
    orientation_error: float
    constraint_violation: float
    closure_residual: float = 0.0


def failure(r: IKResult, frame: str, reach_tol: float, closed: bool) -> Exception:
    """The typed error of a failed solve, with ``r`` attached as ``err.result``."""
    orientation = (
        ""
        if np.isnan(r.orientation_error)
        else f", orientation error {r.orientation_error:.3g} rad"
    )
    closure = f", closure residual {r.closure_residual:.3g}" if closed else ""
    msg = (
        f"IK of frame {frame!r} ({r.solver}, {r.status}, {r.iterations} it): residual "
        f"{r.residual_norm:.3g} > reach_tol {reach_tol:.0e}, position error "
        f"{r.position_error:.3g} m{orientation}, constraint violation "
        f"{r.constraint_violation:.3g}{closure}"
    )
    err: Exception = (
        UnreachablePoseError(
            f"unreachable target: {msg}; the solver stopped at a stationary point, which "
            "a local method cannot tell from a local minimum: valid targets lie in the "
            "image of the joint limits (retry with restarts > 0 to rule out a local minimum)"
        )
        if r.status in STUCK
        else SolverError(f"IK solver failed: {msg}")
    )
    err.result = r  # type: ignore[attr-defined]
    return err


__all__ = ["STUCK", "IKResult", "failure"]
