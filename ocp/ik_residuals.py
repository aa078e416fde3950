"""The IK residual r(q, target) of each mode, with the errors reported beside it.

* ``"pose"``: r = [w_p (p − p_t); w_o vec(R − R_t)], target [p_t; vec(R_t)] (12,);
* ``"position"``: r = w_p (p − p_t), same target layout (R_t unused);
* ``"output"``: the output coordinates of a Mechanism (:class:`rcm_pin.Output`, e.g.
  x, y, rz of the 3-RRR platform), target the value vector of the output (rotation as 9
  numbers, row by row). Per token:

      x, y, z:       w_p (p_i − t)                                  [m]
      rx, ry, rz:    w_o [R_jj / ρ − cos t ;  R_ij / ρ − sin t]      ρ = |(R_ij, R_jj)|
      rotation:      w_o vec(R − R_t)

  with (i, j) of the token's angle atan2(R_ij, R_jj) (:meth:`rcm_pin.Output.value`). The
  angle rows vanish exactly at θ = t (mod 2π), |rows| = 2 |sin((θ − t) / 2)|: smooth, no
  wrap-around, like the Frobenius rows (|R − R_t|_F = 2√2 sin(Δ/2)).

Reported errors: |p − p_t| over the translation tokens [m], and the largest angle error
over the angular tokens [rad] (NaN without one).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

import casadi as ca
import numpy as np

from rcm_pin.model.output import Output

Mode = Literal["pose", "position", "output"]
_ANGLE = {"rx": (2, 1), "ry": (0, 2), "rz": (1, 0)}  # value = atan2(R[i, j], R[j, j])
_AXIS = {"x": 0, "y": 1, "z": 2}


@dataclass(frozen=True)
class Residual:
    """The residual of one mode and its error expressions.

    Attributes:
        target: the target parameter symbol.
        r: weighted residual (column).
        position_error: |p − p_t| [m] (0 without translation).
        orientation_error: rotation angle between R and R_t [rad] (NaN without one).
    """

    target: Any
    r: Any
    position_error: Any
    orientation_error: Any


def _rotation_angle(rot: Any, rot_t: Any) -> Any:
    """Angle [rad] between two rotations from their Frobenius distance."""
    return 2.0 * ca.asin(ca.fmin(1.0, ca.norm_fro(rot - rot_t) / (2.0 * np.sqrt(2.0))))


def pose_residual(mode: Mode, p: Any, rot: Any, wp: float, wo: float) -> Residual:
    """Residual of the ``"pose"`` or ``"position"`` mode (target (12,))."""
    target = ca.SX.sym("target", 12)
    r = wp * (p - target[:3])
    rot_t = ca.reshape(target[3:], 3, 3)
    if mode == "pose":
        r = ca.vertcat(r, wo * ca.vec(rot - rot_t))
    angle = _rotation_angle(rot, rot_t) if mode == "pose" else ca.DM(np.nan)
    return Residual(target, r, ca.norm_2(p - target[:3]), angle)


def output_residual(output: Output, p: Any, rot: Any, wp: float, wo: float) -> Residual:
    """Residual of the ``"output"`` mode (target (output.size,), module docstring)."""
    target = ca.SX.sym("target", output.size)
    rows: list[Any] = []
    shifts: list[Any] = []
    angles: list[Any] = []
    k = 0
    for c in output.coords:
        if c in _AXIS:
            d = p[_AXIS[c]] - target[k]
            rows.append(wp * d)
            shifts.append(d)
            k += 1
        elif c == "rotation":
            rot_t = ca.reshape(target[k : k + 9], 3, 3).T  # row-major values
            rows.append(wo * ca.vec(rot - rot_t))
            angles.append(_rotation_angle(rot, rot_t))
            k += 9
        else:
            i, j = _ANGLE[c]
            a, b = rot[i, j], rot[j, j]
            rho = ca.sqrt(a * a + b * b)
            ct, st = ca.cos(target[k]), ca.sin(target[k])
            rows += [wo * (b / rho - ct), wo * (a / rho - st)]
            angles.append(ca.fabs(ca.atan2(a * ct - b * st, b * ct + a * st)))
            k += 1
    pos = ca.norm_2(ca.vertcat(*shifts)) if shifts else ca.DM(0.0)
    ang = ca.mmax(ca.vertcat(*angles)) if angles else ca.DM(np.nan)
    return Residual(target, ca.vertcat(*rows), pos, ang)


__all__ = ["Mode", "Residual", "output_residual", "pose_residual"]
