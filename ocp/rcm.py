"""The programmable RCM in the CasADi layer: IK of a tool tip with the shaft through a trocar.

The tool of :mod:`rcm_pin.control.rcm_task` (shaft: an axis of a frame; tip: a frame
origin moved by ``L`` along the shaft) becomes a frame ``rcm_tip`` added to a copy of the
model, and the IK NLP of :mod:`ocp.ik` solves

    min_q ½ |p_tip(q) − p_d|²   s.t.   (R b_i)ᵀ (p_T − p_s(q)) = 0,  i = 1, 2     (exact)
                                   or  |p_T − p_s|² − ((R a)ᵀ(p_T − p_s))² ≤ tol²  (tolerance)
                                   and q_lo ≤ q ≤ q_hi,

with the constraint :class:`ocp.ik_constraints.AxisThroughPoint`. Solvers (``solver=``):

* ``"lm"`` (the default of the exact RCM): the compiled projected Levenberg–Marquardt on
  the stacked zero residual [tip error; the two RCM components] (:mod:`ocp.rcm_lm`);
* ``"ipopt"`` (the default, and the only route, of the tolerance form): the NLP above,
  exact Hessian.

Both reach the same zero residual, at different points of the 7-joint arm's solution
manifold. On an unreachable target both raise; with ``raise_on_failure=False`` the LM
returns its least-squares compromise (RCM and tip both off), IPOPT its RCM-feasible
closest tip. :func:`tip_model` is shared with the tracking OCP (:mod:`ocp.rcm_tracking`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import pinocchio as pin

from ocp.ik import IKProblem, IKResult
from ocp.ik_constraints import AxisThroughPoint
from ocp.ik_result import failure
from ocp.ik_targets import start_configuration
from ocp.rcm_lm import RcmLM
from rcm_pin.control.rcm_task import RcmTool
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
        ik: the solver's result (``q`` in the model's order; with ``solver="lm"``
            ``ik.position_error`` is the tip error and ``ik.constraint_violation`` the RCM
            distance below, ``ik.residual_norm`` the LM's |r|).
        rcm_error: distance of p_T from the shaft line at ``ik.q`` by Pinocchio FK [m].
        tip_error: |p_tip − p_d| by Pinocchio FK [m].
    """

    ik: IKResult
    rcm_error: float
    tip_error: float


class RcmIK:
    """IK of the tool tip with the RCM as an equality (``tolerance=0``) or a tolerance [m].

    ``solver="auto"`` is ``"lm"`` for the equality and ``"ipopt"`` for a tolerance.
    """

    def __init__(
        self, model: pin.Model, tool: RcmTool, *, tolerance: float = 0.0, tol: float = 1e-12,
        max_iter: int = 200, solver: Literal["auto", "lm", "ipopt"] = "auto",
    ) -> None:  # fmt: skip
        if solver not in ("auto", "lm", "ipopt"):
            raise InvalidInputError(f"solver must be 'auto', 'lm' or 'ipopt', got {solver!r}")
        if solver == "lm" and tolerance > 0:
            raise InvalidInputError(
                "solver 'lm' solves the RCM as an equality; valid: tolerance=0, or "
                "solver='ipopt' for an RCM tolerance"
            )
        self.solver = ("lm" if tolerance == 0 else "ipopt") if solver == "auto" else solver
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
        self._lm: RcmLM | None = None
        self._trocar = np.asarray(tool.trocar, dtype=float)

    def errors(self, q: np.ndarray, target: np.ndarray) -> tuple[float, float]:
        """(RCM distance, tip error) [m] at ``q`` by Pinocchio forward kinematics (the
        distance as |d − (d·a) a|, d = p_T − p_s, a the unit shaft axis: the same number
        as :func:`~rcm_pin.control.rcm_task.line_distance` to rounding, at a fifth of
        the cost)."""
        pin.forwardKinematics(self.model, self.data, q)
        Ms = pin.updateFramePlacement(self.model, self.data, self.tool.axis_frame)
        tip = pin.updateFramePlacement(self.model, self.data, self.tip_id).translation - target
        a = Ms.rotation[:, self.tool.axis]
        d = self._trocar - Ms.translation
        off = d - (d @ a) * a
        return math.sqrt(off @ off), math.sqrt(tip @ tip)

    def solve(self, target: Any, q0: np.ndarray, *, raise_on_failure: bool = True) -> RcmIKResult:
        """Tip at ``target`` (3,) [m] from ``q0`` with the RCM.

        Raises:
            SolverError, UnreachablePoseError: see :meth:`ocp.ik.IKProblem.solve`.
        """
        p = np.asarray(target, dtype=float).reshape(3)
        if self.solver == "ipopt":
            res = self.problem.solve(p, q0, solver="ipopt", raise_on_failure=raise_on_failure)
            return RcmIKResult(res, *self.errors(res.q, p))
        return self._solve_lm(p, q0, raise_on_failure)

    def _solve_lm(self, p: np.ndarray, q0: np.ndarray, raise_on_failure: bool) -> RcmIKResult:
        if self._lm is None:
            self._lm = RcmLM(self.problem, self.constraint)
        pb = self.problem
        out, ok = self._lm.run(start_configuration(pb.sm, q0, pb.lower, pb.upper), p)
        rcm, tip = self.errors(out.q, p)
        res = IKResult(q=out.q, success=ok, status=out.status, solver="lm",
                       iterations=out.iterations, residual_norm=out.residual_norm,
                       position_error=tip, orientation_error=float("nan"),
                       constraint_violation=rcm)  # fmt: skip
        if raise_on_failure and not ok:
            raise failure(res, TIP_FRAME, pb.reach_tol, False)
        return RcmIKResult(res, rcm, tip)


__all__ = ["TIP_FRAME", "TOLERANCE_REACH", "RcmIK", "RcmIKResult", "tip_model"]
