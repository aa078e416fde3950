"""Forward kinematics through Pinocchio and the RCM check.

These functions take the Mechanism coordinate vector (papers' q1..qn). The papers'
closed form lives in :mod:`rcm_pin.mechanisms.rcm.closed_form`; tests compare the two.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError, UnknownFrameError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.rotations import check_magnitude, numeric_array


def frame_pose(mech: Mechanism, q: np.ndarray, frame: str | int | None = None) -> np.ndarray:
    """Homogeneous placement (4x4) of a frame in the world.

    Args:
        mech: the mechanism.
        q: coordinates (n,) [rad, m].
        frame: frame name or id; the tool frame when None.

    Returns:
        4x4 matrix [R p; 0 1], p in [m].
    """
    q_pin = mech.q_pin(q)
    fid = mech.tool_frame_id if frame is None else _fid(mech, frame)
    pin.forwardKinematics(mech.model, mech.data, q_pin)
    return pin.updateFramePlacement(mech.model, mech.data, fid).homogeneous


def tool_pose(mech: Mechanism, q: np.ndarray) -> np.ndarray:
    """Tool-centre pose (4x4) from Pinocchio (see :func:`frame_pose`)."""
    pin.forwardKinematics(mech.model, mech.data, mech.q_pin(q))
    return pin.updateFramePlacement(mech.model, mech.data, mech.tool_frame_id).homogeneous


def tool_poses(mech: Mechanism, qs: np.ndarray) -> np.ndarray:
    """Tool poses for a batch of configurations (N, n) [rad, m], shape (N, 4, 4).

    Raises:
        InvalidInputError: not numeric, not (N, n), NaN / infinite or beyond
            :data:`rcm_pin.rotations.MAX_ABS`.
    """
    qs = np.atleast_2d(numeric_array(qs, "configurations"))
    if qs.ndim != 2 or qs.shape[1] != mech.nq or not np.all(np.isfinite(qs)):
        raise InvalidInputError(
            f"configurations have shape {qs.shape}; valid: (N, {mech.nq}) finite values"
        )
    check_magnitude(qs, "configurations")
    out = np.empty((qs.shape[0], 4, 4))
    model, data, fid = mech.model, mech.data, mech.tool_frame_id
    for i, q_pin in enumerate(mech.to_pin(qs)):
        pin.forwardKinematics(model, data, q_pin)
        out[i] = pin.updateFramePlacement(model, data, fid).homogeneous
    return out


def rcm_error(mech: Mechanism, q: np.ndarray) -> float:
    """Distance [m] from the RCM point A to the insertion axis, as Pinocchio computes it.

    With o the origin and e the insertion axis of the RCM axis frame (the ``rcm_axis`` of
    ``rcm_axis_frame`` in the URDF's ``<rcm_pin>`` element; e4 for the RCM mechanisms)
    and a the position of the RCM frame, the distance is ||(a − o) − ((a − o)·e) e||.
    Zero for every configuration when the transmissions keep the axis through A.

    Raises:
        UnknownFrameError: the mechanism has no RCM frame.
    """
    if mech.rcm is None:
        raise UnknownFrameError(
            f"{mech.name} has no RCM frame; valid: a mechanism with a remote centre (rcm_*), "
            "or load(..., rcm_frame=...)"
        )
    pin.forwardKinematics(mech.model, mech.data, mech.q_pin(q))
    axis = pin.updateFramePlacement(mech.model, mech.data, mech.rcm.axis_frame_id)
    a = pin.updateFramePlacement(mech.model, mech.data, mech.rcm.point_frame_id).translation
    d = a - axis.translation
    e = axis.rotation[:, mech.rcm.axis]
    return float(np.linalg.norm(d - (d @ e) * e))


def _fid(mech: Mechanism, frame: str | int) -> int:
    if isinstance(frame, (int, np.integer)):
        if not 0 <= int(frame) < mech.model.nframes:
            raise UnknownFrameError(
                f"frame id {frame} out of range; valid: 0..{mech.model.nframes - 1}"
            )
        return int(frame)
    return mech.frame_id(frame)


__all__ = ["frame_pose", "rcm_error", "tool_pose", "tool_poses"]
