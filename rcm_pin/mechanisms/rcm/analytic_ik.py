"""Vectorised analytic inverse kinematics of the RCM mechanisms, every branch.

Pure numpy (no Pinocchio); inverts :mod:`rcm_pin.mechanisms.rcm.closed_form`.

Position (p = q3·e4, e4 = [sin q2, −sin q1 cos q2, cos q1 cos q2]): with r = |p|,
ρ = sqrt(y² + z²) the principal branch is q1 = atan2(−y, z), q2 = atan2(x, ρ)
(cos q2 ≥ 0), q3 = r. As e4(q1 + π, π − q2) = e4 and e4(q1 + π, −q2) = e4(q1, q2 + π)
= −e4, the position branches k are (angles wrapped to (−π, π])::

    k = 0: (q1, q2, r)        k = 1: (q1 + π, π − q2, r)
    k = 2: (q1 + π, −q2, −r)  k = 3: (q1, q2 + π, −r)

Wrist: R_w = (Rx(q1)·Ry(q2))ᵀ·R = Rz(q4)·Ry(q5)·Rz(q6) (``"zyz"``, q5 ∈ [0, π], twin
(q4 + π, −q5, q6 + π)) or Rz(q4)·Ry(q5)·Rx(q6) (``"rpy"``, q5 ∈ [−π/2, π/2], twin
(q4 + π, π − q5, q6 + π)). Branches k = 1, 2, 3 reuse the k = 0 wrist through
Rx(q1 + π)·Ry(π − q2) = R_out·Rz(π), Rx(q1 + π)·Ry(−q2) = R_out·Rx(π) and
Rx(q1)·Ry(q2 + π) = R_out·Ry(π): only angle offsets. Branch index b = 2·k + w.

Degenerate poses are reported (:class:`Degeneracy`), never
resolved arbitrarily; undetermined coordinates are NaN. |p| ≤ ``pos_tol`` (1e-9 m) is
TOOL_AT_RCM; ρ ≤ ``sing_tol``·|p| (|cos q2| ≤ 1e-9) is AXIS_ALONG_BASE; |sin q5|
(``"zyz"``) or |cos q5| (``"rpy"``) ≤ ``sing_tol`` is WRIST_ALIGNED.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from rcm_pin.errors import InvalidInputError, UnreachablePoseError
from rcm_pin.mechanisms.rcm.closed_form import WRIST_TYPES, WristType
from rcm_pin.mechanisms.rcm.ik_scalar import ik_pose_one
from rcm_pin.mechanisms.rcm.ik_solutions import Degeneracy, IKSolutions
from rcm_pin.mechanisms.rcm.ik_tables import (
    _NEAR,
    _POS,
    _TABLE4,
    _TABLE6,
    AXIS_TOL,
    PI,
    POS_TOL,
    SING_TOL,
    Block,
    _as_poses,
    _expand,
    _position,
    _run,
)
from rcm_pin.rotations import ROTATION_TOL, FloatArray, rot_x, rot_y

_ZERO_CODE = np.zeros(1, dtype=np.int8)


def _wrist_near_aligned(
    c: FloatArray, a1: FloatArray, a2: FloatArray, a4: FloatArray, wrist: str
) -> FloatArray:
    """q6 near sin q5 = 0 (zyz) / cos q5 = 0 (rpy) from the well-conditioned q4 ± q6.

    zyz: Rw10 − Rw01 = (1 + c5) sin(q4 + q6), Rw00 + Rw11 = (1 + c5) cos(q4 + q6),
    Rw10 + Rw01 = (c5 − 1) sin(q4 − q6), Rw00 − Rw11 = (c5 − 1) cos(q4 − q6).
    rpy: Rw12 − Rw01 = (1 + s5) sin(q4 − q6), Rw11 + Rw02 = (1 + s5) cos(q4 − q6),
    Rw12 + Rw01 = (s5 − 1) sin(q4 + q6), Rw11 − Rw02 = (1 − s5) cos(q4 + q6).
    """
    rw = np.swapaxes(rot_x(a1) @ rot_y(a2), -1, -2) @ c.reshape(3, 4, -1)[:, :3].transpose(2, 0, 1)
    w = {f"{i}{j}": rw[:, i, j] for i in range(3) for j in range(3)}
    if wrist == "zyz":
        plus = w["22"] >= 0.0  # near q5 = 0: q4 + q6 well determined, else q4 − q6
        s = np.arctan2(w["10"] - w["01"], w["00"] + w["11"])
        d = np.arctan2(-(w["10"] + w["01"]), w["11"] - w["00"])
    else:
        plus = w["20"] >= 0.0  # s5 = −Rw20 ≤ 0: q4 + q6 well determined
        s = np.arctan2(-(w["12"] + w["01"]), w["11"] - w["02"])
        d = np.arctan2(w["12"] - w["01"], w["11"] + w["02"])
    q6 = np.where(plus, s - a4, a4 - d)
    return q6 - 2.0 * PI * np.ceil((q6 - PI) / (2.0 * PI))  # wrap to (−π, π]


def _block6(wrist: str, pos_tol: float, sing_tol: float) -> Block:
    j, k, m = (2, 0, 1) if wrist == "zyz" else (0, 2, 1)  # Rw columns read

    def block(c: FloatArray) -> tuple[list[FloatArray], np.ndarray]:
        a1, a2, r, rho, at_a, along = _position(c[3], c[7], c[11], pos_tol, sing_tol)
        ir, irho = 1.0 / r, 1.0 / rho
        ex, ey, ez = c[3] * ir, c[7] * ir, c[11] * ir  # e4 = p/r
        c1, s1, c2 = c[11] * irho, -c[7] * irho, rho * ir
        s1s2, c1s2 = s1 * ex, c1 * ex
        w2j = ex * c[j] + ey * c[4 + j] + ez * c[8 + j]  # Rw[2, j] = e4·R[:, j]
        w2k = ex * c[k] + ey * c[4 + k] + ez * c[8 + k]
        w2m = ex * c[m] + ey * c[4 + m] + ez * c[8 + m]
        w0j = c2 * c[j] + s1s2 * c[4 + j] - c1s2 * c[8 + j]  # Rw[0, j] = (R_out·x)·R[:, j]
        w1j = c1 * c[4 + j] + s1 * c[8 + j]  # Rw[1, j] = e2·R[:, j]
        h = np.sqrt(w0j * w0j + w1j * w1j)  # |sin q5| (zyz) or |cos q5| (rpy)
        a4 = np.arctan2(w1j, w0j)  # [rad]
        if wrist == "zyz":  # Rw[:, 2] = [c4 s5, s4 s5, c5], Rw[2, :2] = [−s5 c6, s5 s6]
            a5, a6 = np.arctan2(h, w2j), np.arctan2(w2m, -w2k)
        else:  # Rw[:, 0] = [c4 c5, s4 c5, −s5], Rw[2, 1:] = [c5 s6, c5 c6]
            a5, a6 = np.arctan2(-w2j, h), np.arctan2(w2m, w2k)
        code = np.zeros(len(r), dtype=np.int8)
        aligned = h <= sing_tol
        near = np.flatnonzero((h < _NEAR) & ~aligned)
        if near.size:
            a6[near] = _wrist_near_aligned(c[:12, near], a1[near], a2[near], a4[near], wrist)
        if at_a.any() or along.any() or aligned.any():
            code[aligned] = Degeneracy.WRIST_ALIGNED
            code[along] = Degeneracy.AXIS_ALONG_BASE
            code[at_a] = Degeneracy.TOOL_AT_RCM
            hh = np.sqrt(np.maximum(0.0, 1.0 - w2j * w2j))  # q5 needs only e4 when q1 is free
            a5[along] = (np.arctan2(hh, w2j) if wrist == "zyz" else np.arctan2(-w2j, hh))[along]
            a1[along] = np.nan
            a4[code != 0] = a6[code != 0] = np.nan
            a1[at_a] = a2[at_a] = a5[at_a] = np.nan
        return [a1, a2, r, a4, a5, a6], code

    return block


def ik_position(
    p: ArrayLike, q3_sign: int | None = None, pos_tol: float = POS_TOL, sing_tol: float = SING_TOL
) -> IKSolutions:
    """All (q1, q2, q3) with q3·e4(q1, q2) = p.

    Args:
        p: Tool-centre positions [m], shape ``(..., 3)``.
        q3_sign: ``None`` (4 branches k = 0..3), ``+1`` (k = 0, 1) or ``−1`` (k = 2, 3).
        pos_tol: |p| [m] at or below which the pose is TOOL_AT_RCM.
        sing_tol: |cos q2| at or below which the pose is AXIS_ALONG_BASE.

    Returns:
        :class:`IKSolutions` with q of shape ``(n_poses, 4 or 2, 3)``.
    """
    if q3_sign not in (None, 1, -1):
        raise InvalidInputError(f"q3_sign must be None, +1 or -1, got {q3_sign!r}")
    try:
        a = np.asarray(p, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"p must be a numeric array: {exc}") from None
    if a.ndim < 1 or a.shape[-1] != 3:
        raise InvalidInputError(f"p must have shape (..., 3), got {a.shape}")
    if not np.isfinite(a).all():
        raise InvalidInputError("p contains NaN or infinite entries")
    a = a.reshape(-1, 3)
    with np.errstate(divide="ignore", invalid="ignore"):
        a1, a2, r, _, at_a, along = _position(a[:, 0], a[:, 1], a[:, 2], pos_tol, sing_tol)
    code = np.where(at_a, Degeneracy.TOOL_AT_RCM, np.where(along, Degeneracy.AXIS_ALONG_BASE, 0))
    a1[along | at_a] = np.nan
    a2[at_a] = np.nan
    table = _POS if q3_sign is None else _POS[:2] if q3_sign > 0 else _POS[2:]
    buf = np.empty((3 * len(table), len(a)))
    _expand([a1, a2, r], table, buf)
    q = buf.reshape(len(table), 3, -1).transpose(2, 0, 1)
    return IKSolutions(q, code.astype(np.int8), np.zeros(len(a)), None)


def ik_pose(
    T: ArrayLike,
    wrist_type: WristType = "zyz",
    *,
    check_rotation: bool = True,
    rot_tol: float = ROTATION_TOL,
    pos_tol: float = POS_TOL,
    sing_tol: float = SING_TOL,
) -> IKSolutions:
    """All eight six-DOF solutions (4 position x 2 wrist branches) of tool poses.

    Args:
        T: Tool poses, shape ``(..., 4, 4)`` or ``(..., 3, 4)`` (position in [m]).
        wrist_type: ``"zyz"`` (default) or ``"rpy"``; ``None`` delegates to
            :func:`ik_pose_4dof`.
        check_rotation: Screen R (first-order distance to SO(3)); matrices farther than
            1e-12 are replaced by their SVD projection. ``False`` trusts the input.
        rot_tol: Largest accepted projection distance (see ``project_to_rotation``).
        pos_tol: |p| [m] at or below which the pose is TOOL_AT_RCM.
        sing_tol: Threshold on |cos q2| and on |sin q5| (zyz) / |cos q5| (rpy).

    Returns:
        :class:`IKSolutions`, q of shape ``(n_poses, 8, 6)`` (a transposed view).

    Raises:
        InvalidInputError: Wrong shape, NaN / infinite entries or bad last row.
        NotARotationError: Some R is farther than ``rot_tol`` from SO(3).
    """
    if wrist_type is None:
        return ik_pose_4dof(T, check_rotation=check_rotation, rot_tol=rot_tol, sing_tol=sing_tol)
    if wrist_type not in WRIST_TYPES:
        raise InvalidInputError(f"wrist_type must be 'zyz', 'rpy' or None, got {wrist_type!r}")
    if check_rotation and type(T) is np.ndarray and T.dtype == np.float64 and T.ndim == 2:
        fast = ik_pose_one(T, wrist_type, pos_tol, sing_tol) if T.shape[1] == 4 else None
        if fast is not None:  # one regular pose: scalar arithmetic (:mod:`.ik_scalar`)
            return IKSolutions(fast[0][None], _ZERO_CODE.copy(), np.array([fast[1]]), wrist_type)
    block = _block6(wrist_type, pos_tol, sing_tol)
    q, code, dist = _run(_as_poses(T), block, _TABLE6[wrist_type], check_rotation, rot_tol)
    return IKSolutions(q, code, dist, wrist_type)


def ik_pose_4dof(
    T: ArrayLike,
    *,
    check_rotation: bool = True,
    rot_tol: float = ROTATION_TOL,
    axis_tol: float = AXIS_TOL,
    sing_tol: float = SING_TOL,
) -> IKSolutions:
    """Both solutions of the four-DOF mechanism, R = Rx(q1)·Ry(q2)·Rz(q4), p = q3·e4.

    e4 is the tool z axis, so (q1, q2) come from the orientation (two branches,
    (q1, q2) and (q1 + π, π − q2)), q3 = p·e4 and q4 from the tool x axis. p = 0 is
    regular here; AXIS_ALONG_BASE (|cos q2| ≤ ``sing_tol``) leaves q1 and q4 NaN.

    Args:
        T: Tool poses ``(..., 4, 4)`` or ``(..., 3, 4)``.
        check_rotation: As in :func:`ik_pose`.
        rot_tol: As in :func:`ik_pose`.
        axis_tol: Largest distance [m] of p from the tool z axis through A.
        sing_tol: Threshold on |cos q2|.

    Returns:
        :class:`IKSolutions`, q of shape ``(n_poses, 2, 4)``.

    Raises:
        UnreachablePoseError: p is off the tool z axis by more than ``axis_tol``.
    """

    def block(c: FloatArray) -> tuple[list[FloatArray], np.ndarray]:
        ex, ey, ez = c[2], c[6], c[10]  # e4 = R·z
        rho = np.sqrt(ey * ey + ez * ez)
        a1, a2 = np.arctan2(-ey, ez), np.arctan2(ex, rho)
        q3 = c[3] * ex + c[7] * ey + c[11] * ez  # [m]
        off = np.sqrt((c[3] - q3 * ex) ** 2 + (c[7] - q3 * ey) ** 2 + (c[11] - q3 * ez) ** 2)
        if off.max() > axis_tol:
            i = int(off.argmax())
            raise UnreachablePoseError(
                f"4-DOF pose unreachable: the tool centre is {off[i]:.3g} m off the tool z "
                f"axis through A (tolerance {axis_tol:g} m; block index {i}); "
                "the tool z axis must lie along ±e4 = ±p/|p|"
            )
        c1, s1 = ez / rho, -ey / rho
        w00 = rho * c[0] + s1 * ex * c[4] - c1 * ex * c[8]  # (R_out·x)·R[:, 0]
        w10 = c1 * c[4] + s1 * c[8]  # e2·R[:, 0]
        a4 = np.arctan2(w10, w00)
        along = rho <= sing_tol
        a1[along] = a4[along] = np.nan
        return [a1, a2, q3, a4], np.where(along, Degeneracy.AXIS_ALONG_BASE, 0).astype(np.int8)

    q, code, dist = _run(_as_poses(T), block, _TABLE4, check_rotation, rot_tol)
    return IKSolutions(q, code, dist, None)


__all__ = ["AXIS_TOL", "POS_TOL", "SING_TOL", "Degeneracy", "IKSolutions", "ik_pose",
           "ik_pose_4dof", "ik_position"]  # fmt: skip
