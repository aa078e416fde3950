"""Closed-form forward kinematics of the RCM mechanisms (papers 000/003).

The independent route that the tests compare Pinocchio against: pure numpy, no
Pinocchio import, vectorised over leading dimensions (``q`` of shape ``(..., n)`` with
n = 6 for the six-DOF mechanisms and n = 4 for ``rcm_bevel_4dof``).

Coordinates q = (q1, q2, q3, q4, q5, q6): q1, q2, q4, q5, q6 in [rad], q3 in [m]. The
remote centre A is the world origin. Formulas (docs/conventions.md)::

    R_out = Rx(q1)·Ry(q2)                              output link 2
    e4    = R_out·z = [sin q2, −sin q1 cos q2, cos q1 cos q2]
    p     = q3·e4                                      tool centre
    R     = R_out·Rz(q4)·Ry(q5)·Rz(q6)                 wrist_type "zyz" (default)
    R     = R_out·Rz(q4)·Ry(q5)·Rx(q6)                 wrist_type "rpy"
    R     = R_out·Rz(q4)                               wrist_type None (4-DOF)

Paper errata (000): the printed element A_x1 = −(c6(s2 s5 − c2 c4 c5) − c2 s4 s6) has a
sign typo in its last term; the product above gives A_x1 = c6(c2 c4 c5 − s2 s5) − c2 s4 s6.
The printed e5 = [−c2 s4, c1 c4 − s1 s2 s4, c4 s1 − c1 s2 s4] has a sign typo in the
third component (as printed it is not a unit vector); the correct one is
e5 = [−c2 s4, c1 c4 − s1 s2 s4, s1 c4 + c1 s2 s4] = R_out·Rz(q4)·y.
"""

from __future__ import annotations

from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from rcm_pin.errors import InvalidInputError
from rcm_pin.rotations import FloatArray, as_finite, rot_x, rot_y, rot_z

WristType = Literal["zyz", "rpy"] | None
WRIST_TYPES: tuple[WristType, ...] = ("zyz", "rpy", None)


def wrist_type(mech: Any) -> WristType:
    """``"zyz"`` or ``"rpy"`` for a six-DOF RCM mechanism (its ``wrist_type`` xacro
    argument), None without a wrist."""
    if mech.nq < 6:
        return None
    return "rpy" if mech.args.get("wrist_type", "zyz") == "rpy" else "zyz"


def check_q(q: ArrayLike, wrist_type: WristType) -> FloatArray:
    """Validate a configuration array for a wrist type.

    Args:
        q: Configurations, shape ``(..., n)``.
        wrist_type: ``"zyz"`` or ``"rpy"`` (n = 6) or ``None`` (4-DOF, n = 4).

    Returns:
        ``q`` as a float64 array.

    Raises:
        InvalidInputError: Unknown wrist type, wrong last dimension, NaN / inf.
    """
    if wrist_type not in WRIST_TYPES:
        raise InvalidInputError(f"wrist_type must be 'zyz', 'rpy' or None, got {wrist_type!r}")
    n = 4 if wrist_type is None else 6
    return as_finite(q, "q", (n,))


def output_axis(q1: ArrayLike, q2: ArrayLike) -> FloatArray:
    """Output axis e4 = Rx(q1)·Ry(q2)·z = [sin q2, −sin q1 cos q2, cos q1 cos q2].

    Args:
        q1: Platform angle [rad].
        q2: Initial-link angle [rad] (broadcasts with ``q1``).

    Returns:
        Unit vectors, shape ``(..., 3)``.
    """
    a1, a2 = np.broadcast_arrays(np.asarray(q1, float), np.asarray(q2, float))
    c1, s1, c2, s2 = np.cos(a1), np.sin(a1), np.cos(a2), np.sin(a2)
    return np.stack([s2, -s1 * c2, c1 * c2], axis=-1)


def tool_position(q: ArrayLike) -> FloatArray:
    """Tool centre p = q3·e4: x = q3 sin q2, y = −q3 sin q1 cos q2, z = q3 cos q1 cos q2.

    Args:
        q: Configurations ``(..., n)``, n ≥ 3 (only q1, q2, q3 are used).

    Returns:
        Positions [m], shape ``(..., 3)``.
    """
    a = as_finite(q, "q")
    if a.ndim < 1 or a.shape[-1] < 3:
        raise InvalidInputError(f"q must have shape (..., n) with n >= 3, got {a.shape}")
    return a[..., 2, None] * output_axis(a[..., 0], a[..., 1])


def output_rotation(q1: ArrayLike, q2: ArrayLike) -> FloatArray:
    """Orientation of output link 2, R_out = Rx(q1)·Ry(q2).

    Args:
        q1: Platform angle [rad].
        q2: Initial-link angle [rad].

    Returns:
        Rotation matrices ``(..., 3, 3)``.
    """
    return rot_x(q1) @ rot_y(q2)


def tool_rotation(q: ArrayLike, wrist_type: WristType = "zyz") -> FloatArray:
    """Tool orientation R (see the module docstring for the three wrist types).

    Args:
        q: Configurations ``(..., 6)`` (``"zyz"``, ``"rpy"``) or ``(..., 4)`` (``None``).
        wrist_type: ``"zyz"`` (default, Rz·Ry·Rz wrist), ``"rpy"`` (Rz·Ry·Rx) or ``None``.

    Returns:
        Rotation matrices ``(..., 3, 3)``.
    """
    a = check_q(q, wrist_type)
    r = output_rotation(a[..., 0], a[..., 1]) @ rot_z(a[..., 3])
    if wrist_type is None:
        return r
    last = rot_z(a[..., 5]) if wrist_type == "zyz" else rot_x(a[..., 5])
    return r @ rot_y(a[..., 4]) @ last


def tool_pose(q: ArrayLike, wrist_type: WristType = "zyz") -> FloatArray:
    """Homogeneous tool pose [[R, p], [0, 1]] in the world (RCM) frame.

    Args:
        q: Configurations ``(..., 6)`` or ``(..., 4)`` (``wrist_type=None``).
        wrist_type: ``"zyz"``, ``"rpy"`` or ``None``.

    Returns:
        Transforms ``(..., 4, 4)`` (rotation, position [m]).
    """
    a = check_q(q, wrist_type)
    out = np.zeros((*a.shape[:-1], 4, 4))
    out[..., :3, :3] = tool_rotation(a, wrist_type)
    out[..., :3, 3] = tool_position(a)
    out[..., 3, 3] = 1.0
    return out


def joint_axes(q: ArrayLike, wrist_type: WristType = "zyz") -> FloatArray:
    """Pair axes in the world frame: row i is the axis of coordinate q_{i+1}.

    - e1 = [1, 0, 0] (pair 4), e2 = Rx(q1)·y = [0, cos q1, sin q1] (pair 7);
    - row 3 is the translation direction of the prismatic pair 24, i.e. e4 (the paper
      sets e3 = 0 in the angular-velocity sum, since a prismatic pair adds no rotation);
    - e4 = [sin q2, −sin q1 cos q2, cos q1 cos q2] (pair 23);
    - e5 = R_out·Rz(q4)·y = [−c2 s4, c1 c4 − s1 s2 s4, s1 c4 + c1 s2 s4] (pair 26; the
      printed third component has a sign typo, see the module docstring);
    - e6 = R·z (``"zyz"``) or R·x (``"rpy"``, the paper's [cβ cγ, cβ sγ, −sβ]) (pair 27).

    Args:
        q: Configurations ``(..., 6)`` or ``(..., 4)`` (``wrist_type=None``).
        wrist_type: ``"zyz"``, ``"rpy"`` or ``None``.

    Returns:
        Unit axes, shape ``(..., n, 3)`` with n = 6 or 4.
    """
    a = check_q(q, wrist_type)
    c1, s1 = np.cos(a[..., 0]), np.sin(a[..., 0])
    c2, s2 = np.cos(a[..., 1]), np.sin(a[..., 1])
    c4, s4 = np.cos(a[..., 3]), np.sin(a[..., 3])
    zero, one = np.zeros_like(c1), np.ones_like(c1)
    e1 = np.stack([one, zero, zero], axis=-1)
    e2 = np.stack([zero, c1, s1], axis=-1)
    e4 = np.stack([s2, -s1 * c2, c1 * c2], axis=-1)
    axes = [e1, e2, e4, e4]
    if wrist_type is not None:
        e5 = np.stack([-c2 * s4, c1 * c4 - s1 * s2 * s4, s1 * c4 + c1 * s2 * s4], axis=-1)
        r = tool_rotation(a, wrist_type)
        e6 = r[..., :, 2] if wrist_type == "zyz" else r[..., :, 0]
        axes += [e5, e6]
    return np.stack(axes, axis=-2)


__all__ = [
    "WRIST_TYPES",
    "WristType",
    "check_q",
    "joint_axes",
    "output_axis",
    "output_rotation",
    "tool_pose",
    "tool_position",
    "tool_rotation",
    "wrist_type",
]
