"""The remote-centre-of-motion (RCM) task of any serial arm: a tool shaft through a trocar.

The *tool* is a line fixed to the arm: it passes through the origin ``p_s`` of an axis
frame along one of that frame's axes, ``a = R_s e_k`` (k = 0, 1, 2 for x, y, z); the tool
*tip* is the origin of a tip frame moved by ``L`` [m] along ``a``:

    p_tip(q) = p_t(q) + L a(q).

The RCM task asks that the line pass through the trocar point ``p_T`` [m]. Two
formulations, checked against each other in the tests:

* **λ-parametrised RCM point** (Aghakhani, Geravand, Shahriari, Vendittelli, Oriolo,
  "Task control with remote center of motion constraint for minimally invasive robotic
  surgery", ICRA 2013): the point of the shaft ``p_rcm(q, λ) = p_s + λ (p_tip − p_s)``
  must equal ``p_T``; with λ an extra variable its Jacobian is

      J_λ = [ (1 − λ) J_s + λ J_tip ,  p_tip − p_s ]            (3 × (n + 1)),

  where ``J_s``, ``J_tip`` are the linear-velocity Jacobians of ``p_s`` and ``p_tip``.
  The λ of the nearest shaft point is ``λ* = aᵀ(p_T − p_s) / aᵀ(p_tip − p_s)``.
* **point-to-line distance** (the form of Drake's IK constraint): with ``b_1, b_2`` the
  two other axes of the axis frame (an orthonormal basis of the plane normal to ``a``),
  the two components ``e_i = b_iᵀ (p_T − p_s)`` of the perpendicular from the line to
  ``p_T``; ``|e|`` is the distance of ``p_T`` from the line, and (ω the angular-velocity
  Jacobian of the axis frame, d b_i = ω × b_i)

      ∂e_i/∂q = −b_iᵀ J_s + (b_i × (p_T − p_s))ᵀ J_ω              (2 × n).

The λ column lies along ``a``, and with ``e⊥ = p_T − p_rcm(q, λ*)`` (the perpendicular,
``|e⊥| = |e|``) the q-columns obey, for a tip on the shaft frame (``J_tip − J_s = −L[a]×J_ω``),

    b_iᵀ J_λ,q = −∂e_i/∂q + (b_i × e⊥)ᵀ J_ω,

so at ``e = 0`` both formulations impose the same two rows (tested). The tip Jacobian is

    J_tip = J_t − L [a]× J_ω.

All Jacobians are Pinocchio ``LOCAL_WORLD_ALIGNED`` (linear rows: velocity of the point
itself, in world axes) on the model's tangent space.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError
from rcm_pin.model.indices import frame_index

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
AXES = ("x", "y", "z")


@dataclass(frozen=True)
class RcmTool:
    """A tool shaft on an arm and the trocar it must pass through.

    Attributes:
        axis_frame: Pinocchio frame id of the frame whose axis is the shaft.
        axis: which axis of that frame (0, 1, 2 = x, y, z).
        tip_frame: frame id whose origin, moved by ``tip_offset`` along the shaft, is the tip.
        tip_offset: L [m], the tip beyond the tip frame's origin along the shaft.
        trocar: p_T (3,) [m], world coordinates.
        axis_frame_name: name of the axis frame (for reports and JSON).
    """

    axis_frame: int
    axis: int
    tip_frame: int
    tip_offset: float
    trocar: tuple[float, float, float]
    axis_frame_name: str = ""

    @property
    def axis_name(self) -> str:
        """``"x"``, ``"y"`` or ``"z"``."""
        return AXES[self.axis]

    def with_trocar(self, trocar: Any) -> RcmTool:
        """The same tool with another trocar point (validated)."""
        return RcmTool(
            self.axis_frame,
            self.axis,
            self.tip_frame,
            self.tip_offset,
            trocar_point(trocar),
            self.axis_frame_name,
        )


def trocar_point(value: Any) -> tuple[float, float, float]:
    """A finite 3-vector [m].

    Raises:
        InvalidInputError: wrong shape or a NaN / infinite entry.
    """
    try:
        p = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        p = np.zeros(0)
    if p.shape != (3,) or not np.isfinite(p).all():
        raise InvalidInputError(f"trocar must be 3 finite numbers x,y,z [m]; got {value!r}")
    return (float(p[0]), float(p[1]), float(p[2]))


def make_tool(
    model: pin.Model,
    frame: str,
    axis: str = "z",
    *,
    tip_frame: str | None = None,
    tip_offset: float = 0.0,
    trocar: Any = (0.0, 0.0, 0.0),
) -> RcmTool:
    """An :class:`RcmTool` from frame names.

    Raises:
        UnknownFrameError: ``frame`` or ``tip_frame`` is not a frame of ``model`` (the
            message lists the model's frames).
        InvalidInputError: ``axis`` not one of x, y, z or a non-finite ``tip_offset``.
    """
    fid = frame_index(model, frame, "tool frame")
    tid = fid if tip_frame is None else frame_index(model, tip_frame, "tip frame")
    if axis not in AXES:
        raise InvalidInputError(f"tool axis must be one of x, y, z; got {axis!r}")
    if not np.isfinite(tip_offset):
        raise InvalidInputError(f"tip_offset must be finite [m]; got {tip_offset!r}")
    return RcmTool(fid, AXES.index(axis), tid, float(tip_offset), trocar_point(trocar), frame)


@dataclass(frozen=True)
class RcmState:
    """The RCM geometry at one configuration (module docstring for the symbols).

    Attributes:
        p_shaft: p_s (3,) [m].
        axis: a (3,), unit.
        p_tip: p_tip (3,) [m].
        lam: λ* of the shaft point nearest to p_T [-].
        p_rcm: p_rcm(q, λ*) (3,) [m], the foot of the perpendicular from p_T.
        e: (e_1, e_2) [m], the distance formulation's error.
        distance: |p_T − p_rcm| = |e| [m].
        J_tip: (3, nv) tip Jacobian.
        J_dist: (2, nv) ∂e/∂q.
        J_lam: (3, nv + 1) the λ-formulation's Jacobian at λ*.
    """

    p_shaft: np.ndarray
    axis: np.ndarray
    p_tip: np.ndarray
    lam: float
    p_rcm: np.ndarray
    e: np.ndarray
    distance: float
    J_tip: np.ndarray
    J_dist: np.ndarray
    J_lam: np.ndarray


def update_kinematics(model: pin.Model, data: pin.Data, q: np.ndarray) -> None:
    """Joint Jacobians and frame placements of ``q`` (Pinocchio order) into ``data``."""
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)


def rcm_state(model: pin.Model, data: pin.Data, tool: RcmTool) -> RcmState:
    """Both formulations at the configuration last passed to :func:`update_kinematics`.

    Raises:
        InvalidInputError: the tip lies on the axis frame's origin (λ undefined).
    """
    Ms = data.oMf[tool.axis_frame]
    R, p_s = Ms.rotation, Ms.translation.copy()  # copies: no views into ``data``
    k = tool.axis
    a, B = R[:, k].copy(), R[:, ((k + 1) % 3, (k + 2) % 3)]  # B = [b_1 b_2]
    L = tool.tip_offset
    same = tool.tip_frame == tool.axis_frame
    p_tip = (p_s if same else data.oMf[tool.tip_frame].translation) + L * a
    r = np.asarray(tool.trocar) - p_s
    span = p_tip - p_s
    along = float(a @ span)
    if abs(along) < 1e-12:
        raise InvalidInputError(
            "the tool tip coincides with the shaft frame's origin: lambda is undefined; "
            "valid: a tip offset along the shaft (tip_offset != 0)"
        )
    lam = float(a @ r) / along
    e = B.T @ r
    Js = pin.getFrameJacobian(model, data, tool.axis_frame, LWA)
    Jv, Jw = Js[:3], Js[3:]
    Jt = Jv if same else pin.getFrameJacobian(model, data, tool.tip_frame, LWA)[:3]
    J_tip = Jt - L * (pin.skew(a) @ Jw)
    # ∂e_i/∂q = −b_iᵀ J_s + (b_i × r)ᵀ J_ω = b_iᵀ ([r]× J_ω − J_s)
    J_dist = B.T @ (pin.skew(r) @ Jw - Jv)
    J_lam = np.empty((3, Jv.shape[1] + 1))
    J_lam[:, :-1] = (1.0 - lam) * Jv + lam * J_tip
    J_lam[:, -1] = span
    return RcmState(
        p_s, a, p_tip, lam, p_s + lam * span, e, math.hypot(e[0], e[1]), J_tip, J_dist, J_lam
    )


def rcm_point(
    model: pin.Model, data: pin.Data, tool: RcmTool, q: np.ndarray, lam: float
) -> np.ndarray:
    """p_rcm(q, λ) = p_s + λ (p_tip − p_s) [m] at a given λ (for finite differences)."""
    pin.framesForwardKinematics(model, data, q)
    Ms, Mt = data.oMf[tool.axis_frame], data.oMf[tool.tip_frame]
    a = Ms.rotation[:, tool.axis]
    p_tip = Mt.translation + tool.tip_offset * a
    return np.asarray(Ms.translation + lam * (p_tip - Ms.translation), dtype=float)


def line_distance(p_shaft: np.ndarray, axis: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Distance [m] of ``point`` (3,) from the lines ``p_shaft + s axis`` ((..., 3) each):
    ``|(point − p_s) × a| / |a|``, the independent route used by the tests and reports."""
    r = np.asarray(point, dtype=float) - np.asarray(p_shaft, dtype=float)
    a = np.asarray(axis, dtype=float)
    return np.asarray(
        np.linalg.norm(np.cross(r, a), axis=-1) / np.linalg.norm(a, axis=-1), dtype=float
    )


def constrained_tip_jacobian(state: RcmState) -> np.ndarray:
    """The tip Jacobian restricted to motions that keep the RCM: ``J_tip N`` with ``N`` an
    orthonormal basis of the null space of ``J_dist`` (3 × (n − 2))."""
    _, s, vt = np.linalg.svd(state.J_dist)
    rank = int(np.sum(s > 1e-12 * max(1.0, s[0])))
    N = vt[rank:].T
    return np.asarray(state.J_tip @ N, dtype=float)


def manipulability(state: RcmState) -> tuple[float, float]:
    """(Yoshikawa manipulability ``sqrt(det(J Jᵀ))`` [m^3], condition number σ_max/σ_min)
    of the tip Jacobian under the RCM constraint (:func:`constrained_tip_jacobian`)."""
    s = np.linalg.svd(constrained_tip_jacobian(state), compute_uv=False)
    return float(np.prod(s)), float(s[0] / s[-1]) if s[-1] > 0 else float("inf")


__all__ = [
    "AXES",
    "RcmState",
    "RcmTool",
    "constrained_tip_jacobian",
    "line_distance",
    "make_tool",
    "manipulability",
    "rcm_point",
    "rcm_state",
    "trocar_point",
    "update_kinematics",
]
