"""Direct problem of any spherical 3-RRR: one trigonometric polynomial of degree 4.

Leg 1 carries the platform in the tree: with its passive angles ψ_w (pair w_1) and ψ_v
(pair v_1), R = M(ψ_w) Rz(ψ_v) K, M = B_1 Rz(φ_1) Rx(−θ_11) Rz(ψ_w) Ry(−θ_12),
K = Ry(θ_12) Rx(θ_11) B_1ᵀ. With k_i = K v_i0 and m_i = Mᵀ w_i the loop equations of legs
2 and 3 are linear in (cos ψ_v, sin ψ_v):

    a_i cos ψ_v + b_i sin ψ_v + c_i = 0,   a_i = m_x k_x + m_y k_y,
    b_i = m_y k_x − m_x k_y,               c_i = m_z k_z − cos θ_i2          (i = 2, 3)

and (cos ψ_v, sin ψ_v) on the unit circle eliminates ψ_v:

    g(ψ_w) = (b_2 c_3 − b_3 c_2)² + (c_2 a_3 − c_3 a_2)² − (a_2 b_3 − a_3 b_2)² = 0,

a trigonometric polynomial of degree 4 in ψ_w (a_i, b_i, c_i are of degree 1): at most 8
assembly modes. Its coefficients come exactly from an FFT of 32 samples; the roots of
z⁴ g on the unit circle are the real ψ_w (the generic Newton polishes each one).
"""

from __future__ import annotations

import numpy as np

from rcm_pin.mechanisms.spherical_3rrr.closed_form import GeometrySpherical, intermediate_axes
from rcm_pin.rotations import rot_x, rot_y, rot_z

#: Roots of z⁴ g(z) farther than this from the unit circle are complex (not assemblies).
CIRCLE_TOL = 1e-6
#: Samples of g for its 9 Fourier coefficients.
SAMPLES = 32


def _coefficients(
    g: GeometrySpherical, phi: np.ndarray, psi_w: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(a, b, c) (S, 2) of legs 2, 3 at angles ψ_w (S,), and M (S, 3, 3)."""
    w = intermediate_axes(g, phi)
    base = g.B[0] @ rot_z(phi[0]) @ rot_x(-g.t1[0])
    m_mat = base @ rot_z(psi_w) @ rot_y(-g.t2[0])  # (S, 3, 3)
    k = (rot_y(g.t2[0]) @ rot_x(g.t1[0]) @ g.B[0].T @ g.v0[1:].T).T  # (2, 3): k_2, k_3
    m = np.einsum("sji,lj->sli", m_mat, w[1:])  # m_i = Mᵀ w_i, (S, 2, 3)
    a = m[..., 0] * k[:, 0] + m[..., 1] * k[:, 1]
    b = m[..., 1] * k[:, 0] - m[..., 0] * k[:, 1]
    c = m[..., 2] * k[:, 2] - np.cos(g.t2[1:])
    return a, b, c, m_mat


def _g(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    d = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    return (
        (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0]) ** 2
        + (c[:, 0] * a[:, 1] - c[:, 1] * a[:, 0]) ** 2
        - d**2
    )


def _psi_v(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> list[float]:
    """ψ_v solving both legs' a cos ψ + b sin ψ + c = 0: the 2 × 2 solve, or where the two
    equations are parallel (|a_2 b_3 − a_3 b_2| < 1e-9) the roots of one kept by the other."""
    d = a[0] * b[1] - a[1] * b[0]
    if abs(d) >= 1e-9:
        return [float(np.arctan2((c[0] * a[1] - c[1] * a[0]) / d, (b[0] * c[1] - b[1] * c[0]) / d))]
    i = int(np.argmax(np.hypot(a, b)))
    delta = a[i] ** 2 + b[i] ** 2 - c[i] ** 2
    if delta < -1e-9:
        return []
    base, chi = np.arctan2(b[i], a[i]), np.arctan2(np.sqrt(max(delta, 0.0)), -c[i])
    cands = [base - chi, base + chi]
    j = 1 - i
    return [float(x) for x in cands if abs(a[j] * np.cos(x) + b[j] * np.sin(x) + c[j]) < 1e-8]


def direct_position(g: GeometrySpherical, phi: np.ndarray) -> list[np.ndarray]:
    """Platform orientations R of every real assembly mode (module docstring)."""
    phi = np.asarray(phi, dtype=float)
    samples = 2.0 * np.pi * np.arange(SAMPLES) / SAMPLES
    values = _g(*_coefficients(g, phi, samples)[:3])
    spectrum = np.fft.fft(values) / SAMPLES  # g = Σ_j c_j e^{i j ψ}, |j| ≤ 4
    coeffs = np.array([spectrum[j % SAMPLES] for j in range(-4, 5)])  # c_-4 … c_4
    if np.max(np.abs(coeffs)) == 0.0:
        return []
    roots = np.roots(coeffs[::-1])  # z⁴ g(z) = Σ c_j z^(j+4), highest power first
    psis = np.angle(roots[np.abs(np.abs(roots) - 1.0) < CIRCLE_TOL])
    out: list[np.ndarray] = []
    if psis.size == 0:
        return out
    a, b, c, m_mat = _coefficients(g, phi, psis)
    k_mat = rot_y(g.t2[0]) @ rot_x(g.t1[0]) @ g.B[0].T
    for s in range(len(psis)):
        for psi_v in _psi_v(a[s], b[s], c[s]):
            R = m_mat[s] @ rot_z(psi_v) @ k_mat
            if not any(np.max(np.abs(R - o)) < 1e-9 for o in out):
                out.append(R)
    return out


__all__ = ["CIRCLE_TOL", "SAMPLES", "direct_position"]
