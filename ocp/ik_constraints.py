"""Optional geometric constraints of the IK NLP, as CasADi expressions with bounds.

* :class:`AxisThroughPoint`: the line through the origin of a frame along one of its
  local axes must pass through a given world point (the remote-centre-of-motion
  constraint for any arm: a tool shaft through a trocar). With ``tolerance == 0`` it is
  two equations ``(R b_i) . (c - p) = 0`` (``b_1``, ``b_2`` complete the axis to an
  orthonormal basis: full rank, unlike the three components of ``(c - p) x (R a)``);
  with ``tolerance > 0`` one inequality on the squared distance of ``c`` from the line.
* :class:`OrientationCone`: the angle between a local axis of a frame and a world
  direction stays below ``half_angle``: ``(R a) . d >= cos(half_angle)``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from rcm_pin.errors import InvalidInputError


def _unit(v: Any, name: str) -> np.ndarray:
    a = np.asarray(v, dtype=float).reshape(-1)
    if a.shape != (3,) or not np.isfinite(a).all() or np.linalg.norm(a) < 1e-12:
        raise InvalidInputError(f"{name} must be a finite non-zero 3-vector, got {v!r}")
    return a / np.linalg.norm(a)


@dataclass(frozen=True)
class AxisThroughPoint:
    """The ``axis`` line of ``frame`` (default: the IK frame) passes through ``point``."""

    point: tuple[float, float, float]
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    tolerance: float = 0.0  # [m]; 0 = equality
    frame: str | int | None = None

    def __post_init__(self) -> None:
        p = np.asarray(self.point, dtype=float)
        if p.shape != (3,) or not np.isfinite(p).all():
            raise InvalidInputError(f"point must be a finite 3-vector, got {self.point!r}")
        _unit(self.axis, "axis")
        if not (np.isfinite(self.tolerance) and self.tolerance >= 0.0):
            raise InvalidInputError(f"tolerance must be >= 0, got {self.tolerance!r}")


@dataclass(frozen=True)
class OrientationCone:
    """The ``axis`` of ``frame`` stays within ``half_angle`` [rad] of ``direction``."""

    direction: tuple[float, float, float]
    half_angle: float
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    frame: str | int | None = None

    def __post_init__(self) -> None:
        _unit(self.direction, "direction")
        _unit(self.axis, "axis")
        if not 0.0 <= self.half_angle <= np.pi:
            raise InvalidInputError(f"half_angle must lie in [0, pi], got {self.half_angle!r}")


Constraint = AxisThroughPoint | OrientationCone


@dataclass(frozen=True)
class ConstraintExpr:
    """Stacked constraint expression ``lbg <= g(q) <= ubg``."""

    g: Any
    lbg: np.ndarray = field(default_factory=lambda: np.zeros(0))
    ubg: np.ndarray = field(default_factory=lambda: np.zeros(0))


def _basis(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors completing ``axis`` to an orthonormal basis."""
    helper = np.eye(3)[int(np.argmin(np.abs(axis)))]
    b1 = np.cross(axis, helper)
    b1 /= np.linalg.norm(b1)
    return b1, np.cross(axis, b1)


def constraint_expr(c: Constraint, p: Any, rot: Any) -> ConstraintExpr:
    """Expression and bounds of one constraint, for a frame at ``(p, rot)``."""
    axis = _unit(c.axis, "axis")
    if isinstance(c, AxisThroughPoint):
        d = ca.DM(np.asarray(c.point, dtype=float)) - p
        if c.tolerance == 0.0:
            b1, b2 = _basis(axis)
            g = ca.vertcat(
                ca.dot(ca.mtimes(rot, ca.DM(b1)), d), ca.dot(ca.mtimes(rot, ca.DM(b2)), d)
            )
            return ConstraintExpr(g, np.zeros(2), np.zeros(2))
        along = ca.dot(ca.mtimes(rot, ca.DM(axis)), d)
        g = ca.sumsqr(d) - along * along
        return ConstraintExpr(g, np.array([-np.inf]), np.array([c.tolerance**2]))
    direction = _unit(c.direction, "direction")
    g = ca.dot(ca.mtimes(rot, ca.DM(axis)), ca.DM(direction))
    return ConstraintExpr(g, np.array([np.cos(c.half_angle)]), np.array([np.inf]))


def violation(g: np.ndarray, lbg: np.ndarray, ubg: np.ndarray) -> float:
    """Largest bound violation of ``g`` (0 when satisfied)."""
    if g.size == 0:
        return 0.0
    return float(max(0.0, np.max(lbg - g), np.max(g - ubg)))


__all__ = [
    "AxisThroughPoint",
    "Constraint",
    "ConstraintExpr",
    "OrientationCone",
    "constraint_expr",
    "violation",
]
