"""The programmable RCM in the CasADi layer: IK of a tool tip with the shaft through a trocar.

The tool of :mod:`rcm_pin.control.rcm_task` (shaft: an axis of a frame; tip: a frame
origin moved by ``L`` along the shaft) becomes a frame ``rcm_tip`` added to a copy of the
model, and the IK NLP of :mod:`ocp.ik` solves

    min_q ½ |p_tip(q) − p_d|²   s.t.   (R b_i)ᵀ (p_T − p_s(q)) = 0,  i = 1, 2     (exact)
                                   or  |p_T − p_s|² − ((R a)ᵀ(p_T − p_s))² ≤ tol²  (tolerance)
                                   and q_lo ≤ q ≤ q_hi,

with the constraint :class:`ocp.ik_constraints.AxisThroughPoint` (IPOPT, exact Hessian).
:func:`tip_model` is shared with the tracking OCP (:mod:`ocp.rcm_tracking`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from ocp.ik import IKProblem, IKResult
from ocp.ik_constraints import AxisThroughPoint
from rcm_pin.control.rcm_task import RcmTool, line_distance
from rcm_pin.errors import InvalidInputError

#: Name of the frame added at the tool tip.
TIP_FRAME = "rcm_tip"
#: Tip residual accepted with the RCM as a tolerance [m]: the inequality keeps IPOPT's
#: barrier active and it stops at its acceptable level (about 2e-9 m on panda), not 1e-9.
TOLERANCE_REACH = 1e-8


def tip_model(model: pin.Model, tool: RcmTool) -> pin.Model:
    """A copy of ``model`` with the frame :data:`TIP_FRAME` at the tool tip (same
    orientation as the tip frame).

    Raises:
        InvalidInputError: a tip frame other than the shaft frame with a non-zero offset
            (the offset direction would then depend on q).
    """
    if tool.tip_frame != tool.axis_frame and tool.tip_offset != 0.0:
        raise InvalidInputError(
            "a tip offset needs the tip frame to be the shaft frame; valid: tip_offset=0 or "
            "tip_frame = the shaft frame"
        )
    out = pin.Model(model)
    parent = model.frames[tool.tip_frame]
    offset = pin.SE3(np.eye(3), tool.tip_offset * np.eye(3)[tool.axis])
    out.addFrame(
        pin.Frame(
            TIP_FRAME,
            parent.parentJoint,
            tool.tip_frame,
            parent.placement * offset,
            pin.FrameType.OP_FRAME,
        )
    )
    return out


@dataclass(frozen=True)
class RcmIKResult:
    """An RCM IK solve.

    Attributes:
        ik: the IK NLP's result (``q`` in the model's order).
        rcm_error: distance of p_T from the shaft line at ``ik.q`` by Pinocchio FK [m].
        tip_error: |p_tip − p_d| by Pinocchio FK [m].
    """

    ik: IKResult
    rcm_error: float
    tip_error: float


class RcmIK:
    """IK of the tool tip with the RCM as an equality (``tolerance=0``) or a tolerance [m]."""

    def __init__(
        self, model: pin.Model, tool: RcmTool, *, tolerance: float = 0.0, tol: float = 1e-12,
        max_iter: int = 200,
    ) -> None:  # fmt: skip
        self.model, self.tool = tip_model(model, tool), tool
        self.data = self.model.createData()
        self.tip_id = self.model.getFrameId(TIP_FRAME)
        axis = tuple(float(x) for x in np.eye(3)[tool.axis])
        self.constraint = AxisThroughPoint(
            point=tool.trocar,
            axis=axis,  # type: ignore[arg-type]
            tolerance=float(tolerance),
            frame=int(tool.axis_frame),
        )
        self.problem = IKProblem(
            self.model, TIP_FRAME, mode="position", constraints=(self.constraint,), tol=tol,
            max_iter=max_iter, reach_tol=TOLERANCE_REACH if tolerance > 0 else 1e-9,
        )  # fmt: skip

    def errors(self, q: np.ndarray, target: np.ndarray) -> tuple[float, float]:
        """(RCM distance, tip error) [m] at ``q`` by Pinocchio forward kinematics."""
        pin.framesForwardKinematics(self.model, self.data, q)
        Ms = self.data.oMf[self.tool.axis_frame]
        a = Ms.rotation[:, self.tool.axis]
        rcm = float(line_distance(Ms.translation, a, np.asarray(self.tool.trocar)))
        tip = float(np.linalg.norm(self.data.oMf[self.tip_id].translation - target))
        return rcm, tip

    def solve(self, target: Any, q0: np.ndarray, *, raise_on_failure: bool = True) -> RcmIKResult:
        """Tip at ``target`` (3,) [m] from ``q0`` with the RCM.

        Raises:
            SolverError, UnreachablePoseError: see :meth:`ocp.ik.IKProblem.solve`.
        """
        p = np.asarray(target, dtype=float).reshape(3)
        res = self.problem.solve(p, q0, solver="ipopt", raise_on_failure=raise_on_failure)
        return RcmIKResult(res, *self.errors(res.q, p))


__all__ = ["TIP_FRAME", "TOLERANCE_REACH", "RcmIK", "RcmIKResult", "tip_model"]
