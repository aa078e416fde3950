"""Velocity and acceleration problems of a serial Mechanism, through Pinocchio.

Forward: (q, q̇, q̈) -> tool-centre velocity v and acceleration a [m/s, m/s²], tool
angular velocity ω and acceleration ε [rad/s, rad/s²], all in world axes.
Inverse: (v, ω, a, ε) -> (q̇, q̈) by J·q̇ = [v; ω] and J·q̈ = [a; ε] − J̇·q̇, with ω and ε
given directly or from the papers' absolute angles α, β, γ (R = Rz(γ)·Ry(β)·Rx(α),
:func:`omega_from_angle_rates`). J and J̇ come from :mod:`rcm_pin.analysis.jacobians`; a
family may pass its closed-form J to :func:`solve_task` (e.g. the RCM mechanisms,
:mod:`rcm_pin.mechanisms.rcm.velocity`). A rank-deficient J raises
:class:`~rcm_pin.errors.SingularConfigurationError` naming the family's cause.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike

from rcm_pin.analysis.jacobians import LWA, tool_jacobian
from rcm_pin.analysis.singularity_model import singularity_model
from rcm_pin.errors import InvalidInputError, SingularConfigurationError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.rotations import FloatArray, as_finite, check_magnitude, rot_y, rot_z

#: Relative residual above which an over-determined inverse problem (4-DOF with ω) is
#: declared not realisable.
RESIDUAL_TOL = 1e-9
#: Relative rank tolerance of the task Jacobian (as :data:`rcm_pin.analysis.singularity.RANK_TOL`).
RANK_TOL = 1e-9


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


def _vec(x: ArrayLike, n: int, name: str) -> FloatArray:
    """A checked (n,) vector: numeric, finite and within ``MAX_ABS`` (no overflow later)."""
    return check_magnitude(as_finite(x, name, (n,)), name)


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
    q = mech.check_q(q)
    qd = mech.check_v(qd, "qd")
    qdd = np.zeros(mech.nv) if qdd is None else mech.check_v(qdd, "qdd")
    v, a = mech.v_pin(qd), mech.v_pin(qdd)
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


def solve_task(mech: Mechanism, q: FloatArray, J: FloatArray, rhs: FloatArray) -> FloatArray:
    """Solve J·x = rhs (rows of the task); singular -> typed error naming the cause."""
    s = np.linalg.svd(J, compute_uv=False)
    rank = int(np.sum(s > RANK_TOL * max(s[0], 1e-300)))
    if rank < min(J.shape):
        causes = singularity_model(mech).causes(mech, q)
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


def task_target(
    v: ArrayLike,
    omega: ArrayLike | None,
    names: tuple[str, str] = ("v", "omega"),
) -> FloatArray:
    """[v] or [v; ω] as one finite vector (3,) or (6,)."""
    first = _vec(v, 3, names[0])
    return first if omega is None else np.r_[first, _vec(omega, 3, names[1])]


def inverse_velocity(
    mech: Mechanism, q: ArrayLike, v: ArrayLike, omega: ArrayLike | None = None
) -> FloatArray:
    """Inverse velocity problem: q̇ from the tool-centre velocity (and ω).

    Solves J_task·q̇ = [v; ω] (rows [v] only when ``omega`` is None: minimum-norm q̇,
    i.e. zero wrist rates for the RCM mechanisms), J from Pinocchio.

    Raises:
        SingularConfigurationError: J_task rank-deficient (message names the cause).
        InvalidInputError: ω not realisable (4-DOF), bad shapes.
    """
    q = mech.check_q(q)
    rhs = task_target(v, omega)
    return solve_task(mech, q, tool_jacobian(mech, q)[: rhs.size], rhs)


def inverse_acceleration(
    mech: Mechanism,
    q: ArrayLike,
    qd: ArrayLike,
    a: ArrayLike,
    epsilon: ArrayLike | None = None,
) -> FloatArray:
    """Inverse acceleration problem: q̈ from J·q̈ = [a; ε] − J̇·q̇ (J̇·q̇ from the classical
    acceleration at q̈ = 0).

    Raises:
        SingularConfigurationError: J_task rank-deficient (message names the cause).
    """
    q = mech.check_q(q)
    qd = mech.check_v(qd, "qd")
    target = task_target(a, epsilon, ("a", "e"))
    m = forward(mech, q, qd, None)
    bias = np.r_[m.a, m.epsilon][: target.size]
    return solve_task(mech, q, tool_jacobian(mech, q)[: target.size], target - bias)


__all__ = [
    "RANK_TOL",
    "RESIDUAL_TOL",
    "ToolMotion",
    "forward",
    "inverse_acceleration",
    "inverse_velocity",
    "omega_from_angle_rates",
    "solve_task",
    "task_target",
]
