"""Singularity maps of the spherical 3-RRR in tilt-and-torsion angles, vectorised.

A designer reads a spherical wrist by where its platform axis points and how far the platform
turns about it. With the symmetry axis n = Σ u_i / |Σ u_i| of the base (n = (1, 1, 1)/√3 for
the Agile Eye; e_z when Σ u_i = 0) and a frame F0 = [e1 e2 n], the tilt-and-torsion angles of
Bonev et al. are

    R(θ, φ, σ) = F0 Rz(φ) Ry(θ) Rz(σ − φ) F0ᵀ        θ ∈ [0, π] tilt, φ azimuth, σ torsion [rad]

so that R n has tilt θ from n at azimuth φ, and R = I at θ = σ = 0 (the home pose).

Measures of one working mode (:func:`measures`; the closed form of :mod:`.closed_form`,
batched): type 1, min_i |B_ii|/(sin θ_i1 sin θ_i2) ∈ [0, 1]; type 2, σ_min/σ_max of A with
rows (v_i × w_i)/sin θ_i2. Both vanish exactly on the singular sets; NaN where a leg cannot
reach (Δ_i < 0).

Singular curves (:func:`singular_curves`). For the Agile Eye Δ_i = ρ_i² (C_i = 0), so every
orientation is reachable and B_ii = ±ρ_i = ±|u_i × v_i| vanishes only where v_i = ±u_i; type 2
occurs nowhere else (:func:`.closed_form.agile_eye_d`) and everywhere there but at the curves'
meeting points: with v_i = ±u_i every row of A is ⊥ u_i (row i = v_i × w_i, rows j ∝
u_j − (u_j·v_j) v_j with u_j, v_j ⊥ u_i), so det A = 0; where all three legs align (the four
drive-independent orientations) the free drives decide. These are six curves in SO(3):
R = Rot(u_i, t) R_is, R_is the rotation of least angle taking v_i0 to s u_i (s = ±1),
t ∈ [0, 2π). In tilt-and-torsion angles they are curves (θ(t), φ(t), σ(t)), and each slice of
constant torsion meets them in points, not curves: the maps at fixed σ show the measures
falling to 0 at isolated points.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rcm_pin.mechanisms.spherical_3rrr.closed_form import (
    DELTA_TOL,
    GeometrySpherical,
    intermediate_axes,
    leg_roots,
    platform_axes,
)
from rcm_pin.rotations import rot_y, rot_z
from rcm_pin.rotations import wrap_angle as wrap


def symmetry_axis(g: GeometrySpherical) -> np.ndarray:
    """n = Σ u_i / |Σ u_i| (e_z when the base axes sum to zero)."""
    s = g.u.sum(axis=0)
    return s / np.linalg.norm(s) if np.linalg.norm(s) > 1e-9 else np.array([0.0, 0.0, 1.0])


def axis_frame(n: np.ndarray) -> np.ndarray:
    """F0 (3, 3), orthonormal, third column n (first column ⊥ n, in the plane of n and the
    world axis least aligned with n)."""
    e = np.eye(3)[int(np.argmin(np.abs(n)))]
    e1 = e - (e @ n) * n
    e1 /= np.linalg.norm(e1)
    return np.stack([e1, np.cross(n, e1), n], axis=1)


def tt_rotation(n: np.ndarray, tilt: Any, azimuth: Any, torsion: Any) -> np.ndarray:
    """R(θ, φ, σ) (..., 3, 3) of broadcast angle arrays [rad] (module docstring)."""
    f0 = axis_frame(n)
    t, a, s = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (tilt, azimuth, torsion)))
    return f0 @ rot_z(a) @ rot_y(t) @ rot_z(s - a) @ f0.T


def tt_angles(n: np.ndarray, R: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(θ, φ, σ) [rad] of rotations R (..., 3, 3), φ and σ in [−π, π); at θ = 0, φ = 0 and
    σ the turn about n."""
    f0 = axis_frame(n)
    m = f0.T @ R @ f0
    tilt = np.arctan2(np.hypot(m[..., 0, 2], m[..., 1, 2]), m[..., 2, 2])  # exact near 0, π
    flat = np.hypot(m[..., 0, 2], m[..., 1, 2]) < 1e-12
    az = np.where(flat, 0.0, np.arctan2(m[..., 1, 2], m[..., 0, 2]))
    rest = rot_y(-tilt) @ rot_z(-az) @ m  # = Rz(σ − φ)
    return tilt, az, wrap(np.arctan2(rest[..., 1, 0], rest[..., 0, 0]) + az)


def _legs(g: GeometrySpherical, R: np.ndarray, mode: int) -> tuple[np.ndarray, ...]:
    """Rows of A / sin θ_i2 (..., 3, 3), B_ii / (sin θ_i1 sin θ_i2) (..., 3) and the
    unreachable mask (...) of working mode ``mode`` at rotations R (..., 3, 3)."""
    roots, delta, _ = leg_roots(g, R)
    bits = np.array([(mode >> 2) & 1, (mode >> 1) & 1, mode & 1])  # 0 for "+", 1 for "-"
    w = intermediate_axes(g, roots[..., np.arange(3), bits])
    v = platform_axes(g, R)
    nrm = np.cross(w, v) / np.sin(g.t2)[:, None]
    b_diag = np.sum(g.u * nrm, axis=-1) / np.sin(g.t1)
    return -nrm, b_diag, np.any(delta < -DELTA_TOL, axis=-1)


def measures(g: GeometrySpherical, R: np.ndarray, mode: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """(type-1, type-2) measures (...) of working mode ``mode`` (index 4 s_1 + 2 s_2 + s_3)
    at rotations R (..., 3, 3); NaN where a leg cannot reach."""
    a_rows, b_diag, bad = _legs(g, R, mode)
    type1 = np.min(np.abs(b_diag), axis=-1)
    sv = np.linalg.svd(a_rows, compute_uv=False)
    type2 = sv[..., -1] / sv[..., 0]
    return np.where(bad, np.nan, type1), np.where(bad, np.nan, type2)


def determinants(g: GeometrySpherical, R: np.ndarray, mode: int = 0) -> tuple[np.ndarray, ...]:
    """Signed det A and det B (...) of the normalised rows (:func:`measures`), NaN where a
    leg cannot reach: their zero contours are the type-2 and type-1 curves of a slice."""
    a_rows, b_diag, bad = _legs(g, R, mode)
    det_a, det_b = np.linalg.det(a_rows), np.prod(b_diag, axis=-1)
    return np.where(bad, np.nan, det_a), np.where(bad, np.nan, det_b)


def _least_rotation(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The rotation of least angle taking unit a to unit b (a = −b: a half turn about an
    axis ⊥ a, Eigen's choice)."""
    import pinocchio as pin

    return np.asarray(pin.Quaternion.FromTwoVectors(a, b).matrix())


def _axis_angle(u: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Rot(u, t) (S, 3, 3) for unit u and angles t (S,) [rad] (``pin.exp3``)."""
    import pinocchio as pin

    return np.array([pin.exp3(u * ti) for ti in t]).reshape(-1, 3, 3)


def curve_rotations(g: GeometrySpherical, leg: int, sign: float, t: np.ndarray) -> np.ndarray:
    """Rotations (S, 3, 3) on the singular curve v_leg = sign·u_leg at parameters t [rad]."""
    base = _least_rotation(g.v0[leg], sign * g.u[leg])
    return _axis_angle(g.u[leg], np.asarray(t, dtype=float)) @ base


def singular_curves(g: GeometrySpherical, n: np.ndarray, samples: int = 721) -> list[dict]:
    """The six type-1 curves of the Agile Eye (also its type-2 set) in (θ, φ, σ) [rad]:
    ``[{"leg", "sign", "tilt", "azimuth", "torsion"}]`` (module docstring).

    Raises:
        ValueError: not an Agile Eye (other designs have singular surfaces: use the maps).
    """
    if not g.agile_eye:
        raise ValueError("singular curves are the Agile Eye's (θ_i2 = 90°, orthonormal v_i0)")
    t = np.linspace(0.0, 2.0 * np.pi, samples)
    out = []
    for leg in range(3):
        for sign in (1.0, -1.0):
            tilt, az, tor = tt_angles(n, curve_rotations(g, leg, sign, t))
            out.append({"leg": leg + 1, "sign": sign, "tilt": tilt, "azimuth": az, "torsion": tor})
    return out


__all__ = [
    "axis_frame",
    "curve_rotations",
    "determinants",
    "measures",
    "singular_curves",
    "symmetry_axis",
    "tt_angles",
    "tt_rotation",
]
