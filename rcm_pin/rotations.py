"""Elementary rotations, roll–pitch–yaw angles, projection onto SO(3), pose parsing.

Pure numpy, vectorised over leading dimensions: an angle array of shape ``(...)`` gives
rotation matrices of shape ``(..., 3, 3)``. No Pinocchio import (this module is part of
the independent closed-form route that the tests compare Pinocchio against).

Conventions (docs/conventions.md): right-handed frames, angles in [rad], lengths in [m].
The papers' absolute orientation angles α, β, γ give R = Rz(γ)·Ry(β)·Rx(α).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rcm_pin.errors import InvalidInputError, NotARotationError

FloatArray = NDArray[np.float64]

#: Default tolerance of :func:`project_to_rotation` on the Frobenius distance ||R − R_proj||.
#: The papers' A_b rounded to three decimals is ~1e-4 away from SO(3) and passes.
ROTATION_TOL = 1e-2
#: Default tolerance on the last row [0, 0, 0, 1] of a homogeneous transform.
LAST_ROW_TOL = 1e-9
#: Largest accepted magnitude of a coordinate, target entry or angle [rad, m]: larger values
#: are meaningless for a mechanism and would overflow the squared norms of the solvers.
MAX_ABS = 1e6


def short_repr(x: object, limit: int = 60) -> str:
    """``repr(x)`` on one line, cut to ``limit`` characters (messages never dump an input)."""
    text = " ".join(repr(x).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


def numeric_array(x: object, name: str) -> FloatArray:
    """A float64 array of ``x``; strings, bytes, complex numbers and non-numbers are rejected.

    Raises:
        InvalidInputError: ``x`` is not numeric (the message shows it, cut short).
    """
    try:
        raw = np.asarray(x)
        kind = raw.dtype.kind
        if kind == "O" and any(isinstance(v, (str, bytes)) for v in raw.flat):
            kind = "U"
        if kind not in "biufO":
            raise TypeError
        return np.asarray(raw.astype(np.float64))
    except (TypeError, ValueError, OverflowError):
        raise InvalidInputError(
            f"{name} {short_repr(x)} is not numeric; valid: real numbers"
        ) from None


def check_magnitude(a: FloatArray, name: str, bound: float = MAX_ABS) -> FloatArray:
    """``a`` itself when every entry is finite with ``|value| <= bound``.

    Raises:
        InvalidInputError: NaN / infinite entries, or an entry beyond ``bound``.
    """
    if not np.isfinite(a).all():
        raise InvalidInputError(f"{name} has NaN or infinite entries; valid: finite numbers")
    worst = float(np.max(np.abs(a), initial=0.0))
    if worst > bound:
        raise InvalidInputError(
            f"{name} has an entry of magnitude {worst:.3g}; valid: |value| <= {bound:g} "
            "(larger values are meaningless for a mechanism)"
        )
    return a


def as_finite(x: ArrayLike, name: str, tail: tuple[int, ...] = ()) -> FloatArray:
    """Convert to a float64 array, checking the trailing shape and finiteness.

    Args:
        x: Input array-like.
        name: Name used in error messages.
        tail: Required trailing shape, e.g. ``(3, 3)``; ``()`` accepts any shape.

    Returns:
        The float64 array.

    Raises:
        InvalidInputError: Wrong trailing shape, non-numeric or NaN / infinite entries.
    """
    a = numeric_array(x, name)
    if tail and (a.ndim < len(tail) or a.shape[a.ndim - len(tail) :] != tail):
        want = "(..., " + ", ".join(str(t) for t in tail) + ")"
        raise InvalidInputError(f"{name} must have shape {want}, got {a.shape}")
    if not np.isfinite(a).all():
        raise InvalidInputError(f"{name} contains NaN or infinite entries")
    return a


def _elementary(angle: ArrayLike, axis: int) -> FloatArray:
    a = np.asarray(angle, dtype=np.float64)  # [rad]
    c, s = np.cos(a), np.sin(a)
    out = np.zeros((*a.shape, 3, 3))
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    out[..., axis, axis] = 1.0
    out[..., i, i] = c
    out[..., j, j] = c
    out[..., i, j] = -s
    out[..., j, i] = s
    return out


def rot_x(angle: ArrayLike) -> FloatArray:
    """Rotation about x: ``[[1, 0, 0], [0, c, −s], [0, s, c]]``.

    Args:
        angle: Angle(s) [rad], any shape ``(...)``.

    Returns:
        Rotation matrices, shape ``(..., 3, 3)``.
    """
    return _elementary(angle, 0)


def rot_y(angle: ArrayLike) -> FloatArray:
    """Rotation about y: ``[[c, 0, s], [0, 1, 0], [−s, 0, c]]``.

    Args:
        angle: Angle(s) [rad], any shape ``(...)``.

    Returns:
        Rotation matrices, shape ``(..., 3, 3)``.
    """
    return _elementary(angle, 1)


def rot_z(angle: ArrayLike) -> FloatArray:
    """Rotation about z: ``[[c, −s, 0], [s, c, 0], [0, 0, 1]]``.

    Args:
        angle: Angle(s) [rad], any shape ``(...)``.

    Returns:
        Rotation matrices, shape ``(..., 3, 3)``.
    """
    return _elementary(angle, 2)


def rpy_to_matrix(alpha: ArrayLike, beta: ArrayLike, gamma: ArrayLike) -> FloatArray:
    """The papers' absolute orientation R = Rz(γ)·Ry(β)·Rx(α).

    Elements (paper 000): x1 = cos β cos γ, x2 = cos γ sin α sin β − cos α sin γ,
    z2 = cos β sin α, z3 = cos α cos β.

    Args:
        alpha: Roll α about x [rad].
        beta: Pitch β about y [rad].
        gamma: Yaw γ about z [rad]; the three broadcast together.

    Returns:
        Rotation matrices, shape ``(..., 3, 3)``.
    """
    return rot_z(gamma) @ rot_y(beta) @ rot_x(alpha)


def matrix_to_rpy(R: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Inverse of :func:`rpy_to_matrix` with β in [−π/2, π/2].

    At cos β = 0 (gimbal lock) only α ∓ γ is determined; this returns γ = 0 there.

    Args:
        R: Rotation matrices, shape ``(..., 3, 3)``.

    Returns:
        ``(alpha, beta, gamma)`` [rad], each of shape ``(...)``.
    """
    m = as_finite(R, "R", (3, 3))
    cb = np.hypot(m[..., 0, 0], m[..., 1, 0])
    beta = np.arctan2(-m[..., 2, 0], cb)  # [rad]
    lock = cb < 1e-12
    gamma = np.where(lock, 0.0, np.arctan2(m[..., 1, 0], m[..., 0, 0]))  # [rad]
    # Gimbal lock: R = Ry(±π/2)·Rx(α ∓ γ); with γ = 0 read α from the second column.
    alpha = np.where(
        lock, np.arctan2(-m[..., 1, 2], m[..., 1, 1]), np.arctan2(m[..., 2, 1], m[..., 2, 2])
    )  # [rad]
    return alpha, beta, gamma


def project_to_rotation(R: ArrayLike, tol: float = ROTATION_TOL) -> tuple[FloatArray, FloatArray]:
    """Nearest rotation matrix (Frobenius norm) by SVD polar decomposition.

    With R = U·Σ·Vᵀ the nearest rotation is U·diag(1, 1, det(U·Vᵀ))·Vᵀ (the sign fix
    keeps det = +1 for reflections).

    Args:
        R: Matrices, shape ``(..., 3, 3)``.
        tol: Largest accepted distance ||R − R_proj||_F (default :data:`ROTATION_TOL`
            = 1e-2; a matrix rounded to three decimals is ~1e-3 away at most).

    Returns:
        ``(R_proj, distance)``: rotations ``(..., 3, 3)`` and distances ``(...)``.

    Raises:
        InvalidInputError: Wrong shape, NaN or infinite entries.
        NotARotationError: Some distance exceeds ``tol``.
    """
    m = as_finite(R, "R", (3, 3))
    big = float(np.max(np.abs(m), initial=0.0))
    if big > MAX_ABS:  # ||R - R_proj||_F >= |R_ij| - 1: no SVD of huge entries
        raise NotARotationError(
            f"matrix is not a rotation: an entry of magnitude {big:.3g} puts it farther than "
            f"{big - 1.0:.3g} from the nearest rotation, which exceeds the tolerance {tol:.3g}"
        )
    u, _, vt = np.linalg.svd(m)
    d = np.where(np.linalg.det(u @ vt) < 0.0, -1.0, 1.0)
    u[..., :, 2] *= d[..., None]
    proj = u @ vt
    dist = np.linalg.norm((m - proj).reshape(*m.shape[:-2], 9), axis=-1)
    worst = float(dist.max()) if dist.size else 0.0
    if worst > tol:
        index = tuple(int(i) for i in np.unravel_index(dist.argmax(), dist.shape))
        where = "" if dist.ndim == 0 else f" at index {index}"
        raise NotARotationError(
            f"matrix is not a rotation: distance to the nearest rotation {worst:.3g}{where} "
            f"exceeds the tolerance {tol:.3g} (Frobenius norm ||R - R_proj||)"
        )
    return proj, dist


def wrap_angle(angle: ArrayLike) -> FloatArray:
    """Angles wrapped to [−π, π) [rad] (elementwise)."""
    return np.asarray((np.asarray(angle, dtype=np.float64) + np.pi) % (2.0 * np.pi) - np.pi)


def random_rotations(rng: np.random.Generator, n: int) -> FloatArray:
    """n rotation matrices drawn uniformly on SO(3) (Haar measure), shape ``(n, 3, 3)``.

    QR decomposition of Gaussian matrices with the signs of R's diagonal moved into Q
    (Mezzadri 2007), then a column sign flip where det = −1.
    """
    a = rng.standard_normal((n, 3, 3))
    q, r = np.linalg.qr(a)
    q = q * np.sign(np.diagonal(r, axis1=-2, axis2=-1))[:, None, :]
    q[np.linalg.det(q) < 0.0, :, 0] *= -1.0
    return np.asarray(q)


def pose_from_matrix(T: ArrayLike, tol: float = LAST_ROW_TOL) -> tuple[FloatArray, FloatArray]:
    """Split homogeneous transforms into rotation part and translation.

    Args:
        T: Transforms of shape ``(..., 4, 4)`` (last row must be [0, 0, 0, 1] within
            ``tol``) or ``(..., 3, 4)``.
        tol: Tolerance on the last row.

    Returns:
        ``(R, p)``: rotation parts ``(..., 3, 3)`` (not projected, see
        :func:`project_to_rotation`) and translations ``(..., 3)`` [m].

    Raises:
        InvalidInputError: Wrong shape, NaN / infinite entries, or a bad last row.
    """
    a = as_finite(T, "T")
    if a.ndim < 2 or a.shape[-1] != 4 or a.shape[-2] not in (3, 4):
        raise InvalidInputError(f"T must have shape (..., 4, 4) or (..., 3, 4), got {a.shape}")
    if a.shape[-2] == 4:
        dev = np.abs(a[..., 3, :] - np.array([0.0, 0.0, 0.0, 1.0])).max(initial=0.0)
        if dev > tol:
            raise InvalidInputError(
                f"last row of T must be [0, 0, 0, 1] (tolerance {tol:g}), deviation {dev:.3g}"
            )
    return a[..., :3, :3], a[..., :3, 3]


__all__ = [
    "LAST_ROW_TOL",
    "MAX_ABS",
    "ROTATION_TOL",
    "as_finite",
    "check_magnitude",
    "matrix_to_rpy",
    "numeric_array",
    "pose_from_matrix",
    "project_to_rotation",
    "random_rotations",
    "rot_x",
    "rot_y",
    "rot_z",
    "rpy_to_matrix",
    "short_repr",
    "wrap_angle",
]
