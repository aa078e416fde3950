"""Projected Levenberg-Marquardt for nonlinear least squares on compiled CasADi functions.

Minimises ``f(q) = 1/2 |r(q, target)|^2`` subject to ``lower <= q <= upper``. One
iteration is a single call of the named function ``lm_step`` (built once, optionally
JIT-compiled, called through ``Function.buffer()`` so that no Python/CasADi conversion
happens inside the loop):

    r, J = r(q), dr/dv(q)                     (J in tangent coordinates v)
    J   <- J with the columns of the active set zeroed (coordinates on a bound whose
           gradient J^T r points outwards stay put: projected Gauss-Newton)
    lam  = mu * max(diag(J^T J))              (Levenberg damping, relative to the scale)
    dv   = -(J^T J + lam I)^{-1} J^T r        (unrolled Cholesky)
    q+   = clip(integrate(q, dv), lower, upper)

and returns ``f(q)``, ``f(q+)``, the projected-gradient norm and the step norm; the loop
accepts a step that lowers ``f`` and divides ``mu`` by 10, else rejects it and multiplies
``mu`` by 10. Zero-residual problems converge quadratically (``mu`` -> its floor).

A compiled speed twin of the NumPy/SciPy route :mod:`rcm_pin.analysis.serial_ik` (SciPy's
bounded ``least_squares`` on Pinocchio's output error, the reference): from the same
starts both reach the same configuration
(``tests/test_ocp_ik.py::test_the_compiled_lm_is_the_least_squares_reference_on_ur5``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from ocp.buffered import BufferedFunction
from ocp.dynamics import cholesky_solve

MU_INIT = 1e-8
MU_MIN = 1e-14
MU_MAX = 1e12


@dataclass(frozen=True)
class LMOutcome:
    """Raw outcome of :meth:`LevenbergMarquardt.run`."""

    q: np.ndarray
    status: str  # "converged" | "stationary" | "max_iter"
    iterations: int
    residual_norm: float
    gradient_norm: float


def build_lm_step(
    residual: ca.Function,
    jacobian: ca.Function,
    integrate: ca.Function,
    lower: np.ndarray,
    upper: np.ndarray,
    bounded: list[tuple[int, int]],
    opts: dict[str, Any],
) -> ca.Function:
    """The named function ``lm_step(q, target, mu) -> (q_next, f, f_next, gnorm, snorm)``.

    ``bounded`` lists ``(v index, q index)`` of the box-bounded coordinates.
    """
    nq, nt = residual.size1_in(0), residual.size1_in(1)
    nv = jacobian.size2_out(0)
    q, target, mu = ca.SX.sym("q", nq), ca.SX.sym("target", nt), ca.SX.sym("mu")
    r = residual(q, target)
    jac = jacobian(q, target)
    lo, hi = ca.DM(lower), ca.DM(upper)
    grad = ca.mtimes(jac.T, r)
    # active set: coordinates on a bound whose gradient points outwards stay put
    free = ca.SX.ones(nv)
    for iv, iq in bounded:
        out = (q[iq] <= lo[iq]) * (grad[iv] > 0) + (q[iq] >= hi[iq]) * (grad[iv] < 0)
        free[iv] = 1 - out
    jac_free = jac * ca.repmat(free.T, jac.shape[0], 1)
    jtj, jtr = ca.mtimes(jac_free.T, jac_free), ca.mtimes(jac_free.T, r)
    lam = mu * ca.mmax(ca.diag(jtj)) + 1e-300
    dv = -cholesky_solve(jtj + lam * ca.SX.eye(nv), jtr)
    q_next = ca.fmin(ca.fmax(integrate(q, dv), lo), hi)
    # projected gradient: q - clip(integrate(q, -g)) (zero at a bound-constrained optimum)
    gproj = q - ca.fmin(ca.fmax(integrate(q, -grad), lo), hi)
    r_next = residual(q_next, target)
    return ca.Function(
        "lm_step",
        [q, target, mu],
        [
            q_next,
            0.5 * ca.sumsqr(r),
            0.5 * ca.sumsqr(r_next),
            ca.norm_inf(gproj),
            ca.norm_inf(q_next - q),
        ],
        ["q", "target", "mu"],
        ["q_next", "f", "f_next", "gnorm", "snorm"],
        opts,
    )


class LevenbergMarquardt:
    """The iteration loop around ``lm_step``, on preallocated buffers."""

    def __init__(self, step: ca.Function, tol: float = 1e-12, max_iter: int = 100) -> None:
        self.step, self.tol, self.max_iter = step, tol, max_iter
        self._fn = BufferedFunction(step)

    def run(self, q0: np.ndarray, target: np.ndarray, mu0: float = MU_INIT) -> LMOutcome:
        """Iterate from ``q0`` (clipped by the step) towards ``target``."""
        q, tgt, mu_in = self._fn.inputs
        q_next, f_val, f_next, gnorm, snorm = self._fn.outputs
        q[:] = q0
        tgt[:] = target
        mu, tol2 = mu0, 0.5 * self.tol * self.tol
        status, it, f_final = "max_iter", 0, np.inf
        for it in range(1, self.max_iter + 1):  # noqa: B007 - it is reported
            mu_in[0] = mu
            self._fn.evaluate()
            f_final = f_val[0]
            if f_val[0] <= tol2:
                status = "converged"
                break
            if f_next[0] < f_val[0]:
                q[:] = q_next
                f_final = f_next[0]
                mu = max(mu * 0.1, MU_MIN)
                if f_next[0] <= tol2:
                    status = "converged"
                    break
                if snorm[0] < 1e-15 or f_val[0] - f_next[0] < 1e-15 * f_val[0]:
                    status = "stationary"
                    break
            elif gnorm[0] < 1e-14 or mu >= MU_MAX:
                status = "stationary"
                break
            else:
                mu = min(mu * 10.0, MU_MAX)
        return LMOutcome(
            q.copy(), status, it, float(np.sqrt(2.0 * max(f_final, 0.0))), float(gnorm[0])
        )


__all__ = ["LMOutcome", "LevenbergMarquardt", "build_lm_step"]
