"""rcm-pin: remote-centre-of-motion and small parallel mechanisms on Pinocchio.

Public API (see README): :func:`load`, :func:`mechanisms`, :class:`Mechanism`, forward
kinematics (:func:`tool_pose`, :func:`rcm_error`), analytic inverse kinematics
(:func:`solve_ik`), errors in :mod:`rcm_pin.errors`.
"""

from rcm_pin import analytic_ik, closed_form, errors, rotations
from rcm_pin.catalog import MechanismSpec, mechanisms
from rcm_pin.errors import RcmPinError
from rcm_pin.inverse import IKResult, solve_ik, solve_ik_position, solve_ik_within_limits
from rcm_pin.kinematics import frame_pose, rcm_error, tool_pose, tool_poses
from rcm_pin.mechanism import Coupling, Mechanism, from_urdf, load
from rcm_pin.mobility import MobilityCount, mobility

__all__ = [
    "Coupling",
    "IKResult",
    "Mechanism",
    "MechanismSpec",
    "MobilityCount",
    "RcmPinError",
    "analytic_ik",
    "closed_form",
    "errors",
    "frame_pose",
    "from_urdf",
    "load",
    "mechanisms",
    "mobility",
    "rcm_error",
    "rotations",
    "solve_ik",
    "solve_ik_position",
    "solve_ik_within_limits",
    "tool_pose",
    "tool_poses",
]

__version__ = "0.1.0"
