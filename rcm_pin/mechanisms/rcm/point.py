"""Tool-centre point kinematics of the RCM mechanisms: p = q3·e4(q1, q2).

The tool centre of every RCM mechanism (and of the two-mass model) is

.. math:: p = q_3 e_4,\\quad e_4 = [\\sin q_2, -\\sin q_1\\cos q_2, \\cos q_1\\cos q_2],

so :math:`\\dot p = J(q)\\dot q` with :math:`J = [q_3 E_1, q_3 E_2, e_4]` and
:math:`\\ddot p = J\\ddot q + h(q, \\dot q)`. The inverse (principal branch,
cos q2 > 0, q3 > 0): q3 = |p|, q2 = atan2(x, sqrt(y² + z²)), q1 = atan2(−y, z). The
computed-torque law uses these closed forms through the family's task-kinematics hook;
Pinocchio's frame Jacobian is the second route (tests).
"""

from __future__ import annotations

import math

import numpy as np

from rcm_pin.control.references import CartesianTrajectory
from rcm_pin.errors import InvalidInputError, SingularConfigurationError


def _axes(q: np.ndarray) -> tuple[tuple[float, float, float], ...]:
    """e4 and its derivatives E1 = ∂e4/∂q1, E2 = ∂e4/∂q2, E11, E12 as float triples.

    Scalars through :mod:`math`: a call costs a few µs instead of the ~30 µs numpy spends
    building five small arrays (the computed-torque law calls this per right-hand side);
    the products are those of the former array code, in the same order.
    """
    q1, q2 = float(q[0]), float(q[1])
    s1, c1, s2, c2 = math.sin(q1), math.cos(q1), math.sin(q2), math.cos(q2)
    e4 = (s2, -s1 * c2, c1 * c2)
    E1 = (0.0, -c1 * c2, -s1 * c2)
    E2 = (c2, s1 * s2, -c1 * s2)
    E11 = (0.0, s1 * c2, -c1 * c2)
    E12 = (0.0, c1 * s2, s1 * s2)
    return e4, E1, E2, E11, E12


def point_position(q: np.ndarray) -> np.ndarray:
    """Tool centre p = q3 e4 (3,) [m] from (q1, q2, q3, ...)."""
    q3, e4 = float(q[2]), _axes(q)[0]
    return np.array([q3 * e4[0], q3 * e4[1], q3 * e4[2]])


def point_jacobian(q: np.ndarray) -> np.ndarray:
    """J = ∂p/∂(q1, q2, q3) (3, 3) [m/rad, m/rad, -]."""
    e4, E1, E2, _, _ = _axes(q)
    q3 = float(q[2])
    return np.array([[q3 * E1[i], q3 * E2[i], e4[i]] for i in range(3)])


def point_bias(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """h = J̇ q̇ = p̈ − J q̈ (3,) [m/s²]:
    h = 2 q̇3 (E1 q̇1 + E2 q̇2) + q3 (E11 q̇1² + 2 E12 q̇1 q̇2 − e4 q̇2²)."""
    e4, E1, E2, E11, E12 = _axes(q)
    q3, w1, w2, w3 = float(q[2]), float(v[0]), float(v[1]), float(v[2])
    return np.array([
        2.0 * w3 * (E1[i] * w1 + E2[i] * w2)
        + q3 * (E11[i] * w1**2 + 2.0 * E12[i] * w1 * w2 - e4[i] * w2**2)
        for i in range(3)
    ])  # fmt: skip


def point_kinematics(q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """p, J and h of :func:`point_position`, :func:`point_jacobian`, :func:`point_bias`
    vectorised over states q (N, ≥3), q̇ (N, ≥3): (N, 3), (N, 3, 3), (N, 3) [m, m/rad,
    m/s²] (output samples of a simulation): the same formulas, equal to rounding (p and J
    bit for bit, h within a few ulp; tests)."""
    q1, q2, q3 = q[:, 0], q[:, 1], q[:, 2]
    w1, w2, w3 = v[:, 0], v[:, 1], v[:, 2]
    s1, c1, s2, c2 = np.sin(q1), np.cos(q1), np.sin(q2), np.cos(q2)
    zero = np.zeros_like(q1)
    e4 = np.stack([s2, -s1 * c2, c1 * c2], axis=1)
    E1 = np.stack([zero, -c1 * c2, -s1 * c2], axis=1)
    E2 = np.stack([c2, s1 * s2, -c1 * s2], axis=1)
    E11 = np.stack([zero, s1 * c2, -c1 * c2], axis=1)
    E12 = np.stack([zero, c1 * s2, s1 * s2], axis=1)
    qq, ww1, ww2, ww3 = q3[:, None], w1[:, None], w2[:, None], w3[:, None]
    p = qq * e4
    J = np.stack([qq * E1, qq * E2, e4], axis=2)
    h = 2.0 * ww3 * (E1 * ww1 + E2 * ww2) + qq * (
        E11 * ww1**2 + 2.0 * E12 * ww1 * ww2 - e4 * ww2**2
    )
    return p, J, h


def point_ik(p: np.ndarray) -> np.ndarray:
    """(q1, q2, q3) of the principal branch for a tool-centre position p (3,) [m].

    Raises:
        InvalidInputError: p is not 3 finite numbers.
        SingularConfigurationError: p at A (q3 = 0) or on the x axis (cos q2 = 0).
    """
    p = np.asarray(p, dtype=float)
    if p.shape != (3,) or not np.all(np.isfinite(p)):
        raise InvalidInputError(f"p must be 3 finite numbers [m]; got {p!r}")
    rho = float(np.hypot(p[1], p[2]))
    r = float(np.linalg.norm(p))
    if r < 1e-9 or rho < 1e-9 * r:
        raise SingularConfigurationError(
            f"tool centre {p} is at A or on the x axis (q3 = 0 or cos q2 = 0); "
            "valid: a point with y**2 + z**2 > 0"
        )
    return np.array([np.arctan2(-p[1], p[2]), np.arctan2(p[0], rho), r])


def joint_reference(
    traj: CartesianTrajectory, t: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(q, q̇, q̈) of q1..q3 following ``traj`` at time t, by the inverse kinematics.

    q̇ = J⁻¹ ṗ, q̈ = J⁻¹(p̈ − h(q, q̇)).
    """
    q = point_ik(traj.position(t))
    J = point_jacobian(q)
    qd = np.linalg.solve(J, traj.velocity(t))
    qdd = np.linalg.solve(J, traj.acceleration(t) - point_bias(q, qd))
    return q, qd, qdd


__all__ = [
    "joint_reference",
    "point_bias",
    "point_ik",
    "point_jacobian",
    "point_kinematics",
    "point_position",
]
