"""Velocity and acceleration problems of the RCM mechanisms (paper 000), two routes.

Forward: (q, q̇, q̈) -> tool-centre velocity v and acceleration a [m/s, m/s²], tool
angular velocity ω and acceleration ε [rad/s, rad/s²], all in world axes (A = origin).
Inverse: (v, ω, a, ε) -> (q̇, q̈), ω and ε given directly or from the papers' absolute
angles α, β, γ (R = Rz(γ)·Ry(β)·Rx(α), :func:`omega_from_angle_rates`).

Route 1 (Pinocchio, any Mechanism): ``J = getFrameJacobian(tool, LOCAL_WORLD_ALIGNED)``
(rows [v; ω]), the classical acceleration ``getFrameClassicalAcceleration`` and the
Jacobian time variation J̇ with a = J·q̈ + J̇·q̇.

**Pinocchio 4.1 on mimic models**: ``getFrameJacobian`` (every reference frame) and
``getFrameClassicalAcceleration`` agree with the no-mimic model projected through the
coupling (J = J_full·Gv) to 1e-16, but ``getFrameJacobianTimeVariation`` after
``computeJointJacobiansTimeVariation`` is wrong in ``LOCAL`` and ``LOCAL_WORLD_ALIGNED``
(errors of order 1 in the linear rows of the columns after the mimic joints); the
``WORLD`` variant is right. :func:`jacobian_derivative` therefore takes J̇ in ``WORLD``
and shifts it to the tool centre p itself:

    J_lwa = X·J_w,  X = [[I, −[p]×], [0, I]],   J̇_lwa = X·J̇_w + [[0, −[ṗ]×], [0, 0]]·J_w.

Route 2 (closed form, RCM mechanisms, pure numpy): the paper's differentiated position
equations x = q3 sin q2, y = −q3 sin q1 cos q2, z = q3 cos q1 cos q2, ω = Σ q̇i ei
(e3 = 0, prismatic) and ε = Σ q̈i ei + Σ_{j<i} ωj × ωi with ωi = q̇i ei.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike

from rcm_pin.closed_form import WristType, check_q, joint_axes, output_axis
from rcm_pin.errors import InvalidInputError, SingularConfigurationError
from rcm_pin.mechanism import Mechanism
from rcm_pin.rotations import FloatArray, as_finite, rot_y, rot_z

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
#: Relative residual above which an over-determined inverse problem (4-DOF with ω) is
#: declared not realisable.
RESIDUAL_TOL = 1e-9


@dataclass(frozen=True)
class ToolMotion:
    """Tool-centre motion in world axes.

    Attributes:
        v: linear velocity of the tool centre [m/s].
        omega: angular velocity of the tool [rad/s].
        a: classical (not spatial) acceleration of the tool centre [m/s²].
        epsilon: angular acceleration [rad/s²].
    """

    v: FloatArray
    omega: FloatArray
    a: FloatArray
    epsilon: FloatArray


def v_index(mech: Mechanism) -> np.ndarray:
    """Pinocchio v index of each Mechanism coordinate."""
    return np.array([mech.model.joints[mech.model.getJointId(j)].idx_v for j in mech.joint_names])


def _vec(x: ArrayLike, n: int, name: str) -> FloatArray:
    return as_finite(x, name, (n,))


def tool_jacobian(mech: Mechanism, q: ArrayLike) -> FloatArray:
    """Tool Jacobian (6, n), rows [v; ω] of the tool centre, LOCAL_WORLD_ALIGNED.

    Args:
        mech: the mechanism.
        q: coordinates (n,) [rad, m].

    Returns:
        J with [v; ω] = J·q̇, columns in Mechanism order.
    """
    q = mech.check_q(np.asarray(q, dtype=float))
    pin.computeJointJacobians(mech.model, mech.data, mech.to_pin(q))
    pin.updateFramePlacements(mech.model, mech.data)
    J = pin.getFrameJacobian(mech.model, mech.data, mech.tool_frame_id, LWA)
    return np.asarray(J[:, v_index(mech)], dtype=float)


def jacobian_derivative(mech: Mechanism, q: ArrayLike, qd: ArrayLike) -> FloatArray:
    """Time derivative J̇ (6, n) of :func:`tool_jacobian` along q̇ (WORLD route, see module).

    Args:
        mech: the mechanism.
        q: coordinates (n,) [rad, m].
        qd: coordinate rates (n,) [rad/s, m/s].

    Returns:
        J̇ such that a = J·q̈ + J̇·q̇ (classical acceleration of the tool centre).
    """
    q = mech.check_q(np.asarray(q, dtype=float))
    qd = mech.check_q(np.asarray(qd, dtype=float), "qd")
    model, data, fid = mech.model, mech.data, mech.tool_frame_id
    vpin = np.zeros(model.nv)
    idx = v_index(mech)
    vpin[idx] = qd
    pin.computeJointJacobiansTimeVariation(model, data, mech.to_pin(q), vpin)
    pin.updateFramePlacements(model, data)
    Jw = pin.getFrameJacobian(model, data, fid, pin.ReferenceFrame.WORLD)
    dJw = pin.getFrameJacobianTimeVariation(model, data, fid, pin.ReferenceFrame.WORLD)
    p = data.oMf[fid].translation
    out = dJw.copy()
    out[:3] -= np.cross(p, dJw[3:].T).T  # X·J̇_w: v_p = v_o + ω × p = v_o − p × ω
    pd = (Jw[:3] - np.cross(p, Jw[3:].T).T) @ vpin  # tool-centre velocity ṗ
    out[:3] -= np.cross(pd, Jw[3:].T).T
    return np.asarray(out[:, idx], dtype=float)


def forward(
    mech: Mechanism, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike | None = None
) -> ToolMotion:
    """Forward velocity and acceleration problem through Pinocchio.

    Args:
        mech: any Mechanism with a tool frame.
        q: coordinates (n,) [rad, m].
        qd: rates (n,) [rad/s, m/s].
        qdd: accelerations (n,) [rad/s², m/s²]; zero when None.

    Returns:
        :class:`ToolMotion` from ``getFrameVelocity`` and ``getFrameClassicalAcceleration``
        (LOCAL_WORLD_ALIGNED).
    """
    q = mech.check_q(np.asarray(q, dtype=float))
    qd = mech.check_q(np.asarray(qd, dtype=float), "qd")
    qdd = np.zeros(mech.nq) if qdd is None else mech.check_q(np.asarray(qdd, float), "qdd")
    idx = v_index(mech)
    v, a = np.zeros(mech.model.nv), np.zeros(mech.model.nv)
    v[idx], a[idx] = qd, qdd
    pin.forwardKinematics(mech.model, mech.data, mech.to_pin(q), v, a)
    pin.updateFramePlacements(mech.model, mech.data)
    vel = pin.getFrameVelocity(mech.model, mech.data, mech.tool_frame_id, LWA)
    acc = pin.getFrameClassicalAcceleration(mech.model, mech.data, mech.tool_frame_id, LWA)
    return ToolMotion(
        v=np.array(vel.linear),
        omega=np.array(vel.angular),
        a=np.array(acc.linear),
        epsilon=np.array(acc.angular),
    )


# ----------------------------------------------------------------- closed form


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


# ----------------------------------------------------------- absolute angles


def omega_from_angle_rates(
    angles: ArrayLike, rates: ArrayLike, accels: ArrayLike | None = None
) -> tuple[FloatArray, FloatArray]:
    """ω and ε from the papers' absolute angles, R = Rz(γ)·Ry(β)·Rx(α).

    ω = γ̇ z + β̇ Rz(γ) y + α̇ Rz(γ) Ry(β) x, and ε = dω/dt
      = γ̈ ez + β̈ ey' + α̈ ex'' + (γ̇ ez) × (β̇ ey') + (γ̇ ez + β̇ ey') × (α̇ ex'').

    Args:
        angles: (α, β, γ) [rad].
        rates: (α̇, β̇, γ̇) [rad/s].
        accels: (α̈, β̈, γ̈) [rad/s²]; zero when None.

    Returns:
        (ω [rad/s], ε [rad/s²]), each (3,).
    """
    _, be, ga = _vec(angles, 3, "angles")  # R does not depend on α here
    r = _vec(rates, 3, "rates")
    acc = np.zeros(3) if accels is None else _vec(accels, 3, "accels")
    ez = np.array([0.0, 0.0, 1.0])
    ey = rot_z(ga) @ np.array([0.0, 1.0, 0.0])
    ex = rot_z(ga) @ rot_y(be) @ np.array([1.0, 0.0, 0.0])
    wz, wy, wx = r[2] * ez, r[1] * ey, r[0] * ex
    omega = wx + wy + wz
    eps = acc[2] * ez + acc[1] * ey + acc[0] * ex + np.cross(wz, wy) + np.cross(wz + wy, wx)
    return omega, eps


# ------------------------------------------------------------------- inverse


def _jacobian(mech: Mechanism, q: FloatArray, route: str) -> FloatArray:
    if route == "pinocchio":
        return tool_jacobian(mech, q)
    if route == "closed_form":
        _require_rcm(mech)
        return closed_form_jacobian(q, mech.wrist_type)
    raise InvalidInputError(f"route {route!r}; valid: 'pinocchio', 'closed_form'")


def _require_rcm(mech: Mechanism) -> None:
    if mech.rcm_frame_id < 0:
        raise InvalidInputError(
            f"the closed form needs an RCM mechanism, got {mech.name}; valid: rcm_bevel, "
            "rcm_bevel_4dof, rcm_belt"
        )


def _solve(mech: Mechanism, q: FloatArray, J: FloatArray, rhs: FloatArray) -> FloatArray:
    """Solve J·x = rhs (rows of the task); singular -> typed error naming the cause."""
    from rcm_pin.singularity import RANK_TOL, classify

    s = np.linalg.svd(J, compute_uv=False)
    rank = int(np.sum(s > RANK_TOL * max(s[0], 1e-300)))
    if rank < min(J.shape):
        causes = classify(mech, q) if mech.rcm_frame_id >= 0 else []
        named = "; ".join(f"{c.description} ({c.condition})" for c in causes) or "rank loss"
        raise SingularConfigurationError(
            f"{mech.name} is singular at q = {np.round(q, 6).tolist()}: Jacobian rank "
            f"{rank} < {min(J.shape)} (sigma_min/sigma_max = {s[-1] / s[0]:.3g} <= "
            f"{RANK_TOL:g}); cause: {named}"
        )
    x, *_ = np.linalg.lstsq(J, rhs, rcond=None)
    res = np.linalg.norm(J @ x - rhs)
    if J.shape[0] > J.shape[1] and res > RESIDUAL_TOL * max(1.0, float(np.linalg.norm(rhs))):
        raise InvalidInputError(
            f"the requested tool motion is not realisable by {mech.name} ({mech.nq} DOF): "
            f"least-squares residual {res:.3g}; valid: omega in the span of the pair axes"
        )
    return np.asarray(x, dtype=float)


def inverse_velocity(
    mech: Mechanism,
    q: ArrayLike,
    v: ArrayLike,
    omega: ArrayLike | None = None,
    route: str = "pinocchio",
) -> FloatArray:
    """Inverse velocity problem: q̇ from the tool-centre velocity (and ω).

    Solves J_task·q̇ = [v; ω] (rows [v] only when ``omega`` is None: minimum-norm q̇,
    i.e. zero wrist rates for the RCM mechanisms).

    Args:
        mech: the mechanism.
        q: coordinates (n,) [rad, m].
        v: tool-centre velocity (3,) [m/s].
        omega: tool angular velocity (3,) [rad/s], or None.
        route: ``"pinocchio"`` or ``"closed_form"`` (RCM mechanisms).

    Returns:
        q̇ (n,) [rad/s, m/s].

    Raises:
        SingularConfigurationError: J_task rank-deficient (message names the cause).
        InvalidInputError: ω not realisable (4-DOF), bad shapes.
    """
    q = mech.check_q(np.asarray(q, dtype=float))
    rhs = _vec(v, 3, "v") if omega is None else np.r_[_vec(v, 3, "v"), _vec(omega, 3, "omega")]
    J = _jacobian(mech, q, route)[: rhs.size]
    return _solve(mech, q, J, rhs)


def inverse_acceleration(
    mech: Mechanism,
    q: ArrayLike,
    qd: ArrayLike,
    a: ArrayLike,
    epsilon: ArrayLike | None = None,
    route: str = "pinocchio",
) -> FloatArray:
    """Inverse acceleration problem: q̈ from J·q̈ = [a; ε] − J̇·q̇.

    Args:
        mech: the mechanism.
        q: coordinates (n,) [rad, m].
        qd: rates (n,) [rad/s, m/s] (from :func:`inverse_velocity`).
        a: tool-centre acceleration (3,) [m/s²].
        epsilon: angular acceleration (3,) [rad/s²], or None (position rows only).
        route: ``"pinocchio"`` (J̇·q̇ from the classical acceleration at q̈ = 0) or
            ``"closed_form"`` (the bias from :func:`closed_form_forward` at q̈ = 0).

    Returns:
        q̈ (n,) [rad/s², m/s²].

    Raises:
        SingularConfigurationError: J_task rank-deficient (message names the cause).
    """
    q = mech.check_q(np.asarray(q, dtype=float))
    qd = mech.check_q(np.asarray(qd, dtype=float), "qd")
    target = _vec(a, 3, "a") if epsilon is None else np.r_[_vec(a, 3, "a"), _vec(epsilon, 3, "e")]
    if route == "closed_form":
        _require_rcm(mech)
        m = closed_form_forward(q, qd, None, mech.wrist_type)
    else:
        m = forward(mech, q, qd, None)
    bias = np.r_[m.a, m.epsilon][: target.size]
    J = _jacobian(mech, q, route)[: target.size]
    return _solve(mech, q, J, target - bias)


__all__ = [
    "LWA",
    "ToolMotion",
    "closed_form_forward",
    "closed_form_jacobian",
    "coupling_terms",
    "forward",
    "inverse_acceleration",
    "inverse_velocity",
    "jacobian_derivative",
    "omega_from_angle_rates",
    "tool_jacobian",
    "v_index",
]
