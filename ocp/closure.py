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
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import casadi as ca
import numpy as np
from scipy.linalg import qr

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


def closure_function(sm: SymbolicModel, loops: Loops) -> ca.Function:
    """``closure(q) -> e``: the kept closure rows as a named CasADi function."""
    q = ca.SX.sym("q", sm.nq)
    return ca.Function("closure", [q], [closure_expr(sm, loops, q)], ["q"], ["e"])


__all__ = ["closure_expr", "closure_function", "independent_rows", "log3"]
