"""Closed form of the spherical 3-RRR of paper 004 (Fig. 5): loop equations, modes, A and B.

Geometry (``xacro/spherical_3rrr.urdf.xacro``; every axis through the centre O)::

    B_i  = Rz(yaw_i) Ry(pitch_i) Rx(roll_i)                 leg frame, u_i = B_i e_z
    w_i  = B_i Rz(φ_i) (0, sin θ_i1, cos θ_i1)              intermediate axis, φ_i driven [rad]
    v_i  = R v_i0,  v_i0 = B_i Rx(−θ_i1) Ry(−θ_i2) e_z      platform axis, R = platform orientation
    F_i  = w_i · v_i − cos θ_i2 = 0                         loop equation of leg i [1]

Inverse problem (tan(φ/2) form). With c = B_iᵀ R v_i0, F_i = A cos φ + B sin φ + C where
A = sin θ_i1 c_y, B = −sin θ_i1 c_x, C = cos θ_i1 c_z − cos θ_i2; t = tan(φ/2) gives the
quadratic (C − A) t² + 2 B t + (C + A) = 0, t = (−B ± √Δ)/(C − A), Δ = A² + B² − C². It is
evaluated in the equivalent form φ = δ ∓ χ, δ = atan2(B, A), χ = atan2(√Δ, −C) (no division,
exact at the home pose where C − A = 0). ∂F_i/∂φ_i = u_i·(w_i × v_i) = ±ρ sin χ: the root
δ − χ has u_i·(w_i × v_i) > 0, labelled ``+`` (the home pose is ``+++``), δ + χ is ``-``;
2 roots per leg, 2³ = 8 working modes, index 4 s_1 + 2 s_2 + s_3 (s_i = 1 for ``-``).

Direct problem. For θ_i2 = 90° with orthonormal platform axes v_i0 (the Agile Eye, whatever
θ_i1), Q = R V0 = [v_1 v_2 v_3] is orthonormal with v_i ⊥ w_i: v_2 = a on the great circle
⊥ w_2, v_3 = ±(a × w_3)/|a × w_3|, v_1 = det V0 · v_2 × v_3 ⊥ w_1, i.e.
(a·w_3)(a·w_1) = w_1·w_3, a trigonometric equation K0 + K1 cos 2t + K2 sin 2t = 0 in the
angle t of a (where a ∥ w_3, e.g. at home, v_1 = ±(a × w_1)/|a × w_1| is taken first):
two lines a, each with the signs of a and of v_3: 8 real solutions for every input
(measured). Four of them do not depend on the drives: R v_i0 = ±u_i for every leg
(4 sign patterns with det R = 1), where w_i ⊥ u_i = ±v_i closes each leg whatever φ_i
(all three legs in a type-1 self-motion). The other four are the assembly modes, the count
of Bonev, Chablat and Wenger ("Working and assembly modes of the Agile Eye", ICRA 2006:
four solutions to the direct kinematics); :func:`direct_position` returns those, and the
four drive-independent ones only with ``degenerate=True``. Other designs:
:mod:`rcm_pin.mechanisms.spherical_3rrr.direct` (degree-4 trigonometric polynomial; for
the Agile Eye it is ill-conditioned, with the four drive-independent roots, and unused).

Velocities: Ḟ_i = u_i·(w_i × v_i) φ̇_i + (v_i × w_i)·ω = 0, so A ω = −B φ̇ with A rows
(v_i × w_i)ᵀ and B = diag(u_i·(w_i × v_i)) [1]; det B = 0: a leg has u_i, w_i, v_i coplanar
(type 1); det A = 0: the normals w_i × v_i are linearly dependent (type 2).

Agile Eye (defaults): w_i ⊥ u_i and w_i ⊥ v_i give w_i = ±u_i × v_i/|u_i × v_i|, so
w_i × v_i ∝ u_i − (u_i·v_i) v_i, and in platform axes det A = ±D/∏|u_i × v_i| with
D = R00 R11 R22 + R01 R12 R20 = (R00 R11)² + (R01 R12)² + (R01 R11)² (cofactor identities
R22 = R00 R11 − R01 R10, R20 = R01 R12 − R02 R11 and rows 0 ⊥ 1). D = 0 forces
R02 = ±1, R10 = ±1 or R21 = ±1, i.e. some v_i ∥ u_i, which is the type-1 set: **for the
orthogonal design type 2 occurs nowhere off the type-1 set** (:func:`agile_eye_d`). The
type-1 set itself, v_i = ±u_i, is 3 legs × 2 signs = 6 curves in SO(3) (each: one
alignment, then any turn about u_i), the "six singularity curves (instead of surfaces)"
of Bonev, Chablat and Wenger; in the paper's tan φ form it is the 0/0 of F_i.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from rcm_pin.rotations import rot_x, rot_y, rot_z, rpy_to_matrix
from rcm_pin.rotations import wrap_angle as wrap

#: Δ below −DELTA_TOL is unreachable; within it the two roots of a leg merge (type 1).
DELTA_TOL = 1e-12
#: The joints of the cut-open tree, in the order of :func:`joint_angles`.
JOINTS = ("u1", "u2", "u3", "w1", "w2", "w3", "v1", "v2", "v3")


@dataclass(frozen=True)
class GeometrySpherical:
    """Leg frames B (3, 3, 3), link angles t1, t2 (3,) [rad], radii r_p, r_d [m]."""

    B: np.ndarray
    t1: np.ndarray
    t2: np.ndarray
    rp: float
    rd: float

    @classmethod
    def from_params(cls, p: Mapping[str, float]) -> GeometrySpherical:
        """From the sidecar ``params`` (angles in degrees)."""
        rpy = np.radians([[p[f"leg_{i}_{k}"] for k in ("roll", "pitch", "yaw")] for i in (1, 2, 3)])
        return cls(
            B=rpy_to_matrix(rpy[:, 0], rpy[:, 1], rpy[:, 2]),
            t1=np.radians([p[f"theta_{i}1"] for i in (1, 2, 3)]),
            t2=np.radians([p[f"theta_{i}2"] for i in (1, 2, 3)]),
            rp=float(p["proximal_radius"]),
            rd=float(p["distal_radius"]),
        )

    @property
    def u(self) -> np.ndarray:
        """Base axes u_i (3, 3), one per row."""
        return self.B[:, :, 2]

    @property
    def v0(self) -> np.ndarray:
        """Platform axes v_i0 (3, 3) at the home pose R = I, one per row."""
        return (self.B @ rot_x(-self.t1) @ rot_y(-self.t2))[:, :, 2]

    @property
    def agile_eye(self) -> bool:
        """θ_i2 = 90° and orthonormal v_i0: the direct problem has the closed form."""
        v0 = self.v0
        return bool(
            np.max(np.abs(self.t2 - np.pi / 2)) < 1e-12
            and np.max(np.abs(v0 @ v0.T - np.eye(3))) < 1e-12
        )


def intermediate_axes(g: GeometrySpherical, phi: np.ndarray) -> np.ndarray:
    """w_i (..., 3, 3) for drive angles φ (..., 3) [rad]."""
    local = np.stack([np.zeros(3), np.sin(g.t1), np.cos(g.t1)], axis=-1)
    return np.einsum("iab,...ibc,ic->...ia", g.B, rot_z(phi), local)


def platform_axes(g: GeometrySpherical, R: np.ndarray) -> np.ndarray:
    """v_i = R v_i0 (..., 3, 3), one per row, at orientations R (..., 3, 3)."""
    return g.v0 @ np.swapaxes(R, -1, -2)


def loop_residual(g: GeometrySpherical, R: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """F_i = w_i·v_i − cos θ_i2 (3,) [1]."""
    return np.sum(intermediate_axes(g, phi) * platform_axes(g, R), axis=1) - np.cos(g.t2)


def leg_coefficients(g: GeometrySpherical, R: np.ndarray) -> tuple[np.ndarray, ...]:
    """(A, B, C) (..., 3) of F_i = A cos φ_i + B sin φ_i + C at orientations R (..., 3, 3):
    with c = B_iᵀ v_i, A = sin θ_i1 c_y, B = −sin θ_i1 c_x, C = cos θ_i1 c_z − cos θ_i2."""
    cl = np.einsum("iba,...ib->...ia", g.B, platform_axes(g, R))  # c = B_iᵀ v_i
    s1 = np.sin(g.t1)
    return s1 * cl[..., 1], -s1 * cl[..., 0], np.cos(g.t1) * cl[..., 2] - np.cos(g.t2)


def leg_roots(g: GeometrySpherical, R: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per leg the roots (..., 3, 2) [rad] (``+`` then ``-``), Δ (..., 3) and ρ (..., 3) at
    orientations R (..., 3, 3) (module docstring)."""
    a, b, cc = leg_coefficients(g, R)
    delta = a * a + b * b - cc * cc
    d = np.arctan2(b, a)
    chi = np.arctan2(np.sqrt(np.maximum(delta, 0.0)), -cc)
    return wrap(np.stack([d - chi, d + chi], axis=-1)), delta, np.hypot(a, b)


def inverse_position(g: GeometrySpherical, R: np.ndarray) -> np.ndarray:
    """Drive angles (8, 3) [rad] of every working mode (index 4 s_1 + 2 s_2 + s_3).

    Callers check :func:`leg_roots` Δ ≥ −DELTA_TOL first (reachability).
    """
    roots, _, _ = leg_roots(g, R)
    w = np.arange(8)
    signs = np.stack([(w >> 2) & 1, (w >> 1) & 1, w & 1], axis=1)
    return roots[np.arange(3), signs]


def direct_position(
    g: GeometrySpherical, phi: np.ndarray, degenerate: bool = False
) -> list[np.ndarray]:
    """Platform orientations R of every assembly mode (Agile Eye closed form, module
    docstring); ``degenerate``: also the four with every v_i ∥ u_i (|u_i·v_i| > 1 − 1e-9)."""
    w = intermediate_axes(g, phi)
    v0 = g.v0
    det0 = float(np.linalg.det(v0.T))
    _, _, vt = np.linalg.svd(w[1][None, :])
    p, s = vt[1], vt[2]  # orthonormal basis of the plane ⊥ w_2
    p1, s1, p3, s3 = p @ w[0], s @ w[0], p @ w[2], s @ w[2]
    k0 = 0.5 * (p3 * p1 + s3 * s1) - w[0] @ w[2]
    k1, k2 = 0.5 * (p3 * p1 - s3 * s1), 0.5 * (p3 * s1 + s3 * p1)
    rho = np.hypot(k1, k2)
    if rho < 1e-300 or abs(k0) > rho * (1.0 + 1e-12):
        return []
    base, half = np.arctan2(k2, k1), np.arccos(np.clip(-k0 / rho, -1.0, 1.0))
    out: list[np.ndarray] = []
    for two_t in sorted({base - half, base + half}) if half > 0 else [base]:
        a0 = np.cos(two_t / 2) * p + np.sin(two_t / 2) * s
        n3, n1 = np.cross(a0, w[2]), np.cross(a0, w[0])
        for sa in (1.0, -1.0):
            for sb in (1.0, -1.0):
                v2 = sa * a0
                if np.linalg.norm(n3) >= np.linalg.norm(n1):  # the better-conditioned side
                    v3 = sb * n3 / np.linalg.norm(n3)
                    v1 = det0 * np.cross(v2, v3)
                else:  # a ∥ w_3 (e.g. at home): v_1 ⊥ a, w_1 first, then v_3
                    v1 = sb * n1 / np.linalg.norm(n1)
                    v3 = det0 * np.cross(v1, v2)
                R = np.stack([v1, v2, v3], axis=1) @ v0  # R = Q V0ᵀ with V0 = v0ᵀ
                along = np.abs(np.sum(g.u * platform_axes(g, R), axis=1)) > 1.0 - 1e-9
                if degenerate or not np.all(along):
                    out.append(R)
    return out


def joint_angles(g: GeometrySpherical, R: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """(u1, u2, u3, w1, w2, w3, v1, v2, v3) [rad] of the tree at orientation R, drives φ.

    The frame behind pair v_i (the platform for leg 1, the stub tip_i for legs 2, 3) equals
    the platform's frame platform_v_i = R B_i Rx(−θ_i1) Ry(−θ_i2) when the leg is closed.
    """
    fwb = g.B @ rot_z(phi) @ rot_x(-g.t1)  # frames of the w joints before their rotation
    vl = np.einsum("ikj,ik->ij", fwb, platform_axes(g, R))
    psi_w = np.arctan2(-vl[:, 1], -vl[:, 0])
    before_v = fwb @ rot_z(psi_w) @ rot_y(-g.t2)  # frames of the v joints before rotation
    m = np.swapaxes(before_v, -1, -2) @ R @ g.B @ rot_x(-g.t1) @ rot_y(-g.t2)
    return wrap(np.r_[phi, psi_w, np.arctan2(m[:, 1, 0], m[:, 0, 0])])


def ab_matrices(
    g: GeometrySpherical, R: np.ndarray, phi: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """A (rows (v_i × w_i)ᵀ) and B (diag u_i·(w_i × v_i)) of A ω = −B φ̇ [1]."""
    n = np.cross(intermediate_axes(g, phi), platform_axes(g, R))
    return -n, np.diag(np.sum(g.u * n, axis=1))


def measures(g: GeometrySpherical, R: np.ndarray, phi: np.ndarray) -> tuple[float, float]:
    """(type-1, type-2) measures: min |B_ii| / (sin θ_i1 sin θ_i2) and σ_min/σ_max of A with
    unit rows (0 on the singular sets)."""
    a_mat, b_mat = ab_matrices(g, R, phi)
    b_n = np.abs(np.diag(b_mat)) / (np.sin(g.t1) * np.sin(g.t2))
    sv = np.linalg.svd(a_mat / np.sin(g.t2)[:, None], compute_uv=False)
    return float(b_n.min()), float(sv[-1] / sv[0])


def agile_eye_d(R: np.ndarray) -> float:
    """D = (R00 R11)² + (R01 R12)² + (R01 R11)² (module docstring), ≥ 0."""
    return float((R[0, 0] * R[1, 1]) ** 2 + (R[0, 1] * R[1, 2]) ** 2 + (R[0, 1] * R[1, 1]) ** 2)
