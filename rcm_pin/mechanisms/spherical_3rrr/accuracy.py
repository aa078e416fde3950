"""Accuracy of the spherical 3-RRR by paper 004's linear theory, beside the nonlinear change.

Drives locked. Error variables: the link angles θ_i1 = angle(u_i, w_i), θ_i2 = angle(w_i, v_i)
(the platform's axes v_i0 keep their nominal directions: a link is made wrong, not the
platform) and the drive angles φ_i (an encoder offset). With x = (α, β, γ),
R = Rz(γ)Ry(β)Rx(α), the loop equations of paper 004 with the extra variables are

    F_i(x, φ, θ) = w_i(φ_i, θ_i1) · R(x) v_i0 − cos θ_i2 = 0,
    w_i = B_i Rz(φ_i) (0, sin θ_i1, cos θ_i1)                                   [1]

Linear theory: J δx = W, J = ∂F/∂x (3 × 3), W = −(∂F/∂θ δθ + ∂F/∂φ δφ) (the paper's
"coefficients" W_1..W_3), solved by Cramer's rule δα = det J_1 / det J (J_1: J with column 1
replaced by W). The paper prints

    δα = (F1β F2γ W3 − F1β F3γ W2 − F1γ F2β W3 + F1γ F3β W2 + F2β F2γ W1 − F2γ F3β W1)
         / (F1α F2β F3γ − F1β F2γ F3β − F1β F2α F3γ + F1β F3α F2γ + F2α F1γ F3β − F1γ F2β F3α)

(Fiβ = ∂F_i/∂β). The cofactor expansion of det J_1 along its first column has
W1 (F2β F3γ − F2γ F3β): the fifth numerator term F2β **F2γ** W1 is a misprint for
F2β **F3γ** W1. det J = F1α (F2β F3γ − F2γ F3β) − F1β (F2α F3γ − F2γ F3α) + F1γ (...): the
second denominator term **F1β** F2γ F3β is a misprint for **F1α** F2γ F3β (as printed, F1α
appears once and the expansion is not a determinant). The other ten terms are right.
:func:`cramer_delta_alpha` evaluates both.

Derivatives (two routes): closed form, ∂F_i/∂x = ((v_i × w_i)ᵀ E(x)) (E: ω = E ẋ, :mod:`.paper`),
∂F_i/∂θ_i1 = (B_i Rz(φ_i)(0, cos θ_i1, −sin θ_i1))·v_i, ∂F_i/∂θ_i2 = sin θ_i2,
∂F_i/∂φ_i = u_i·(w_i × v_i); and complex step on F (tests). Nonlinear change: F = 0 re-solved
by Newton from x on the perturbed design (:func:`nonlinear_error`); its second route is
Pinocchio (the generic placement errors of :mod:`rcm_pin.analysis.accuracy`: a turn δ of the
placement of pair w_i about its x axis is δθ_i1 = −δ, of pair v_i about its y axis δθ_i2 = −δ).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rcm_pin.analysis.accuracy import cramer
from rcm_pin.errors import SolverError
from rcm_pin.mechanisms.spherical_3rrr import paper
from rcm_pin.mechanisms.spherical_3rrr.closed_form import GeometrySpherical

#: The error variables, in the order of the columns of :func:`error_jacobian`.
PARAMETERS = ("theta_11", "theta_21", "theta_31", "theta_12", "theta_22", "theta_32",
              "phi_1", "phi_2", "phi_3")  # fmt: skip


def _rpy(x: np.ndarray) -> np.ndarray:
    """R = Rz(γ)Ry(β)Rx(α), real or complex (for the complex step)."""
    (ca, cb, cg), (sa, sb, sg) = np.cos(x), np.sin(x)
    return np.array(
        [
            [cb * cg, cg * sa * sb - ca * sg, sa * sg + ca * cg * sb],
            [cb * sg, ca * cg + sa * sb * sg, ca * sb * sg - cg * sa],
            [-sb, cb * sa, ca * cb],
        ]
    )


def residual(g: GeometrySpherical, x: np.ndarray, p: np.ndarray, v0: np.ndarray) -> np.ndarray:
    """F (3,) at angles x (3,) and errors-included variables p = (θ_i1, θ_i2, φ_i) (9,)
    [rad], platform axes v0 (3, 3) (module docstring); real or complex."""
    t1, t2, phi = p[:3], p[3:6], p[6:]
    local = np.stack([-np.sin(phi) * np.sin(t1), np.cos(phi) * np.sin(t1), np.cos(t1)], axis=1)
    w = np.einsum("iab,ib->ia", g.B, local)
    v = v0 @ _rpy(x).T
    return np.sum(w * v, axis=1) - np.cos(t2)


def variables(g: GeometrySpherical, phi: np.ndarray) -> np.ndarray:
    """The nominal p = (θ_i1, θ_i2, φ_i) (9,) [rad]."""
    return np.r_[g.t1, g.t2, phi]


def output_jacobian(g: GeometrySpherical, x: np.ndarray, p: np.ndarray, v0: np.ndarray):
    """J = ∂F/∂x (3, 3) in closed form: rows (v_i × w_i)ᵀ E(x)."""
    t1, phi = p[:3], p[6:]
    local = np.stack([-np.sin(phi) * np.sin(t1), np.cos(phi) * np.sin(t1), np.cos(t1)], axis=1)
    w = np.einsum("iab,ib->ia", g.B, local)
    v = v0 @ _rpy(x).T
    return np.cross(v, w) @ paper.rate_matrix(*x)


def error_jacobian(g: GeometrySpherical, x: np.ndarray, p: np.ndarray, v0: np.ndarray):
    """∂F/∂p (3, 9) in closed form (module docstring), columns in :data:`PARAMETERS` order."""
    t1, t2, phi = p[:3], p[3:6], p[6:]
    v = v0 @ _rpy(x).T
    d_t1 = np.einsum(
        "iab,ib->ia",
        g.B,
        np.stack([-np.sin(phi) * np.cos(t1), np.cos(phi) * np.cos(t1), -np.sin(t1)], axis=1),
    )
    d_phi = np.einsum(
        "iab,ib->ia",
        g.B,
        np.stack([-np.cos(phi) * np.sin(t1), -np.sin(phi) * np.sin(t1), 0 * t1], axis=1),
    )
    out = np.zeros((3, 9))
    out[np.arange(3), np.arange(3)] = np.sum(d_t1 * v, axis=1)
    out[np.arange(3), 3 + np.arange(3)] = np.sin(t2)
    out[np.arange(3), 6 + np.arange(3)] = np.sum(d_phi * v, axis=1)
    return out


def cramer_delta_alpha(J: np.ndarray, W: np.ndarray, printed: bool = False) -> float:
    """δα by Cramer's rule: det J_1 / det J, or the paper's printed expression."""
    num, den = cramer_terms(J, W, printed)
    return num / den


def cramer_terms(J: np.ndarray, W: np.ndarray, printed: bool = False) -> tuple[float, float]:
    """(numerator, denominator) of δα, term by term as printed (``printed``: with its two
    index misprints; else det J_1 and det J)."""
    f = {(i + 1, "abg"[j]): J[i, j] for i in range(3) for j in range(3)}
    w1, w2, w3 = W
    num = (f[1, "b"] * f[2, "g"] * w3 - f[1, "b"] * f[3, "g"] * w2 - f[1, "g"] * f[2, "b"] * w3
           + f[1, "g"] * f[3, "b"] * w2
           + f[2, "b"] * (f[2, "g"] if printed else f[3, "g"]) * w1
           - f[2, "g"] * f[3, "b"] * w1)  # fmt: skip
    den = (f[1, "a"] * f[2, "b"] * f[3, "g"]
           - (f[1, "b"] if printed else f[1, "a"]) * f[2, "g"] * f[3, "b"]
           - f[1, "b"] * f[2, "a"] * f[3, "g"] + f[1, "b"] * f[3, "a"] * f[2, "g"]
           + f[2, "a"] * f[1, "g"] * f[3, "b"] - f[1, "g"] * f[2, "b"] * f[3, "a"])  # fmt: skip
    return float(num), float(den)


def linear_error(J: np.ndarray, W: np.ndarray) -> np.ndarray:
    """δx (3,) [rad] of J δx = W by Cramer's rule (every component)."""
    return cramer(J, W)


def nonlinear_error(
    g: GeometrySpherical, x: np.ndarray, p: np.ndarray, dp: np.ndarray, v0: np.ndarray
) -> np.ndarray:
    """δx (3,) [rad]: F(x + δx, p + δp) = 0 by Newton from x (the same assembly).

    Raises:
        SolverError: no convergence to 1e-15 in 50 iterations.
    """
    y, pp = np.array(x, dtype=float), p + dp
    for _ in range(50):
        f = residual(g, y, pp, v0)
        if np.max(np.abs(f)) < 1e-15:
            return y - x
        y = y - np.linalg.solve(output_jacobian(g, y, pp, v0), f)
    raise SolverError("spherical 3-RRR accuracy: Newton on the perturbed loops did not converge")


def table(g: GeometrySpherical, x: np.ndarray, phi: np.ndarray, size: float) -> list[dict]:
    """One row per error variable (δ = ``size`` [rad]): linear (Cramer) and nonlinear δx
    [rad], their norms, relative difference, and the paper's printed δα."""
    v0, p = g.v0, variables(g, phi)
    J, dF = output_jacobian(g, x, p, v0), error_jacobian(g, x, p, v0)
    rows: list[dict[str, Any]] = []
    for k, name in enumerate(PARAMETERS):
        dp = np.zeros(9)
        dp[k] = size
        W = -dF @ dp
        lin, non = linear_error(J, W), nonlinear_error(g, x, p, dp, v0)
        rows.append(
            {
                "joint": name,
                "component": "θ" if name.startswith("theta") else "φ",
                "error": size,
                "linear": lin,
                "nonlinear": non,
                "linear_output": float(np.linalg.norm(lin)),
                "nonlinear_output": float(np.linalg.norm(non)),
                "relative_difference": float(
                    np.linalg.norm(non - lin) / max(float(np.linalg.norm(non)), 1e-300)
                ),
                "delta_alpha_printed": cramer_delta_alpha(J, W, printed=True),
                "delta_alpha_corrected": cramer_delta_alpha(J, W),
            }
        )
    return rows


__all__ = [
    "PARAMETERS",
    "cramer_delta_alpha",
    "cramer_terms",
    "error_jacobian",
    "linear_error",
    "nonlinear_error",
    "output_jacobian",
    "residual",
    "table",
    "variables",
]
