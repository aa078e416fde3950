"""Loop closures of a closed :class:`~rcm_pin.Mechanism` as CasADi expressions.

Built from the :class:`~ocp.symbolic.SymbolicModel` frame placements of the cut-open
tree, closure by closure (frames a and b, kept rows ``closure.rows``):

    3d:  e = R_aᵀ (p_a − p_b)                       [m]        (Pinocchio's residual)
    6d:  e = [ᵃp_b ; log₃(ᵃR_b)],  ᵃp_b = R_aᵀ (p_b − p_a),  ᵃR_b = R_aᵀ R_b   [m, rad]

The 3d rows are Pinocchio's (:func:`rcm_pin.model.loops.residual_from_data`) exactly. The
6d rows replace Pinocchio's log₆(ᵃM_b) by the translation and the rotation logarithm of
ᵃM_b: both vanish exactly where the frames coincide (and, on a planar loop, where the kept
rows do), and their Jacobians agree wherever the loop is closed (ᵃM_b = I), so an
equality constraint on either defines the same closed configurations with the same
constraint Jacobian there; away from closure they differ by second-order terms only.

:func:`log3` is smooth through θ = 0 (the closed configurations): ω = (θ / sin θ) v with
v = vee(R − Rᵀ) / 2 = sin θ · axis, and θ / sin θ replaced by 1 + |v|² / 6 below
θ ≈ 1e-8 (error O(θ⁴)); it is not defined at θ = π (nor is log₃).

:func:`pinocchio_closure` is the second form, which mirrors Pinocchio's Newton inputs
(:func:`rcm_pin.model.loops.residual_and_jacobian`) operation for operation, for the
compiled Newton of :mod:`ocp.kernels`:

    3d:  e = R_aᵀ (p_a − p_b),   J = R_aᵀ (J_a − J_b)_lin     (LOCAL_WORLD_ALIGNED; this J
         drops ∂R_aᵀ/∂q, so it is exact only where e = 0, as Pinocchio's route is)
    6d:  e = log₆(ᵃM_b) = [V⁻¹(ω) ᵃp_b ; ω],  ω = log₃(ᵃR_b),  J = ∂e/∂q (exact, as
         Pinocchio's Jlog₆(ᵃM_b)(J_b − Ad(ᵇM_a) J_a) is), with
         V⁻¹(ω) p = α p − ½ ω × p + β (ω·p) ω,  α = θ sin θ / (2 (1 − cos θ)),
         β = 1/θ² − sin θ / (2 θ (1 − cos θ))  (series 1 − θ²/12 − θ⁴/720, 1/12 + θ²/720
         below θ² = 1e-8, as ``pin.log6``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import casadi as ca
import numpy as np

from ocp.kinematics import Sym
from ocp.symbolic import SymbolicModel
from rcm_pin.model.loops import Loops
from rcm_pin.model.newton import constraint_rank

_SMALL = 1e-16  # |v|^2 below which theta / sin(theta) takes its series [-]


def log3(rot: Sym) -> Sym:
    """The rotation vector ω (3,) [rad] of a rotation matrix (``pin.log3``, θ < π)."""
    v = 0.5 * ca.vertcat(rot[2, 1] - rot[1, 2], rot[0, 2] - rot[2, 0], rot[1, 0] - rot[0, 1])
    c = 0.5 * (rot[0, 0] + rot[1, 1] + rot[2, 2] - 1.0)
    s2 = ca.sumsqr(v)
    s = ca.sqrt(ca.fmax(s2, 1e-300))
    scale = ca.if_else(ca.logic_and(s2 < _SMALL, c > 0), 1.0 + s2 / 6.0, ca.atan2(s, c) / s)
    return scale * v


def independent_rows(jacobian: np.ndarray) -> list[int]:
    """Rows of a closure Jacobian that form an independent set (rank-revealing QR of Jᵀ with
    column pivoting; the rank as :func:`rcm_pin.model.newton.constraint_rank` counts it).

    An over-constrained loop (a parallelogram written as a 4R loop) has structurally
    redundant rows; an NLP given all of them as equalities has more constraints than
    freedoms in them (IPOPT: ``Not_Enough_Degrees_Of_Freedom``). Keeping an independent
    subset defines the same closed configurations near the one where J is evaluated.
    """
    if jacobian.shape[0] == 0:
        return []
    rank = constraint_rank(jacobian)
    from scipy.linalg import qr  # lazy: the closure kernels load this module at start-up

    _, _, piv = qr(jacobian.T, mode="economic", pivoting=True)
    return sorted(int(i) for i in piv[:rank])


def closure_expr(sm: SymbolicModel, loops: Loops, q: Sym, rows: Sequence[int] | None = None) -> Sym:
    """The kept closure rows e(q) (m,) of every closure, in ``loops.closures`` order
    (``rows``: only these of them, e.g. :func:`independent_rows`)."""
    parts: list[Any] = []
    for c in loops.closures:
        p_a, r_a = sm.frame_placement(c.frame_a_id)(q)
        p_b, r_b = sm.frame_placement(c.frame_b_id)(q)
        if c.kind == "3d":
            err = ca.mtimes(r_a.T, p_a - p_b)
        else:
            err = ca.vertcat(ca.mtimes(r_a.T, p_b - p_a), log3(ca.mtimes(r_a.T, r_b)))
        parts += [err[r] for r in c.rows]
    if rows is not None:
        parts = [parts[i] for i in rows]
    return ca.vertcat(*parts) if parts else type(q).zeros(0, 1)


def log6(rot: Sym, p: Sym) -> Sym:
    """``pin.log6`` of the placement (R, p): [V⁻¹(ω) p ; ω] (6,) [m, rad] (module docstring)."""
    w = log3(rot)
    t2 = ca.sumsqr(w)
    th = ca.sqrt(ca.fmax(t2, 1e-300))
    st, ct = ca.sin(th), ca.cos(th)
    small = t2 < 1e-8
    alpha = ca.if_else(small, 1.0 - t2 / 12.0 - t2 * t2 / 720.0, th * st / (2.0 * (1.0 - ct)))
    beta = ca.if_else(small, 1.0 / 12.0 + t2 / 720.0, 1.0 / t2 - st / (2.0 * th * (1.0 - ct)))
    lin = alpha * p - 0.5 * ca.cross(w, p) + beta * ca.dot(w, p) * w
    return ca.vertcat(lin, w)


def pinocchio_closure(
    sm: SymbolicModel, loops: Loops, q: Sym, columns: Sequence[int]
) -> tuple[Sym, Sym]:
    """Pinocchio's closure residual e(q) (m,) and its Newton Jacobian (m, len(columns))
    restricted to the v ``columns`` (module docstring: the second form). ``q`` must be
    an SX symbol (or an expression of SX symbols) of a Euclidean model (nq = nv)."""
    es: list[Any] = []
    js: list[Any] = []
    cols = list(columns)
    for c in loops.closures:
        p_a, r_a = sm.frame_placement(c.frame_a_id)(q)
        p_b, r_b = sm.frame_placement(c.frame_b_id)(q)
        rows = list(c.rows)
        if c.kind == "3d":
            j_a = sm.frame_jacobian(c.frame_a_id)(q)
            j_b = sm.frame_jacobian(c.frame_b_id)(q)
            rt = r_a.T
            es.append(ca.mtimes(rt, p_a - p_b)[rows])
            js.append(ca.mtimes(rt, j_a[:3, cols] - j_b[:3, cols])[rows, :])
        else:
            err = log6(ca.mtimes(r_a.T, r_b), ca.mtimes(r_a.T, p_b - p_a))[rows]
            es.append(err)
            js.append(ca.jacobian(err, q)[:, cols])
    return ca.vertcat(*es), ca.vertcat(*js)


def closure_function(sm: SymbolicModel, loops: Loops) -> ca.Function:
    """``closure(q) -> e``: the kept closure rows as a named CasADi function."""
    q = ca.SX.sym("q", sm.nq)
    return ca.Function("closure", [q], [closure_expr(sm, loops, q)], ["q"], ["e"])


__all__ = [
    "closure_expr",
    "closure_function",
    "independent_rows",
    "log3",
    "log6",
    "pinocchio_closure",
]
