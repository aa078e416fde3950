"""IK inputs: targets as parameter vectors, joint boxes and start configurations.

A target is stored as the 12-vector ``[p_t; vec(R_t)]`` (column-major ``R_t``), the NLP
parameter of every IK solver. Continuous joints (a ``(cos, sin)`` pair in ``q``) are never
box-bounded; their start value is the angle 0 (mid-range) or a uniform angle (random).
The ``"output"`` mode of a Mechanism takes the value vector of its output coordinates
(:func:`output_target`).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pinocchio as pin

from ocp.symbolic import SymbolicModel
from rcm_pin.errors import InvalidInputError
from rcm_pin.model.output import POSE, Output

_EYE = np.eye(3)


def target_vector(target: Any, mode: str) -> np.ndarray:
    """``[p_t; vec(R_t)]`` (12,) from a 4x4 pose, a ``pin.SE3`` or (``mode="position"``)
    a 3-vector."""
    if isinstance(target, pin.SE3):
        target = target.homogeneous
    t = np.asarray(target, dtype=float)
    if not np.isfinite(t).all():
        raise InvalidInputError("target has NaN or infinite entries")
    out = np.zeros(12)
    out[3:] = _EYE.reshape(-1, order="F")
    if t.shape == (3,) and mode == "position":
        out[:3] = t
        return out
    if t.shape in ((4, 4), (3, 4)):
        rot = t[:3, :3]
        det = rot[0] @ np.cross(rot[1], rot[2])
        if np.abs(rot.T @ rot - _EYE).max() > 1e-9 or det < 0:
            raise InvalidInputError("target rotation is not a rotation matrix (tol 1e-9)")
        out[:3], out[3:] = t[:3, 3], rot.reshape(-1, order="F")
        return out
    raise InvalidInputError(
        f"target must be a (4, 4) pose, pin.SE3 or (3,) position in mode='position'; "
        f"got shape {t.shape} in mode={mode!r}"
    )


def output_target(output: Output, target: Any) -> np.ndarray:
    """The value vector (output.size,) of an output target: the output coordinates'
    values (a rotation as 9 numbers row by row, or a 3x3), or, for a pose output
    (x, y, z, rotation), also a 4x4 pose or a ``pin.SE3``.

    Raises:
        InvalidInputError: wrong length or non-finite entries.
        NotARotationError: a rotation too far from SO(3).
    """
    if isinstance(target, pin.SE3):
        target = target.homogeneous
    if output.coords == POSE:
        t = np.asarray(target, dtype=float)
        if t.shape in ((4, 4), (3, 4)):
            target = np.concatenate([t[:3, 3], t[:3, :3].reshape(9)])
    return output.coerce(target)


def _continuous(sm: SymbolicModel) -> list[int]:
    return [j.idx_q for j in sm.joints if j.kind == "revolute_unbounded" and not j.mimic]


def box(sm: SymbolicModel, lower: Any, upper: Any) -> tuple[np.ndarray, np.ndarray]:
    """Joint box (default: the model's limits); continuous joints unbounded."""
    lo = np.array(sm.model.lowerPositionLimit if lower is None else lower, dtype=float)
    hi = np.array(sm.model.upperPositionLimit if upper is None else upper, dtype=float)
    if lo.shape != (sm.nq,) or hi.shape != (sm.nq,) or np.any(lo > hi):
        raise InvalidInputError(f"lower/upper must be ({sm.nq},) arrays with lower <= upper")
    for i in _continuous(sm):
        lo[i : i + 2], hi[i : i + 2] = -np.inf, np.inf
    return lo, hi


def start_configuration(sm: SymbolicModel, q0: Any, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """``q0`` checked and clipped into the box; ``None``: the middle of the box."""
    if q0 is None:
        mid = np.where(np.isfinite(lo) & np.isfinite(hi), 0.5 * (lo + hi), 0.0)
        for i in _continuous(sm):
            mid[i : i + 2] = 1.0, 0.0
        return mid
    q = np.asarray(q0, dtype=float)
    if q.shape != (sm.nq,) or not np.isfinite(q).all():
        raise InvalidInputError(f"q0 must be a finite ({sm.nq},) array")
    return np.clip(q, lo, hi)


def random_configuration(
    sm: SymbolicModel, lo: np.ndarray, hi: np.ndarray, rng: np.random.Generator
) -> np.ndarray:
    """Uniform within the finite box (infinite sides: +-pi; continuous: uniform angle)."""
    q = rng.uniform(np.where(np.isfinite(lo), lo, -np.pi), np.where(np.isfinite(hi), hi, np.pi))
    for i in _continuous(sm):
        a = rng.uniform(-np.pi, np.pi)
        q[i : i + 2] = np.cos(a), np.sin(a)
    return q


__all__ = [
    "box",
    "output_target",
    "random_configuration",
    "start_configuration",
    "target_vector",
]
