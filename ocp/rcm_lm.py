"""The exact RCM IK as a zero-residual least-squares problem, by a compiled projected LM.

With the RCM as an equality the IK of :mod:`ocp.rcm` has the solution set

    r(q, p_d) = [ p_tip(q) − p_d                 (3)
                  (R(q) b_1)ᵀ (p_T − p_s(q))      (1)     = 0,   q_lo ≤ q ≤ q_hi
                  (R(q) b_2)ᵀ (p_T − p_s(q)) ]    (1)

(``b_1``, ``b_2`` complete the shaft axis to an orthonormal basis: the two components of
p_T − p_s orthogonal to the shaft, the residual of :class:`ocp.ik_constraints.AxisThroughPoint`;
``|r|² = |tip error|² + RCM distance²``). A 7-joint arm has a manifold of solutions; the
projected Levenberg–Marquardt of :mod:`ocp.ik_lm` takes the damped least-squares step
``−(JᵀJ + λI)⁻¹ Jᵀ r`` (λ → 0 at a zero residual: the minimum-norm Gauss–Newton step, which
stays near the warm start) and keeps ``q`` in the limits by its active set and clipping.
Its one function per iteration, ``lm_step``, is compiled to C through the disk cache of
:mod:`ocp.compiled` and called on buffers. IPOPT on the NLP of :mod:`ocp.rcm` reaches the
same zero residual at its own point of the manifold.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from ocp.compiled import compiled
from ocp.ik import IKProblem
from ocp.ik_constraints import AxisThroughPoint, constraint_expr
from ocp.ik_lm import LevenbergMarquardt, LMOutcome, build_lm_step


def rcm_residual(problem: IKProblem, constraint: AxisThroughPoint) -> ca.Function:
    """``rcm_residual(q, target) -> r`` (5,): tip error, then the two RCM components."""
    sm = problem.sm
    q, target = ca.SX.sym("q", sm.nq), ca.SX.sym("target", 3)
    p_tip, _ = sm.frame_placement(problem.fid)(q)
    p_shaft, rot = sm.frame_placement(constraint.frame)(q)  # type: ignore[arg-type]
    rcm = constraint_expr(constraint, p_shaft, rot).g
    r = ca.vertcat(p_tip - target, rcm)
    return ca.Function("rcm_residual", [q, target], [r], ["q", "target"], ["r"])


def tangent_jacobian(residual: ca.Function, problem: IKProblem) -> ca.Function:
    """``rcm_jacobian(q, target) -> J = dr/dq · dq/dv`` (tangent coordinates)."""
    sm = problem.sm
    q, target, dv = ca.SX.sym("q", sm.nq), ca.SX.sym("target", 3), ca.SX.sym("dv", sm.nv)
    tangent = ca.substitute(ca.jacobian(sm.integrate()(q, dv), dv), dv, 0 * dv)
    r = residual(q, target)
    jac = ca.mtimes(ca.jacobian(r, q), tangent)
    return ca.Function("rcm_jacobian", [q, target], [jac], ["q", "target"], ["J"])


class RcmLM:
    """The compiled LM of the exact RCM IK of ``problem`` (built once, run per target)."""

    def __init__(self, problem: IKProblem, constraint: AxisThroughPoint) -> None:
        if constraint.tolerance != 0.0:
            raise ValueError("the least-squares form needs the RCM as an equality")
        sm = problem.sm
        residual = rcm_residual(problem, constraint)
        bounded = [
            (j.idx_v, j.idx_q) for j in sm.joints if not j.mimic and j.kind != "revolute_unbounded"
        ]
        step = build_lm_step(
            residual,
            tangent_jacobian(residual, problem),
            sm.integrate(),
            problem.lower,
            problem.upper,
            bounded,
            {},
        )
        self.step = compiled(step, key="rcm_lm")
        self.lm = LevenbergMarquardt(self.step, problem.tol, problem.max_iter)
        self.reach_tol = problem.reach_tol

    def run(self, q0: np.ndarray, target: np.ndarray) -> tuple[LMOutcome, bool]:
        """The LM from ``q0`` (clipped into the limits by the first step) to ``target``;
        and whether it met the residual ``reach_tol``."""
        out = self.lm.run(q0, target)
        ok = out.status in ("converged", "stationary") and out.residual_norm <= self.reach_tol
        return out, ok


__all__ = ["RcmLM", "rcm_residual", "tangent_jacobian"]
