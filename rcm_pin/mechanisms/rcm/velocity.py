"""Velocity and acceleration problems of the RCM mechanisms by the papers' formulas.

The second route beside Pinocchio (:mod:`rcm_pin.analysis.velocity`): the differentiated
position equations x = q3 sin q2, y = −q3 sin q1 cos q2, z = q3 cos q1 cos q2, ω = Σ q̇i ei
(e3 = 0, prismatic) and ε = Σ q̈i ei + Σ_{j<i} ωj × ωi with ωi = q̇i ei (paper 000).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from rcm_pin.analysis.velocity import ToolMotion, solve_task, task_target
from rcm_pin.errors import InvalidInputError
from rcm_pin.mechanisms.rcm.closed_form import (
    WristType,
    check_q,
    joint_axes,
    output_axis,
    wrist_type,
)
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.rotations import FloatArray


def closed_form_jacobian(q: ArrayLike, wrist_type: WristType = "zyz") -> FloatArray:
    """Closed-form tool Jacobian (..., 6, n): rows ∂p/∂q and the pair axes ei (e3 = 0).

    With e4 = [s2, −s1 c2, c1 c2]: ∂p/∂q1 = q3·[0, −c1 c2, −s1 c2],
    ∂p/∂q2 = q3·[c2, s1 s2, −c1 s2], ∂p/∂q3 = e4, ∂p/∂q4..6 = 0 (wrist centre = tool
    centre).

    Args:
        q: configurations (..., 6) or (..., 4) (``wrist_type=None``) [rad, m].
        wrist_type: ``"zyz"``, ``"rpy"`` or None.

    Returns:
        J, shape (..., 6, n).
    """
    a = check_q(q, wrist_type)
    c1, s1, c2, s2, q3 = (
        np.cos(a[..., 0]),
        np.sin(a[..., 0]),
        np.cos(a[..., 1]),
        np.sin(a[..., 1]),
        a[..., 2],
    )
    n = a.shape[-1]
    J = np.zeros((*a.shape[:-1], 6, n))
    J[..., :3, 0] = np.stack([0 * c1, -c1 * c2, -s1 * c2], axis=-1) * q3[..., None]
    J[..., :3, 1] = np.stack([c2, s1 * s2, -c1 * s2], axis=-1) * q3[..., None]
    J[..., :3, 2] = output_axis(a[..., 0], a[..., 1])
    axes = joint_axes(a, wrist_type)
    axes[..., 2, :] = 0.0  # prismatic pair: no rotation
    J[..., 3:, :] = np.swapaxes(axes, -1, -2)
    return J


def closed_form_forward(
    q: ArrayLike, qd: ArrayLike, qdd: ArrayLike | None = None, wrist_type: WristType = "zyz"
) -> ToolMotion:
    """Forward velocity/acceleration problem by the papers' formulas (vectorised).

    Position (paper 000, with the corrected sign of the first term of dy/dt)::

        ẋ = q̇2 q3 c2 + q̇3 s2
        ẏ = −q̇1 q3 c1 c2 + q̇2 q3 s1 s2 − q̇3 s1 c2
        ż = −q̇1 q3 s1 c2 − q̇2 q3 c1 s2 + q̇3 c1 c2
        a = q̈3 e4 + 2 q̇3 ė4 + q3 ë4,   ë4 = Σ q̈k ∂k e4 + Σ q̇k q̇l ∂k∂l e4  (k, l ∈ {1, 2})

    Rotation: ω = Σ q̇i ei, ε = Σ q̈i ei + Σ_{j<i} (q̇j ej) × (q̇i ei).

    Args:
        q: configurations (..., n) [rad, m].
        qd: rates (..., n) [rad/s, m/s].
        qdd: accelerations (..., n) [rad/s², m/s²]; zero when None.
        wrist_type: ``"zyz"``, ``"rpy"`` or None.

    Returns:
        :class:`ToolMotion` with arrays of shape (..., 3).
    """
    a_ = check_q(q, wrist_type)
    qd_ = check_q(qd, wrist_type)
    qdd_ = np.zeros_like(qd_) if qdd is None else check_q(qdd, wrist_type)
    c1, s1, c2, s2 = np.cos(a_[..., 0]), np.sin(a_[..., 0]), np.cos(a_[..., 1]), np.sin(a_[..., 1])
    q3 = a_[..., 2, None]
    d1, d2, d3 = qd_[..., 0, None], qd_[..., 1, None], qd_[..., 2, None]
    z = 0 * c1
    e4 = np.stack([s2, -s1 * c2, c1 * c2], axis=-1)
    e4_1 = np.stack([z, -c1 * c2, -s1 * c2], axis=-1)  # ∂e4/∂q1
    e4_2 = np.stack([c2, s1 * s2, -c1 * s2], axis=-1)  # ∂e4/∂q2
    e4_11 = np.stack([z, s1 * c2, -c1 * c2], axis=-1)
    e4_12 = np.stack([z, c1 * s2, s1 * s2], axis=-1)
    e4_22 = np.stack([-s2, s1 * c2, -c1 * c2], axis=-1)
    e4d = d1 * e4_1 + d2 * e4_2
    e4dd = (
        qdd_[..., 0, None] * e4_1
        + qdd_[..., 1, None] * e4_2
        + d1 * d1 * e4_11
        + 2 * d1 * d2 * e4_12
        + d2 * d2 * e4_22
    )
    v = d3 * e4 + q3 * e4d
    acc = qdd_[..., 2, None] * e4 + 2 * d3 * e4d + q3 * e4dd
    axes = joint_axes(a_, wrist_type)
    axes[..., 2, :] = 0.0
    wi = qd_[..., :, None] * axes  # ωi = q̇i ei, (..., n, 3)
    omega = wi.sum(axis=-2)
    prior = np.cumsum(wi, axis=-2) - wi  # Σ_{j<i} ωj
    eps = (qdd_[..., :, None] * axes).sum(axis=-2) + np.cross(prior, wi).sum(axis=-2)
    return ToolMotion(v=v, omega=omega, a=acc, epsilon=eps)


def coupling_terms(q: ArrayLike, qd: ArrayLike, wrist_type: WristType = "zyz") -> FloatArray:
    """The paper's ε_{1-6} = Σ_{j<i} ωj × ωi [rad/s²] (angular acceleration at q̈ = 0)."""
    return closed_form_forward(q, qd, None, wrist_type).epsilon


def _require_rcm(mech: Mechanism) -> None:
    if mech.rcm is None or mech.family.name != "rcm":
        raise InvalidInputError(
            f"the closed form needs an RCM mechanism, got {mech.name}; valid: rcm_bevel, "
            "rcm_bevel_4dof, rcm_belt"
        )


def inverse_velocity(
    mech: Mechanism, q: ArrayLike, v: ArrayLike, omega: ArrayLike | None = None
) -> FloatArray:
    """q̇ from [v; ω] with the closed-form Jacobian (see the Pinocchio route's docstring)."""
    _require_rcm(mech)
    q = mech.check_q(q)
    rhs = task_target(v, omega)
    return solve_task(mech, q, closed_form_jacobian(q, wrist_type(mech))[: rhs.size], rhs)


def inverse_acceleration(
    mech: Mechanism, q: ArrayLike, qd: ArrayLike, a: ArrayLike, epsilon: ArrayLike | None = None
) -> FloatArray:
    """q̈ from [a; ε] with the closed-form Jacobian and bias (:func:`closed_form_forward`)."""
    _require_rcm(mech)
    q = mech.check_q(q)
    qd = mech.check_q(qd, "qd")
    target = task_target(a, epsilon, ("a", "e"))
    m = closed_form_forward(q, qd, None, wrist_type(mech))
    bias = np.r_[m.a, m.epsilon][: target.size]
    J = closed_form_jacobian(q, wrist_type(mech))[: target.size]
    return solve_task(mech, q, J, target - bias)


__all__ = [
    "closed_form_forward",
    "closed_form_jacobian",
    "coupling_terms",
    "inverse_acceleration",
    "inverse_velocity",
]
