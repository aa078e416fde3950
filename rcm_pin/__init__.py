"""rcm-pin: remote-centre-of-motion and small parallel mechanisms on Pinocchio.

Public API (see README):

* :func:`load` a catalogue name (:func:`names`, :func:`catalogue`, :func:`get_entry`) or a
  URDF / xacro path into a :class:`Mechanism` (serial or closed, one class);
* :func:`forward` and :func:`inverse`: the position problems of every mechanism, every
  branch / working mode / assembly mode labelled;
* :func:`tool_pose`, :func:`frame_pose`, :func:`rcm_error`: forward kinematics;
* :func:`mobility`: the formula count beside the rank of the closure Jacobian;
* typed errors in :mod:`rcm_pin.errors`, one base class :class:`RcmPinError`.
"""

from rcm_pin import errors, rotations
from rcm_pin.analysis.kinematics import frame_pose, rcm_error, tool_pose, tool_poses
from rcm_pin.analysis.mobility import MobilityCount, mobility
from rcm_pin.analysis.position import PositionResult, PositionSolution, forward, inverse
from rcm_pin.catalog import CatalogEntry, from_urdf, get_entry, load, names
from rcm_pin.catalog import mechanisms as catalogue
from rcm_pin.errors import RcmPinError
from rcm_pin.model import Coupling, Family, Loops, Mechanism, Output

__all__ = [
    "CatalogEntry",
    "Coupling",
    "Family",
    "Loops",
    "Mechanism",
    "MobilityCount",
    "Output",
    "PositionResult",
    "PositionSolution",
    "RcmPinError",
    "catalogue",
    "errors",
    "forward",
    "frame_pose",
    "from_urdf",
    "get_entry",
    "inverse",
    "load",
    "mobility",
    "names",
    "rcm_error",
    "rotations",
    "tool_pose",
    "tool_poses",
]

__version__ = "0.2.0"
