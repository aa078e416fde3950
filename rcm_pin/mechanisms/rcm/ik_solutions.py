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
        try:
            lo, up = (np.broadcast_to(np.asarray(v, float), (nq,)) for v in (lower, upper))
        except ValueError:
            raise InvalidInputError(f"limits must have shape ({nq},)") from None
        if np.isnan(lo).any() or np.isnan(up).any() or (lo > up).any():
            raise InvalidInputError(f"limits must be ({nq},) with lower <= upper, no NaN")
        angle = np.arange(nq) != 2  # q3 is a length
        best, viol = self.q.copy(), _violation(self.q, lo, up)
        for s in (2 * PI, -2 * PI):
            cand = self.q + s * angle
            v = _violation(cand, lo, up)
            better = v < viol
            best[better], viol[better] = cand[better], v[better]
        return best, np.asarray((viol <= tol).all(-1))

    def within_limits(self, lower: ArrayLike, upper: ArrayLike, tol: float = 1e-12) -> np.ndarray:
        """Bool mask ``(n_poses, n_branches)``: branch inside the limits up to ±2π wraps."""
        return self.fit_limits(lower, upper, tol)[1]
