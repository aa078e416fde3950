"""Branch tables, input checks and the chunked driver of the analytic IK.

Split from :mod:`rcm_pin.mechanisms.rcm.analytic_ik` (one idea per module): which angle
variant (a, −a, a + π, π − a) each coordinate takes in each branch, the screening of the
input poses (shape, NaN, last row, distance from SO(3)) and the loop over in-cache blocks.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from enum import IntEnum

import numpy as np
from numpy.typing import ArrayLike

from rcm_pin.errors import InvalidInputError
from rcm_pin.rotations import FloatArray, project_to_rotation

POS_TOL = 1e-9  # [m]
SING_TOL = 1e-9  # [-] threshold on |cos q2|, |sin q5| or |cos q5|
AXIS_TOL = 1e-9  # [m] 4-DOF: largest distance of p from the tool z axis line
CHUNK = 8192  # poses per in-cache block
_NEAR = 1e-3  # below this |sin q5| (|cos q5|) q6 is recomputed from q4 ± q6
_SCREEN = 1e-12  # rotations this close to SO(3) (first order) skip the SVD projection
PI = np.pi

Block = Callable[[FloatArray], tuple[list[FloatArray], np.ndarray]]


class _V(IntEnum):
    ID = 0  # a
    NEG = 1  # −a
    PP = 2  # a + π
    MP = 3  # π − a


_I, _N, _P, _M = _V.ID, _V.NEG, _V.PP, _V.MP
_POS = [(_I, _I, _I), (_P, _M, _I), (_P, _N, _N), (_I, _P, _N)]  # (q1, q2, q3) per k
_WRIST = {  # (q4, q5, q6) per branch b = 2k + w
    "zyz": [(_I, _I, _I), (_P, _N, _P), (_P, _I, _I), (_I, _N, _P),
            (_N, _M, _P), (_M, _P, _I), (_M, _M, _P), (_N, _P, _I)],
    "rpy": [(_I, _I, _I), (_P, _M, _P), (_P, _I, _I), (_I, _M, _P),
            (_N, _N, _P), (_M, _P, _I), (_M, _N, _P), (_N, _P, _I)],
}  # fmt: skip
_TABLE6 = {w: [_POS[b // 2] + t[b] for b in range(8)] for w, t in _WRIST.items()}
_TABLE4 = [(_I, _I, _I, _I), (_P, _M, _I, _P)]  # 4-DOF: (q1, q2, q3, q4)


def _variant(a: FloatArray, v: _V, angle: bool) -> FloatArray:
    """The variant of ``a`` ∈ (−π, π], wrapped to (−π, π] (lengths: only ±a)."""
    if v == _V.ID:
        return a
    if v == _V.NEG:
        return np.where(a < PI, -a, a) if angle else -a
    if v == _V.PP:
        return a + np.where(a > 0.0, -PI, PI)
    return np.where(a >= 0.0, PI, -PI) - a


def _expand(cols: list[FloatArray], table: Sequence[tuple[_V, ...]], out: FloatArray) -> None:
    """Branch rows out[b·nq + j] = variant(cols[j], table[b][j]) (q3, j = 2, is a length)."""
    nq = len(cols)
    for j, a in enumerate(cols):
        for v in sorted({t[j] for t in table}):
            val = _variant(a, v, j != 2)
            for row in (b * nq + j for b, t in enumerate(table) if t[j] == v):
                out[row] = val


def _components(T: FloatArray, i0: int) -> FloatArray:
    """Check a block of transforms (n, 3|4, 4); return its entries as rows (12|16, n)."""
    n, m = T.shape[0], T.shape[1] * 4
    c = np.empty((m, n))
    np.copyto(c.T, T.reshape(n, m))  # row 4·i + j holds T[:, i, j]
    if not np.isfinite(c.sum()) and not np.isfinite(c).all():
        bad = int(np.flatnonzero(~np.isfinite(c).all(0))[0]) + i0
        raise InvalidInputError(f"T contains NaN or infinite entries (first at pose {bad})")
    if m == 16 and max(np.abs(c[12:15]).max(), np.abs(c[15] - 1.0).max()) > 1e-9:
        dev = np.abs(c[12:16] - np.array([[0.0], [0.0], [0.0], [1.0]])).max(0)
        raise InvalidInputError(
            f"last row of T must be [0, 0, 0, 1] (tolerance 1e-9); pose "
            f"{int(dev.argmax()) + i0} deviates by {dev.max():.3g}"
        )
    return c


def _check_rotation(c: FloatArray, rot_tol: float) -> FloatArray:
    """Distances to SO(3); R with ||RᵀR − I||_F / 2 > 1e-12 or det ≤ 0 is SVD-projected."""
    r = c[:12].reshape(3, 4, -1)[:, :3]  # r[i, j] = R[:, i, j]
    x, y, z = r[:, 0], r[:, 1], r[:, 2]  # columns of R, each (3, n)

    def dot(u: FloatArray, v: FloatArray) -> FloatArray:
        return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]

    gxx, gyy, gzz = dot(x, x) - 1.0, dot(y, y) - 1.0, dot(z, z) - 1.0
    gxy, gxz, gyz = dot(x, y), dot(x, z), dot(y, z)
    sq = gxx * gxx + gyy * gyy + gzz * gzz + 2.0 * (gxy * gxy + gxz * gxz + gyz * gyz)
    dist = 0.5 * np.sqrt(sq)  # first-order distance ||RᵀR − I||_F / 2 (exact to O(d²))
    det = z[0] * (x[1] * y[2] - x[2] * y[1]) + z[1] * (x[2] * y[0] - x[0] * y[2])
    det += z[2] * (x[0] * y[1] - x[1] * y[0])
    bad = np.flatnonzero((dist > _SCREEN) | (det <= 0.0))
    if bad.size:
        proj, d = project_to_rotation(r[:, :, bad].transpose(2, 0, 1), rot_tol)
        r[:, :, bad] = proj.transpose(1, 2, 0)
        dist[bad] = d
    return dist


def _position(x: FloatArray, y: FloatArray, z: FloatArray, pos_tol: float, sing_tol: float):
    """Principal (q1, q2, r), ρ and the degeneracy masks (at A, along the base axis)."""
    rho = np.sqrt(y * y + z * z)
    r = np.sqrt(rho * rho + x * x)  # [m]
    a1, a2 = np.arctan2(0.0 - y, z), np.arctan2(x, rho)  # [rad] (0 − y: no −0.0)
    at_a = r <= pos_tol
    return a1, a2, r, rho, at_a, (rho <= sing_tol * r) & ~at_a


def _run(
    poses: FloatArray, block: Block, table: Sequence[tuple[_V, ...]], check: bool, rot_tol: float
) -> tuple[FloatArray, np.ndarray, FloatArray]:
    """Chunked driver: q (n, n_branches, nq) as a view of a (n_branches·nq, n) buffer."""
    n, nb, nq = len(poses), len(table), len(table[0])
    buf = np.empty((nb * nq, n))
    code = np.empty(n, dtype=np.int8)
    dist = np.zeros(n)
    with np.errstate(divide="ignore", invalid="ignore"):
        for i0 in range(0, n, CHUNK):
            c = _components(poses[i0 : i0 + CHUNK], i0)
            if check:
                dist[i0 : i0 + CHUNK] = _check_rotation(c, rot_tol)
            cols, code[i0 : i0 + CHUNK] = block(c)
            _expand(cols, table, buf[:, i0 : i0 + CHUNK])
    return buf.reshape(nb, nq, n).transpose(2, 0, 1), code, dist


def _as_poses(T: ArrayLike) -> FloatArray:
    try:
        a = np.asarray(T, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"T must be a numeric array: {exc}") from None
    if a.ndim < 2 or a.shape[-1] != 4 or a.shape[-2] not in (3, 4):
        raise InvalidInputError(f"T must have shape (..., 4, 4) or (..., 3, 4), got {a.shape}")
    return a.reshape(-1, *a.shape[-2:])


__all__ = ["AXIS_TOL", "CHUNK", "PI", "POS_TOL", "SING_TOL"]
