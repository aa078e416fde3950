"""rcm-pin: remote-centre-of-motion and small parallel mechanisms on Pinocchio.

Public API (see README): :func:`load`, :func:`mechanisms`, :class:`Mechanism`, forward
kinematics (:func:`tool_pose`, :func:`rcm_error`), analytic inverse kinematics
(:func:`solve_ik`), errors in :mod:`rcm_pin.errors`.
"""

from rcm_pin import errors
from rcm_pin.catalog import MechanismSpec, mechanisms
from rcm_pin.errors import RcmPinError
from rcm_pin.kinematics import frame_pose, rcm_error, tool_pose, tool_poses
from rcm_pin.mechanism import Coupling, Mechanism, from_urdf, load
from rcm_pin.mobility import MobilityCount, mobility

__all__ = [
    "Coupling",
    "Mechanism",
    "MechanismSpec",
    "MobilityCount",
    "RcmPinError",
    "errors",
    "frame_pose",
    "from_urdf",
    "load",
    "mechanisms",
    "mobility",
    "rcm_error",
    "tool_pose",
    "tool_poses",
]

__version__ = "0.1.0"
