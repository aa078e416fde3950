"""Differential IK with a programmable RCM at control rate: one QP per step (qpsolvers, daqp).

Each step of length ``dt`` [s] moves the tool tip to the next reference sample ``p_d``
while the shaft stays through the trocar; with ``g = k_post dt (q_post − q)`` (a posture
pull that only acts in the arm's redundancy):

    min  ½ |Δq − g|² + ½ μ |Δq|²
    s.t. J_tip Δq = p_d − p_tip                                         (tip)
         RCM rows:  distance form  J_dist Δq = −e
                    λ form         J_λ [Δq; Δλ] = p_T − p_rcm   (Δλ free)
         max(k_pos (q_lo − q), −v_max dt) ≤ Δq ≤ min(k_pos (q_hi − q), v_max dt)

(:mod:`rcm_pin.control.rcm_task` for the symbols). When the box makes the tip row
infeasible the tip moves into the cost (``½|J_tip Δq − (p_d − p_tip)|²``, RCM still
hard); ``hard=False`` puts the RCM rows in the cost too, with weight ``w_rcm``: the
positioning phase that brings an arm from a posture far from the trocar onto the first
path point. :meth:`RcmQP.step_pink` solves the first problem through pink
(:mod:`rcm_pin.control.rcm_pink`); the tests check that both give the same Δq.

The model is the kinematic chain that carries the tool (:func:`chain_model`): joints that
do not support the tool frames (a gripper's fingers) are locked at their reference value.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import pinocchio as pin

from rcm_pin.control.rcm_task import RcmState, RcmTool, make_tool, rcm_state, update_kinematics
from rcm_pin.errors import InvalidInputError, SolverError, require
from rcm_pin.model.mechanism import Mechanism

Formulation = Literal["distance", "lambda"]
#: Bound on Δλ (free in the λ form; daqp wants finite bounds) [-].
LAMBDA_STEP_BOUND = 1e3
#: Weight on Δλ² in the λ form: ~0 would leave Δλ free, but daqp factorises the Hessian
#: and a 1e-10 entry beside 1 stalls the RCM error near 1e-9 m; 1e-6 converges to 1e-12 m
#: and moves Δq by ~w Δλ ≈ 1e-11 per step (tested against the distance form).
LAMBDA_WEIGHT = 1e-6
#: Weight of the posture term when the tip is in the cost (small: it only breaks the tie
#: in the arm's redundancy; its pull on the tip is ~1e-6 of the step).
POSTURE_SOFT = 1e-6


@dataclass(frozen=True)
class ChainModel:
    """The tool-carrying chain of a Mechanism.

    Attributes:
        model: reduced Pinocchio model (locked joints removed).
        tool: the tool on ``model``'s frame ids.
        active: Mechanism coordinate index of each ``model`` joint (q order).
        q_ref: the Mechanism configuration that the locked joints keep.
    """

    model: pin.Model
    tool: RcmTool
    active: np.ndarray
    q_ref: np.ndarray

    def to_mechanism(self, q: np.ndarray) -> np.ndarray:
        """Chain configurations (..., n) -> Mechanism coordinates (..., nq)."""
        q = np.asarray(q, dtype=float)
        out = np.broadcast_to(self.q_ref, q.shape[:-1] + self.q_ref.shape).copy()
        out[..., self.active] = q
        return out


def chain_model(
    mech: Mechanism,
    frame: str,
    axis: str,
    tip_offset: float,
    trocar: tuple[float, float, float],
    q_ref: np.ndarray,
) -> ChainModel:
    """Lock every joint that does not support ``frame`` (module docstring).

    Raises:
        UnknownFrameError: ``frame`` is not a frame of the mechanism (valid names listed).
        InvalidInputError: a mechanism with loop closures or mimic joints.
    """
    full = make_tool(mech.model, frame, axis, tip_offset=tip_offset, trocar=trocar)
    if mech.loops is not None or mech.model.nq != mech.nq or mech.nq != mech.nv:
        raise InvalidInputError(
            f"{mech.name}: the programmable RCM needs a serial arm without mimic or continuous "
            "joints; valid: a serial arm of the catalogue (mechanical RCMs use their analytic IK)"
        )
    support = set(mech.model.supports[mech.model.frames[full.axis_frame].parentJoint])
    locked = [j for j in range(1, mech.model.njoints) if j not in support]
    q_pin = mech.to_pin(q_ref)
    model = pin.buildReducedModel(mech.model, locked, q_pin) if locked else pin.Model(mech.model)
    active = np.array(
        [mech.joint_names.index(model.names[j]) for j in range(1, model.njoints)], dtype=int
    )
    tool = make_tool(model, frame, axis, tip_offset=tip_offset, trocar=trocar)
    return ChainModel(model, tool, active, np.asarray(q_ref, dtype=float).copy())


class RcmQP:
    """One control step of the programmable RCM (module docstring)."""

    def __init__(
        self,
        model: pin.Model,
        tool: RcmTool,
        dt: float,
        *,
        formulation: Formulation = "distance",
        damping: float = 1e-10,
        position_gain: float = 0.5,
        w_rcm: float = 10.0,
        posture: np.ndarray | None = None,
        posture_gain: float = 1.0,
    ) -> None:
        if formulation not in ("distance", "lambda"):
            raise InvalidInputError(
                f"formulation must be 'distance' or 'lambda'; got {formulation!r}"
            )
        if not (np.isfinite(dt) and dt > 0):
            raise InvalidInputError(f"dt must be > 0 [s]; got {dt!r}")
        # the [arms] extra: qpsolvers with the daqp solver (MissingExtraError without them)
        self._solve_qp = require("arms", "qpsolvers").solve_qp
        require("arms", "daqp")
        self.model, self.data, self.tool = model, model.createData(), tool
        self.dt, self.formulation, self.damping = float(dt), formulation, float(damping)
        self.position_gain, self.w_rcm = float(position_gain), float(w_rcm)
        self.lower = np.asarray(model.lowerPositionLimit, dtype=float)
        self.upper = np.asarray(model.upperPositionLimit, dtype=float)
        self.v_max = np.asarray(model.velocityLimit, dtype=float)
        self.posture = None if posture is None else np.asarray(posture, dtype=float).copy()
        self.posture_gain = float(posture_gain)
        self._eye = np.eye(model.nv)
        self._pink: tuple[Any, ...] | None = None

    def state(self, q: np.ndarray) -> RcmState:
        """The RCM geometry at ``q`` (chain order)."""
        update_kinematics(self.model, self.data, q)
        return rcm_state(self.model, self.data, self.tool)

    def bounds(self, q: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
        """Box on Δq: position limits (times the gain) and velocity limits over ``dt``."""
        vdt = self.v_max * dt
        lo = np.maximum(self.position_gain * (self.lower - q), -vdt)
        hi = np.minimum(self.position_gain * (self.upper - q), vdt)
        return np.minimum(lo, 0.0), np.maximum(hi, 0.0)

    def _rcm_rows(self, s: RcmState) -> tuple[np.ndarray, np.ndarray]:
        """(A, b) of the hard RCM rows on [Δq] (distance) or [Δq; Δλ] (λ form)."""
        if self.formulation == "distance":
            return s.J_dist, -s.e
        return s.J_lam, np.asarray(self.tool.trocar) - s.p_rcm

    def _solve(
        self, H: np.ndarray, g: np.ndarray, A: np.ndarray | None, b: np.ndarray | None,
        lo: np.ndarray, hi: np.ndarray,
    ) -> np.ndarray | None:  # fmt: skip
        n = self.model.nv
        if A is not None and A.shape[1] == n + 1:  # λ form: Δλ (nearly) free
            H = np.block([[H, np.zeros((n, 1))], [np.zeros((1, n)), np.array([[LAMBDA_WEIGHT]])]])
            g, big = np.append(g, 0.0), np.array([LAMBDA_STEP_BOUND])
            lo, hi = np.append(lo, -big), np.append(hi, big)
        x = self._solve_qp(H, g, A=A, b=b, lb=lo, ub=hi, solver="daqp")
        return None if x is None else np.asarray(x[:n], dtype=float)

    def step(
        self, q: np.ndarray, p_target: np.ndarray, *, hard: bool = True, dt: float | None = None,
        posture: bool = True,
    ) -> np.ndarray:  # fmt: skip
        """Δq of one step from ``q`` towards the tip target ``p_target`` [m] (module
        docstring: tip and RCM as equalities, else the tip in the cost, else all soft);
        ``posture=False`` drops the posture pull (the last steps of positioning).

        Raises:
            SolverError: the QP is infeasible (the RCM rows cannot be met within the
                joint position and velocity limits).
        """
        s = self.state(q)
        h = self.dt if dt is None else dt
        lo, hi = self.bounds(q, h)
        post = np.zeros(self.model.nv) if self.posture is None or not posture else self.posture - q
        post = self.posture_gain * h * post
        J, r = s.J_tip, np.asarray(p_target, dtype=float) - s.p_tip
        A, b = self._rcm_rows(s)
        if not hard:
            w = self.w_rcm**2
            H = J.T @ J + w * s.J_dist.T @ s.J_dist + (self.damping + POSTURE_SOFT) * self._eye
            x = self._solve(H, -J.T @ r + w * s.J_dist.T @ s.e - POSTURE_SOFT * post, None, None,
                            lo, hi)  # fmt: skip
        else:
            tip_rows = np.hstack([J, np.zeros((3, A.shape[1] - J.shape[1]))])
            H = (1.0 + self.damping) * self._eye
            x = self._solve(H, -post, np.vstack([tip_rows, A]), np.concatenate([r, b]), lo, hi)
            if x is None:  # the tip cannot follow within the box: keep the RCM, tip in the cost
                H = J.T @ J + (self.damping + POSTURE_SOFT) * self._eye
                x = self._solve(H, -J.T @ r - POSTURE_SOFT * post, A, b, lo, hi)
        if x is None:
            raise SolverError(
                f"RCM QP infeasible at RCM distance {s.distance:.3e} m: the shaft cannot stay "
                "through the trocar within the joint position and velocity limits; valid: a "
                "slower path or a trocar farther from the limits"
            )
        return x

    def step_pink(self, q: np.ndarray, p_target: np.ndarray) -> np.ndarray:
        """The same first-level step through pink: tip and RCM as constraints, the posture
        as pink's ``PostureTask`` (gain = posture gain × dt) in the cost."""
        pink = require("arms", "pink")
        from pink.limits import ConfigurationLimit, VelocityLimit
        from pink.tasks import PostureTask

        from rcm_pin.control.rcm_pink import RcmTask, ToolTipTask

        if self._pink is None:
            posture = PostureTask(cost=1.0, gain=self.posture_gain * self.dt)
            posture.set_target(np.zeros(self.model.nq) if self.posture is None else self.posture)
            self._pink = (
                RcmTask(self.tool),
                ToolTipTask(self.tool),
                posture,
                [ConfigurationLimit(self.model, self.position_gain), VelocityLimit(self.model)],
            )
        rcm, tip, posture, limits = self._pink
        tip.set_target(p_target)  # type: ignore[attr-defined]
        conf = pink.Configuration(self.model, self.data, np.asarray(q, dtype=float).copy())
        v = pink.solve_ik(
            conf, [posture] if self.posture is not None else [], self.dt, solver="daqp",
            damping=self.damping, limits=limits, constraints=[tip, rcm],
        )  # fmt: skip
        return np.asarray(v, dtype=float) * self.dt


__all__ = ["ChainModel", "Formulation", "RcmQP", "chain_model"]
