"""Closed form of the planar 3-RRR of paper 004 (Fig. 1): loop equations F1..F3 restored.

Geometry (all from the xacro arguments, see ``xacro/planar_3rrr.urdf.xacro``)::

    A_i = R_b (cos a_i, sin a_i)                       base pivots, driven angle q_i [rad]
    B_i = A_i + l1_i (cos q_i, sin q_i)                elbows
    C_i = O + r_p (cos(φ + b_i), sin(φ + b_i))         platform vertices, O = (x, y) [m]
    F_i(x, y, φ, q_i) = |C_i − B_i|² − l2_i² = 0       loop equation of leg i   [m²]

The paper prints F_i = (x + sin φ − x_Bi − l_i cos q_i)² + (y + cos φ − y_Bi − l_i sin q_i)² = 0:
unit platform circumradius, a clockwise angle φ_paper = −φ with b = (90°, −30°, 210°), and
the right-hand side l2_i² (the distal link length) dropped; the y-terms of F_2, F_3 are printed
with the opposite sign, which does not describe an equilateral platform (vertices at 90°, 30°,
150°) and is read as a misprint. Above, r_p, l2_i and φ are restored as independent
parameters; with r_p = 1, b = (90°, −30°, 210°) and φ = −φ_paper, F_1 is the paper's
expression minus l2_1².

Velocities (Angeles–Gosselin): differentiating F along a motion, A ẋ = −B q̇ with
A = ∂F/∂(x, y, φ) (3 × 3) and B = ∂F/∂q = diag(∂F_i/∂q_i). Rows: with u_i = C_i − B_i,
    A_i = 2 [u_iᵀ, (C_i − O) × u_i]          (a × b = a_x b_y − a_y b_x, [m², m²/rad])
    B_ii = −2 (B_i − A_i) × u_i              [m²/rad]
det B = 0: some leg has A_i, B_i, C_i aligned (type 1); det A = 0: the lines B_iC_i meet in
one point or are parallel (type 2).

Working modes: the inverse problem of leg i gives two q_i (elbow sign σ_i = ±1), 2³ = 8
modes. Assembly modes: the direct problem reduces to one trigonometric polynomial of degree
6 in φ (:func:`direct_position`), hence at most 6 (real) assembly modes.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from rcm_pin.rotations import wrap_angle as wrap


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


@dataclass(frozen=True)
class Geometry3RRR:
    """Dimensions of the 3-RRR: A (3, 2) [m], b (3,) [rad], r_p, l1 (3,), l2 (3,) [m]."""

    base: np.ndarray
    b: np.ndarray
    rp: float
    l1: np.ndarray
    l2: np.ndarray

    @classmethod
    def from_params(cls, p: Mapping[str, float]) -> Geometry3RRR:
        """From the ``params`` of the sidecar (angles in degrees)."""
        a = np.radians([p[f"base_angle_{i}"] for i in (1, 2, 3)])
        rb = p["base_radius"]
        return cls(
            base=np.stack([rb * np.cos(a), rb * np.sin(a)], axis=1),
            b=np.radians([p[f"platform_angle_{i}"] for i in (1, 2, 3)]),
            rp=float(p["platform_radius"]),
            l1=np.array([p[f"proximal_{i}"] for i in (1, 2, 3)]),
            l2=np.array([p[f"distal_{i}"] for i in (1, 2, 3)]),
        )

    def vertices(self, pose: np.ndarray) -> np.ndarray:
        """Platform vertices C (..., 3, 2) [m] for poses (..., 3) = (x, y, φ)."""
        pose = np.asarray(pose, dtype=float)
        ang = pose[..., None, 2] + self.b
        return pose[..., None, :2] + self.rp * np.stack([np.cos(ang), np.sin(ang)], axis=-1)

    def elbows(self, q: np.ndarray) -> np.ndarray:
        """Elbows B (..., 3, 2) [m] for drive angles q (..., 3) [rad]."""
        q = np.asarray(q, dtype=float)
        return self.base + self.l1[:, None] * np.stack([np.cos(q), np.sin(q)], axis=-1)


def loop_equations(g: Geometry3RRR, pose: np.ndarray, q: np.ndarray) -> np.ndarray:
    """F_i = |C_i − B_i|² − l2_i² (..., 3) [m²]."""
    u = g.vertices(pose) - g.elbows(q)
    return np.sum(u * u, axis=-1) - g.l2**2


def ab_matrices(g: Geometry3RRR, pose: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A = ∂F/∂(x, y, φ) and B = ∂F/∂q (..., 3, 3) from the closed form (module docstring)."""
    pose = np.asarray(pose, dtype=float)
    c = g.vertices(pose)
    bb = g.elbows(q)
    u = c - bb
    a_mat = 2.0 * np.concatenate([u, _cross(c - pose[..., None, :2], u)[..., None]], axis=-1)
    b_diag = -2.0 * _cross(bb - g.base, u)
    b_mat = b_diag[..., :, None] * np.eye(3)
    return a_mat, b_mat


def reachable(g: Geometry3RRR, pose: np.ndarray) -> np.ndarray:
    """Whether every leg reaches its platform vertex, |l1_i − l2_i| ≤ |A_i C_i| ≤ l1_i + l2_i
    (...,) bool: the reach mask of :func:`inverse_position` (the same 1e-12 band on the
    cosine) without computing any angle, for maps that need only reachability."""
    d = g.vertices(pose) - g.base
    dist2 = np.sum(d * d, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        cos_g = (dist2 + g.l1**2 - g.l2**2) / (2.0 * g.l1 * np.sqrt(dist2))
    return np.all(np.abs(cos_g) < 1.0 + 1e-12, axis=-1)


def inverse_position(g: Geometry3RRR, pose: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """All 8 working modes of the inverse problem, vectorised over poses.

    Mode index w = 4 s_1 + 2 s_2 + s_3 with s_i = 0 for elbow sign σ_i = +1 and 1 for −1:
    q_i = atan2(C_i − A_i) + σ_i acos((|A_iC_i|² + l1_i² − l2_i²) / (2 l1_i |A_iC_i|)).

    Args:
        g: geometry.
        pose: (..., 3) = (x [m], y [m], φ [rad]).

    Returns:
        (q (..., 8, 3) drive angles in [−π, π) [rad], reachable (...,) bool). Unreachable
        poses give NaN angles.
    """
    c = g.vertices(pose)
    d = c - g.base
    dist = np.linalg.norm(d, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        cos_g = (dist**2 + g.l1**2 - g.l2**2) / (2.0 * g.l1 * dist)
    # within 1e-12 of ±1 the leg is taken as exactly stretched / folded (type-1 pose)
    cos_g = np.where(np.abs(np.abs(cos_g) - 1.0) < 1e-12, np.sign(cos_g), cos_g)
    reach = np.all(np.abs(cos_g) <= 1.0, axis=-1)
    gam = np.arccos(np.clip(cos_g, -1.0, 1.0))
    gam = np.where(np.abs(cos_g) <= 1.0, gam, np.nan)
    theta = np.arctan2(d[..., 1], d[..., 0])
    signs = np.array([[1 - 2 * ((w >> (2 - i)) & 1) for i in range(3)] for w in range(8)])
    q = theta[..., None, :] + signs * gam[..., None, :]
    return wrap(q), reach


def passive_angles(g: Geometry3RRR, pose: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Passive joints (B1, C1, B2, B3) [rad] in Pinocchio's order for pose and drives.

    B_i (relative elbow) = atan2(C_i − B_i) − q_i; C1 = φ − q_1 − B1 (platform angle = sum of
    leg-1 joint angles, as in the xacro).
    """
    c = g.vertices(pose)
    u = c - g.elbows(q)
    rel = wrap(np.arctan2(u[..., 1], u[..., 0]) - q)
    c1 = wrap(np.asarray(pose)[..., 2] - q[..., 0] - rel[..., 0])
    return np.stack([rel[..., 0], c1, rel[..., 1], rel[..., 2]], axis=-1)


def full_q(g: Geometry3RRR, pose: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Pinocchio configuration (A1, B1, C1, A2, B2, A3, B3) (..., 7) [rad]."""
    p = passive_angles(g, pose, q)
    return np.stack(
        [q[..., 0], p[..., 0], p[..., 1], q[..., 1], p[..., 2], q[..., 2], p[..., 3]], axis=-1
    )


def _phi_polynomial_roots(g: Geometry3RRR, q: np.ndarray, n_samples: int = 64) -> np.ndarray:
    """Real roots φ of g(φ) = |adj(M) h − det(M) d_1|² − l2_1² det(M)² (degree-6 trig poly).

    With d_i(φ) = B_i − r_p(cos(φ + b_i), sin(φ + b_i)), the loop equations |O − d_i|² = l2_i²
    minus the first one are linear in O: M O = h, M = 2 [d_2 − d_1; d_3 − d_1],
    h_i = |d_i|² − |d_1|² − l2_i² + l2_1². The coefficients c_j (|j| ≤ 6) come exactly from an
    FFT of samples; the roots of z⁶ Σ c_j z^j on the unit circle are the real φ.
    """
    phis = 2.0 * np.pi * np.arange(n_samples) / n_samples
    bb = g.elbows(q)
    ang = phis[:, None] + g.b
    d = bb - g.rp * np.stack([np.cos(ang), np.sin(ang)], axis=-1)  # (S, 3, 2)
    m = 2.0 * (d[:, 1:] - d[:, :1])  # (S, 2, 2)
    nd = np.sum(d * d, axis=-1)
    h = nd[:, 1:] - nd[:, :1] - g.l2[1:] ** 2 + g.l2[0] ** 2
    det = m[:, 0, 0] * m[:, 1, 1] - m[:, 0, 1] * m[:, 1, 0]
    adj_h = np.stack(
        [m[:, 1, 1] * h[:, 0] - m[:, 0, 1] * h[:, 1], -m[:, 1, 0] * h[:, 0] + m[:, 0, 0] * h[:, 1]],
        axis=-1,
    )
    r = adj_h - det[:, None] * d[:, 0]
    vals = np.sum(r * r, axis=-1) - g.l2[0] ** 2 * det**2
    coef = np.fft.fft(vals) / n_samples  # c_j for j = 0..6 and −6..−1 (at n_samples − j)
    poly = np.array([coef[j % n_samples] for j in range(6, -7, -1)])  # z^6 c_6 ... c_-6
    scale = np.max(np.abs(poly))
    roots = np.roots(poly / scale) if scale > 0 else np.array([])
    on_circle = roots[np.abs(np.abs(roots) - 1.0) < 1e-5]
    return np.angle(on_circle)


def direct_position(g: Geometry3RRR, q: np.ndarray, tol: float = 1e-9) -> np.ndarray:
    """Every assembly mode (x, y, φ) (N, 3) for drive angles q (3,) [rad], closed form.

    Roots of the degree-6 polynomial in φ, then O from the linear system, polished by a few
    Newton steps on F (closed-form Jacobian A) and deduplicated. Modes whose residual stays
    above ``tol`` [m²] (spurious roots where M is singular) are dropped.
    """
    out: list[np.ndarray] = []
    bb = g.elbows(q)
    for phi in _phi_polynomial_roots(g, np.asarray(q, dtype=float)):
        ang = phi + g.b
        d = bb - g.rp * np.stack([np.cos(ang), np.sin(ang)], axis=-1)
        m = 2.0 * (d[1:] - d[:1])
        nd = np.sum(d * d, axis=-1)
        h = nd[1:] - nd[:1] - g.l2[1:] ** 2 + g.l2[0] ** 2
        try:
            o = np.linalg.solve(m, h)
        except np.linalg.LinAlgError:
            continue
        pose = np.array([o[0], o[1], phi])
        for _ in range(8):
            f = loop_equations(g, pose, q)
            a_mat, _ = ab_matrices(g, pose, q)
            try:
                pose = pose - np.linalg.solve(a_mat, f)
            except np.linalg.LinAlgError:
                break
        if np.all(np.isfinite(pose)) and np.max(np.abs(loop_equations(g, pose, q))) < tol:
            pose[2] = wrap(pose[2])
            if not any(np.max(np.abs(wrap(pose - p))) < 1e-7 for p in out):
                out.append(pose)
    return np.array(out).reshape(-1, 3)
