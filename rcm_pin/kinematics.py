"""Forward kinematics through Pinocchio and the RCM check.

These functions take the Mechanism coordinate vector (papers' q1..qn). The papers'
closed form lives in :mod:`rcm_pin.closed_form`; tests compare the two.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError, UnknownFrameError
from rcm_pin.mechanism import Mechanism

#: Frame whose z axis is the output axis e4 of the RCM mechanisms (output link 2).
OUTPUT_LINK_FRAME = "output_link"


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
    """Tool poses for a batch of configurations, shape (N, 4, 4)."""
    qs = np.atleast_2d(np.asarray(qs, dtype=float))
    if qs.shape[1] != mech.nq or not np.all(np.isfinite(qs)):
        raise InvalidInputError(
            f"configurations have shape {qs.shape}; valid: (N, {mech.nq}) finite values"
        )
    out = np.empty((qs.shape[0], 4, 4))
    model, data, fid = mech.model, mech.data, mech.tool_frame_id
    for i, q_pin in enumerate(mech.to_pin(qs)):
        pin.forwardKinematics(model, data, q_pin)
        out[i] = pin.updateFramePlacement(model, data, fid).homogeneous
    return out


def rcm_error(mech: Mechanism, q: np.ndarray, frame: str = OUTPUT_LINK_FRAME) -> float:
    """Distance [m] from the RCM point A to the output-link axis, as Pinocchio computes it.

    With o the origin and e the z axis of the output-link frame and a the position of
    the ``rcm`` frame, the distance is ||(a − o) − ((a − o)·e) e||. Zero for every
    configuration when the transmissions keep the output axis through A.

    Raises:
        UnknownFrameError: the mechanism has no RCM frame or no output-link frame.
    """
    if mech.rcm_frame_id < 0:
        raise UnknownFrameError(f"{mech.name} has no RCM frame; valid: the rcm_* mechanisms")
    fid = _fid(mech, frame)
    q = mech.check_q(q)
    pin.forwardKinematics(mech.model, mech.data, mech.to_pin(q))
    out = pin.updateFramePlacement(mech.model, mech.data, fid)
    a = pin.updateFramePlacement(mech.model, mech.data, mech.rcm_frame_id).translation
    d = a - out.translation
    e = out.rotation[:, 2]
    return float(np.linalg.norm(d - (d @ e) * e))


def _fid(mech: Mechanism, frame: str | int) -> int:
    if isinstance(frame, (int, np.integer)):
        if not 0 <= int(frame) < mech.model.nframes:
            raise UnknownFrameError(
                f"frame id {frame} out of range; valid: 0..{mech.model.nframes - 1}"
            )
        return int(frame)
    return mech.frame_id(frame)
