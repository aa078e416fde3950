"""Rank-revealing Newton on the closure residual, and the mobility it reveals.

Drives fixed, passive joints free: solve e(q_a, q_p) = 0 for q_p. The step is

    Δq_p = −J_p⁺ e                        (J_p = ∂e/∂q_p, m × n_p)

with J_p⁺ the Moore–Penrose pseudo-inverse of rank r (singular values below
``RANK_TOL``·σ₁ dropped), so square, over-constrained (more rows than independent
constraints, e.g. a parallelogram written as a 4R loop) and under-determined systems all
converge quadratically to the nearest consistent configuration. A square, well-conditioned
J_p takes the plain ``np.linalg.solve`` step (the same iterates as an LU Newton). Each step
is clipped to ``max_step`` (it keeps the iterate on its branch) and applied with
``pin.integrate`` (multi-DOF and continuous joints). Revolute passive angles are wrapped to
[−π, π) at the end; prismatic joints are not.

:func:`solve_passive` on a Euclidean model with a square or tall J_p also exists as a
CasADi kernel (the same iterates to rounding, found through :mod:`rcm_pin.model.kernels`;
provider :mod:`ocp.kernels`); :func:`rcm_pin.analysis.closed_position.solve_drives` uses
it where it reproduces this loop and runs this loop everywhere else.

Mobility: at a closed configuration the loops leave nv − rank(J_c) freedoms; the drives
fix k of them. :func:`constraint_rank` is the numerical rank used by
:mod:`rcm_pin.analysis.mobility` and by the velocity analysis.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from rcm_pin.errors import SolverError
from rcm_pin.model.loops import Loops, residual_and_jacobian
from rcm_pin.model.output import Output
from rcm_pin.rotations import wrap_angle

#: Newton stops when the closure residual norm is below this [m].
RESIDUAL_TOL = 1e-13
#: Relative singular-value threshold of the rank decisions.
RANK_TOL = 1e-10
#: Default iteration cap of :func:`solve_passive`.
MAX_ITER = 60
#: Default largest passive-joint step per iteration [rad, m].
MAX_STEP = 0.5


def constraint_rank(jac: np.ndarray, tol: float = RANK_TOL) -> int:
    """Numerical rank of a Jacobian: #σᵢ > tol·σ₁ (0 for an empty or zero matrix)."""
    if jac.size == 0:
        return 0
    s = np.linalg.svd(jac, compute_uv=False)
    return int(np.sum(s > tol * max(float(s[0]), 1e-300)))


def _step(jp: np.ndarray, e: np.ndarray, res: float) -> np.ndarray:
    """−J_p⁺ e: LU when square and sane, else SVD least squares, LM if that blows up."""
    if jp.shape[0] == jp.shape[1]:
        try:
            step = -np.linalg.solve(jp, e)
            if float(np.abs(step).max(initial=0.0)) < 1e3:  # NaN fails this test too
                return step
        except np.linalg.LinAlgError:
            pass
    step = -np.linalg.lstsq(jp, e, rcond=RANK_TOL)[0]
    if not float(np.abs(step).max(initial=0.0)) < 1e3:
        mu = 1e-6 + res
        step = -np.linalg.solve(jp.T @ jp + mu * np.eye(jp.shape[1]), jp.T @ e)
    return step


def _advance(
    model: pin.Model,
    loops: Loops,
    q: np.ndarray,
    idx_v: np.ndarray,
    step: np.ndarray,
    idx_q: np.ndarray,
) -> np.ndarray:
    if loops.euclidean:
        q[idx_q] += step
        return q
    dv = np.zeros(model.nv)
    dv[idx_v] = step
    return np.asarray(pin.integrate(model, q, dv))


def wrap_passive(loops: Loops, q: np.ndarray, drives: bool = False) -> np.ndarray:
    """q with the passive (and with ``drives`` every) revolute angle wrapped to [−π, π)."""
    idx = loops.revolute_q if drives else loops.wrap_q
    if idx.size:
        q[idx] = wrap_angle(q[idx])
    return q


def solve_passive(
    model: pin.Model,
    data: pin.Data,
    loops: Loops,
    q_drives: np.ndarray,
    q_guess: np.ndarray,
    *,
    max_iter: int = MAX_ITER,
    max_step: float = MAX_STEP,
    name: str = "",
) -> tuple[np.ndarray, int, float]:
    """Newton on the closure residual with the drives fixed (module docstring).

    Args:
        model: Pinocchio model of the tree.
        data: its data (scratch).
        loops: closures and partition.
        q_drives: drive values (k,) [rad, m].
        q_guess: full starting configuration (nq,).
        max_iter: iteration cap.
        max_step: largest passive-joint step per iteration [rad, m].
        name: mechanism name for messages.

    Returns:
        (q with passive revolute angles wrapped, iterations, final residual norm [m]).

    Raises:
        SolverError: no convergence to :data:`RESIDUAL_TOL`.
    """
    q = np.array(q_guess, dtype=float)
    q[loops.drive_q] = q_drives
    res = math.inf
    for it in range(max_iter + 1):
        e, jac = residual_and_jacobian(model, data, loops, q)
        res = math.sqrt(float(e @ e))
        if res < RESIDUAL_TOL:
            return wrap_passive(loops, q), it, res
        step = _step(jac[:, loops.passive_v], e, res)
        peak = float(np.abs(step).max(initial=0.0))
        if peak > max_step:
            step *= max_step / peak
        q = _advance(model, loops, q, loops.passive_v, step, loops.passive_q)
    raise SolverError(
        f"{name}: closure Newton did not converge in {max_iter} iterations "
        f"(residual {res:.3e} m > {RESIDUAL_TOL:.0e} m) for drives {np.round(q_drives, 6)}"
    )


def solve_output(
    model: pin.Model,
    data: pin.Data,
    loops: Loops,
    output: Output,
    target: np.ndarray,
    q0: np.ndarray,
    *,
    max_iter: int = 20,
    tol: float = 1e-14,
) -> tuple[np.ndarray, int, float, float]:
    """Newton over every joint on [e(q); x(q) − x_t] = 0 (inverse problem polish).

    The stacked Jacobian [J_c; J_x] is square for a regular working mode (m + dim x = nv);
    the least-squares step also serves over-constrained loops.

    Returns:
        (q, iterations, closure residual norm [m], output error norm [m, rad]).
    """
    q = np.array(q0, dtype=float)
    dx_norm = math.inf
    for it in range(max_iter + 1):
        e, jc = residual_and_jacobian(model, data, loops, q)
        oMf = pin.updateFramePlacement(model, data, output.frame_id)
        dx = output.error(output.value(oMf), target)
        dx_norm = float(np.max(np.abs(dx), initial=0.0))
        if float(np.linalg.norm(e)) < RESIDUAL_TOL and dx_norm < tol:
            return wrap_passive(loops, q, True), it, float(np.linalg.norm(e)), dx_norm
        jx = pin.getFrameJacobian(model, data, output.frame_id, pin.LOCAL_WORLD_ALIGNED)
        jac = np.vstack([jc, jx[output.rows]])
        step = -np.linalg.lstsq(jac, np.concatenate([e, dx]), rcond=None)[0]
        q = _advance(model, loops, q, np.arange(model.nv), step, np.arange(model.nq))
    pin.forwardKinematics(model, data, q)
    from rcm_pin.model.loops import residual_from_data

    res = float(np.linalg.norm(residual_from_data(model, data, loops)))
    return wrap_passive(loops, q, True), max_iter, res, dx_norm


__all__ = [
    "MAX_ITER",
    "MAX_STEP",
    "RANK_TOL",
    "RESIDUAL_TOL",
    "constraint_rank",
    "solve_output",
    "solve_passive",
    "wrap_passive",
]
