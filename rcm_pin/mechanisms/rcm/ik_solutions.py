"""Result types of the analytic IK: degeneracy codes and the branch container.

Split from :mod:`rcm_pin.mechanisms.rcm.analytic_ik` (one idea per module); re-exported there.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

import numpy as np
from numpy.typing import ArrayLike

from rcm_pin.errors import InvalidInputError
from rcm_pin.mechanisms.rcm.closed_form import WristType
from rcm_pin.rotations import FloatArray

PI = np.pi


class Degeneracy(IntEnum):
    """Degeneracy code of a pose (one per pose; the first that applies, in this order)."""

    NONE = 0
    TOOL_AT_RCM = 1  # |p| ≈ 0: q3 = 0, q1, q2 (and the wrist) undetermined
    AXIS_ALONG_BASE = 2  # e4 = ±x: cos q2 = 0, q1 undetermined
    WRIST_ALIGNED = 3  # sin q5 = 0 (zyz) / cos q5 = 0 (rpy): only q4 ± q6 determined


def _violation(q: FloatArray, lower: FloatArray, upper: FloatArray) -> FloatArray:
    return np.maximum(lower - q, 0.0) + np.maximum(q - upper, 0.0)


def _shifts(nq: int) -> tuple[FloatArray, FloatArray]:
    """The shifts +2π and −2π of the angles (nq,) (q3, index 2, is a length)."""
    angle = np.arange(nq) != 2
    _SHIFTS[nq] = out = (2 * PI * angle, -2 * PI * angle)
    return out


_SHIFTS: dict[int, tuple[FloatArray, FloatArray]] = {}


@dataclass(frozen=True)
class IKSolutions:
    """All IK branches of a batch of poses.

    Attributes:
        q: Solutions, shape ``(n_poses, n_branches, nq)`` (may be a non-contiguous view);
            NaN where a coordinate is undetermined (see ``degenerate``).
        degenerate: :class:`Degeneracy` codes, int8 array ``(n_poses,)``.
        projection_distance: Frobenius distance of each input R from SO(3) ``(n_poses,)``
            (first-order estimate below 1e-12, exact SVD value above; 0 for positions).
        wrist_type: ``"zyz"``, ``"rpy"`` or ``None`` (4-DOF or position only).
    """

    q: FloatArray
    degenerate: np.ndarray
    projection_distance: FloatArray
    wrist_type: WristType

    def fit_limits(
        self, lower: ArrayLike, upper: ArrayLike, tol: float = 1e-12
    ) -> tuple[FloatArray, np.ndarray]:
        """Shift angles by ±2π into ``[lower, upper]`` where that helps.

        Args:
            lower: Lower limits ``(nq,)`` (−inf allowed) [rad, m for q3].
            upper: Upper limits ``(nq,)``.
            tol: Accepted violation.

        Returns:
            ``(q_fitted, ok)``: ``q_fitted`` like ``q`` (each angle as q, q + 2π or
            q − 2π, the one closest to the box) and ``ok`` ``(n_poses, n_branches)``.
        """
        nq = self.q.shape[-1]
        lo, up = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
        if lo.shape not in ((), (1,), (nq,)) or up.shape not in ((), (1,), (nq,)):
            raise InvalidInputError(f"limits must have shape ({nq},)")
        if not (lo <= up).all():  # (NaN fails the comparison)
            raise InvalidInputError(f"limits must be ({nq},) with lower <= upper, no NaN")
        # q, then q + 2π, then q − 2π (angles only) where strictly closer to the box;
        # |x − min(max(x, lower), upper)| is the violation max(lower − x, 0) +
        # max(x − upper, 0), bit for bit
        q, low, high = self.q, np.maximum, np.minimum
        best, viol = q, np.abs(q - high(low(q, lo), up))
        for shift in _SHIFTS.get(nq) or _shifts(nq):
            cand = q + shift
            v = np.abs(cand - high(low(cand, lo), up))
            better = v < viol
            best, viol = np.where(better, cand, best), np.where(better, v, viol)
        return best, np.asarray((viol <= tol).all(-1))  # (np.where: a new array, not q)

    def within_limits(self, lower: ArrayLike, upper: ArrayLike, tol: float = 1e-12) -> np.ndarray:
        """Bool mask ``(n_poses, n_branches)``: branch inside the limits up to ±2π wraps."""
        return self.fit_limits(lower, upper, tol)[1]
