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
"""

from ocp.ik import IKProblem, IKResult, solve_ik
from ocp.ik_constraints import AxisThroughPoint, OrientationCone
from ocp.symbolic import SymbolicModel
from ocp.tracking import TrackingOCP, TrackingResult

__all__ = [
    "AxisThroughPoint",
    "IKProblem",
    "IKResult",
    "OrientationCone",
    "SymbolicModel",
    "TrackingOCP",
    "TrackingResult",
    "solve_ik",
]
