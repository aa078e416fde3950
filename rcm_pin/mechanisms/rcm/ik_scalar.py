"""The analytic IK of one regular six-DOF pose in scalar arithmetic (the one-pose fast path).

The vectorised IK (:mod:`.analytic_ik`) pays numpy's per-call overhead on every array it
touches, about 0.4 ms for one pose. This module computes the same eight branches with the
``math`` module for the common case: a finite 3×4 / 4×4 pose whose rotation passes the
first-order SO(3) screen (distance ≤ 1e-12, det > 0), away from every degeneracy
(|p| > pos_tol, ρ > sing_tol·|p|) and from the near-aligned wrist band (|sin q5| or
|cos q5| ≥ 1e-3, where the vectorised code recomputes q6 from q4 ± q6). Anything else
returns None and the caller runs the vectorised code, so both give the same branches in the
same order (tests compare them to 1e-12 on random poses). The formulas are those of
:func:`.analytic_ik._block6` and the branch table of :mod:`.ik_tables`.
"""

from __future__ import annotations

import math
from operator import itemgetter

import numpy as np

from rcm_pin.mechanisms.rcm.ik_tables import _NEAR, _SCREEN, _TABLE6, POS_TOL, SING_TOL
from rcm_pin.model.so3_defect import so3_defect

PI = math.pi
#: Per wrist type, an itemgetter picking the 48 branch entries (8 branches × q1..q6, row-
#: major) from the 24 variants (a, −a, a + π, π − a) of the six principal coordinates.
_PICK = {
    w: itemgetter(*(4 * i + int(v) for branch in t for i, v in enumerate(branch)))
    for w, t in _TABLE6.items()
}


def _variants(a: float) -> tuple[float, float, float, float]:
    """(a, −a, a + π, π − a) of an angle in (−π, π], each wrapped to (−π, π]: the scalar
    twin of :func:`.ik_tables._variant`, indexed by :class:`.ik_tables._V`."""
    return (
        a,
        -a if a < PI else a,
        a + (-PI if a > 0.0 else PI),
        (PI if a >= 0.0 else -PI) - a,
    )


def _screen(r: list[float]) -> float | None:
    """First-order distance of R (row-major 9 entries) from SO(3), or None if it needs the
    SVD projection (distance > 1e-12 or det ≤ 0)."""
    sq, det = so3_defect(r)
    dist = 0.5 * math.sqrt(sq)
    return dist if dist <= _SCREEN and det > 0.0 else None


def ik_pose_one(
    T: np.ndarray, wrist: str, pos_tol: float = POS_TOL, sing_tol: float = SING_TOL
) -> tuple[np.ndarray, float] | None:
    """The eight branches (8, 6) and the projection distance of one regular pose, or None
    when the pose needs the vectorised code (module docstring).

    Args:
        T: a float64 array (4, 4) or (3, 4) [m].
        wrist: ``"zyz"`` or ``"rpy"``.
    """
    c = T.ravel().tolist()
    if len(c) == 16 and (c[12] != 0.0 or c[13] != 0.0 or c[14] != 0.0 or c[15] != 1.0):
        return None
    if not all(map(math.isfinite, c)):
        return None
    dist = _screen([c[0], c[1], c[2], c[4], c[5], c[6], c[8], c[9], c[10]])
    if dist is None:
        return None
    x, y, z = c[3], c[7], c[11]
    rho = math.sqrt(y * y + z * z)
    r = math.sqrt(rho * rho + x * x)  # [m]
    if r <= pos_tol or rho <= sing_tol * r:
        return None
    a1, a2 = math.atan2(0.0 - y, z), math.atan2(x, rho)  # [rad]
    ir, irho = 1.0 / r, 1.0 / rho
    ex, ey, ez = x * ir, y * ir, z * ir  # e4 = p/r
    c1, s1, c2 = z * irho, -y * irho, rho * ir
    s1s2, c1s2 = s1 * ex, c1 * ex
    j, k, m = (2, 0, 1) if wrist == "zyz" else (0, 2, 1)
    w2j = ex * c[j] + ey * c[4 + j] + ez * c[8 + j]  # Rw[2, j] = e4·R[:, j]
    w2k = ex * c[k] + ey * c[4 + k] + ez * c[8 + k]
    w2m = ex * c[m] + ey * c[4 + m] + ez * c[8 + m]
    w0j = c2 * c[j] + s1s2 * c[4 + j] - c1s2 * c[8 + j]
    w1j = c1 * c[4 + j] + s1 * c[8 + j]
    h = math.sqrt(w0j * w0j + w1j * w1j)  # |sin q5| (zyz) or |cos q5| (rpy)
    if h < _NEAR:
        return None
    a4 = math.atan2(w1j, w0j)
    if wrist == "zyz":
        a5, a6 = math.atan2(h, w2j), math.atan2(w2m, -w2k)
    else:
        a5, a6 = math.atan2(-w2j, h), math.atan2(w2m, w2k)
    values = (  # q3 is a length: only ±r
        *_variants(a1), *_variants(a2), r, -r, r, r,
        *_variants(a4), *_variants(a5), *_variants(a6),
    )  # fmt: skip
    return np.array(_PICK[wrist](values)).reshape(8, 6), dist


__all__ = ["ik_pose_one"]
