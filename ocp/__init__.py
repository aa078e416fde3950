"""CasADi layer of rcm-pin: the symbolic twin of a ``pin.Model`` (mimic joints included),
inverse-kinematics NLPs and trajectory-tracking OCPs built from it.

* :class:`SymbolicModel`: named ``casadi.Function`` s (frame placements and Jacobians,
  RNEA, mass matrix, gravity, nonlinear effects, forward dynamics) of any model with
  revolute, prismatic, continuous and mimic joints;
* :class:`IKProblem` / :func:`solve_ik`: IK of any :class:`rcm_pin.Mechanism` of the
  catalogue (``rcm_pin.load(name)``, the panda and ur5 arms included) or any model with a
  frame: a frame's pose or position with joint limits and optional
  :class:`AxisThroughPoint` (RCM) / :class:`OrientationCone` constraints, or a closed
  mechanism's output coordinates with its loop closures as equality constraints
  (:mod:`ocp.closure`); Levenberg-Marquardt by default, IPOPT or SQP with constraints;
* :class:`TrackingOCP`: tool-position tracking of a serial mechanism by direct collocation
  with implicit (inverse) dynamics and drive limits; :mod:`ocp.paper000` sets up paper
  000's example;
* :class:`RcmIK` / :class:`RcmTrackingOCP`: an arm's tool held through a trocar (a
  programmable RCM, :mod:`ocp.rcm`, :mod:`ocp.rcm_tracking`) by an NLP and an OCP.

The re-exports are the public API of the package (``docs/api.md``), imported on first
access: ``import ocp`` loads no CasADi.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from rcm_pin.lazy import lazy_exports

if TYPE_CHECKING:
    from ocp.ik import IKProblem, IKResult, solve_ik
    from ocp.ik_constraints import AxisThroughPoint, OrientationCone
    from ocp.rcm import RcmIK, RcmIKResult
    from ocp.rcm_tracking import RcmTrackingOCP, RcmTrackingResult
    from ocp.symbolic import SymbolicModel
    from ocp.tracking import TrackingOCP, TrackingResult

#: The re-exports, imported on first access (PEP 562): the closure kernels
#: (:mod:`ocp.kernels`, loaded on a closed mechanism's first solve) need neither the IK
#: nor the tracking layer.
_LAZY = {
    "AxisThroughPoint": "ik_constraints",
    "IKProblem": "ik",
    "IKResult": "ik",
    "OrientationCone": "ik_constraints",
    "RcmIK": "rcm",
    "RcmIKResult": "rcm",
    "RcmTrackingOCP": "rcm_tracking",
    "RcmTrackingResult": "rcm_tracking",
    "SymbolicModel": "symbolic",
    "TrackingOCP": "tracking",
    "TrackingResult": "tracking",
    "solve_ik": "ik",
}


__getattr__, __dir__ = lazy_exports(__name__, _LAZY)


__all__ = [
    "AxisThroughPoint",
    "IKProblem",
    "IKResult",
    "OrientationCone",
    "RcmIK",
    "RcmIKResult",
    "RcmTrackingOCP",
    "RcmTrackingResult",
    "SymbolicModel",
    "TrackingOCP",
    "TrackingResult",
    "solve_ik",
]
