"""Name → index lookups on a Pinocchio model with errors that list the valid names."""

from __future__ import annotations

import pinocchio as pin

from rcm_pin.errors import UnknownFrameError


def joint_index(model: pin.Model, name: str, what: str = "joint") -> int:
    """Pinocchio joint id of a joint name.

    Raises:
        UnknownFrameError: the message lists the model's joints.
    """
    if not isinstance(name, str) or not model.existJointName(name):
        raise UnknownFrameError(
            f"unknown {what} {name!r} in {model.name}; valid: {', '.join(model.names[1:])}"
        )
    return int(model.getJointId(name))


def frame_index(model: pin.Model, name: str, what: str = "frame") -> int:
    """Pinocchio frame id of a frame name.

    Raises:
        UnknownFrameError: the message lists the model's frames.
    """
    if not isinstance(name, str) or not model.existFrame(name):
        names = sorted({f.name for f in model.frames})
        raise UnknownFrameError(
            f"unknown {what} {name!r} in {model.name}; valid: {', '.join(names)}"
        )
    return int(model.getFrameId(name))
