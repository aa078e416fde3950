"""Paper 004's tan φ equations F1..F3 of the Agile Eye, and A, B from their derivatives.

With R = Rz(γ)Ry(β)Rx(α) and the legs u_i = e_i, w_i0 = e_{i+1}, v_i0 = e_{i+2} (the xacro's
defaults), F_i = tg φ_i − f_i(α, β, γ) = 0 (module docstring of the family for the F1
misprint). Differentiating, ∂f/∂(α, β, γ) · (α̇, β̇, γ̇) = diag(1/cos² φ_i) φ̇, so in the
Angeles–Gosselin form A_p ṙ = −B_p φ̇ with A_p = −∂f/∂(α, β, γ), B_p = diag(1/cos² φ_i) and
ω = E(α, β, γ) ṙ (E: :func:`rate_matrix`). The derivatives are taken by complex step
(f is analytic): exact to rounding, no step-size error. This is the third route to the output
Jacobian beside Pinocchio's constraints and the loop equations w_i·v_i = cos θ_i2.
"""

from __future__ import annotations

import numpy as np

#: Complex-step size [rad].
STEP = 1e-30


def tan_phi(alpha: complex, beta: complex, gamma: complex) -> dict[str, np.ndarray]:
    """tan φ_i of the paper's F1..F3: ``printed`` and ``corrected`` (3,) each.

    F1 as printed, tg φ11 = (cos γ sin γ sin β + cos γ sin α)/(cos α cos β), is not the
    loop equation of leg 1 (u_1 = x, w_10 = y, v_10 = z): w_1 ⊥ R e_z gives
    tg φ11 = −R_12/R_22 = (cos γ sin α − sin γ sin β cos α)/(cos α cos β) (cos α misprinted
    as cos γ in the first term, and its sign). F2, F3 as printed are right.
    """
    sa, ca, sb, cb, sg, cg = (f(x) for x in (alpha, beta, gamma) for f in (np.sin, np.cos))
    f2 = sb / (cg * cb)
    f3 = -(cg * sb * sa - ca * sg) / (ca * cg + sa * sb * sg)
    printed = np.array([(cg * sg * sb + cg * sa) / (ca * cb), f2, f3])
    corrected = np.array([(cg * sa - sg * sb * ca) / (ca * cb), f2, f3])
    return {"printed": printed, "corrected": corrected}


def rate_matrix(alpha: float, beta: float, gamma: float) -> np.ndarray:
    """E (3, 3) with ω = E (α̇, β̇, γ̇) (world axes) for R = Rz(γ)Ry(β)Rx(α)."""
    cb, sb, cg, sg = np.cos(beta), np.sin(beta), np.cos(gamma), np.sin(gamma)
    x_axis = np.array([cg * cb, sg * cb, -sb])  # Rz(γ)Ry(β) e_x
    y_axis = np.array([-sg, cg, 0.0])  # Rz(γ) e_y
    return np.stack([x_axis, y_axis, np.array([0.0, 0.0, 1.0])], axis=1)


def ab_matrices(angles: np.ndarray, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A_p (on (α̇, β̇, γ̇)) and B_p of the corrected F1..F3 (module docstring) [1]."""
    a_p = np.zeros((3, 3))
    for j in range(3):
        z = np.asarray(angles, dtype=complex)
        z[j] += 1j * STEP
        a_p[:, j] = -np.imag(tan_phi(*z)["corrected"]) / STEP
    return a_p, np.diag(1.0 / np.cos(phi) ** 2)


def output_jacobian(angles: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """ω = J φ̇ from the paper's equations: J = −E A_p⁻¹ B_p (3, 3)."""
    a_p, b_p = ab_matrices(angles, phi)
    return -rate_matrix(*angles) @ np.linalg.solve(a_p, b_p)


__all__ = ["STEP", "ab_matrices", "output_jacobian", "rate_matrix", "tan_phi"]
