"""Accuracy of the 3-PPaPa by the linear theory of paper 004, beside the nonlinear change.

Drives locked, link lengths l = (l1, l2, l3) in error by δl (the same in the three legs).
Differentiating F(p, q, l) = 0 (:mod:`.closed_form`) gives A δp = −(∂F/∂l) δl with

    ∂F_i/∂l1 = −l1/(s_i1 √(l1² − c²)) = −1/cos θ_i,   ∂F_i/∂l2 = −1/cos φ_i,   ∂F_i/∂l3 = −1,

and Cramer's rule δx_k = det A_k / det A, A_k: A with column k replaced by −(∂F/∂l) δl.
The paper's printed denominator is garbled; restored from the geometry it is det A (the
Jacobian of F in p, rows (−1, −tan φ_i, tan θ_i) in leg i's columns (a, b, c)):

    Δ = det A = −1 − tan φ_1 tan θ_2 − tan φ_2 tan θ_3 − tan φ_3 tan θ_1
                + tan θ_1 tan θ_2 tan θ_3 − tan φ_1 tan φ_2 tan φ_3

(:func:`cramer_denominator`), so the linear theory fails exactly on the type-2 set. The
nonlinear change re-solves F = 0 on the perturbed geometry (Newton from the nominal point,
same working mode).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from rcm_pin.analysis.accuracy import cramer
from rcm_pin.errors import SingularConfigurationError, SolverError
from rcm_pin.mechanisms.translational_3ppapa.closed_form import (
    Geometry3PPaPa,
    a_matrix,
    residual,
)

#: Link-length error variables, in the order of the columns of :func:`length_jacobian`.
LENGTHS = ("l1", "l2", "l3")


def length_jacobian(angles: np.ndarray) -> np.ndarray:
    """∂F/∂(l1, l2, l3) (3, 3) [-] from the crank angles (3, 2) θ_i, φ_i."""
    return -np.column_stack([1.0 / np.cos(angles[:, 0]), 1.0 / np.cos(angles[:, 1]), np.ones(3)])


#: The restored Cramer denominator, as printed in the report.
DENOMINATOR = (
    "det A = -1 - tan(phi1) tan(theta2) - tan(phi2) tan(theta3) - tan(phi3) tan(theta1)"
    " + tan(theta1) tan(theta2) tan(theta3) - tan(phi1) tan(phi2) tan(phi3)"
)


def cramer_denominator(angles: np.ndarray) -> float:
    """Δ = det A [-] expanded in the crank angles (3, 2) θ_i, φ_i (module docstring)."""
    t, f = np.tan(angles[:, 0]), np.tan(angles[:, 1])
    return float(
        -1.0 - f[0] * t[1] - f[1] * t[2] - f[2] * t[0] + t[0] * t[1] * t[2] - f[0] * f[1] * f[2]
    )


def linear_error(a_mat: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """δp [m] of A δp = rhs by Cramer's rule (denominator det A).

    Raises:
        SingularConfigurationError: |det A| < 1e-12 (type-2 singularity: no linear theory).
    """
    try:
        return cramer(a_mat, rhs)
    except SingularConfigurationError as exc:
        raise SingularConfigurationError(f"3-PPaPa accuracy: {exc}") from None


def nonlinear_error(
    g: Geometry3PPaPa, q: np.ndarray, p: np.ndarray, signs: np.ndarray, dl: np.ndarray
) -> np.ndarray:
    """δp [m]: F(p + δp, q, l + δl) = 0 by Newton from p (working mode ``signs`` (3, 2)).

    Raises:
        SolverError: no convergence to 1e-14 in 50 iterations.
    """
    gp = replace(g, l1=g.l1 + dl[0], l2=g.l2 + dl[1], l3=g.l3 + dl[2])
    x = np.array(p, dtype=float)
    for _ in range(50):
        f = residual(gp, q, x, signs)
        if np.max(np.abs(f)) < 1e-14:
            return x - p
        x = x - np.linalg.solve(a_matrix(gp, x, signs), f)
    raise SolverError(f"3-PPaPa accuracy: Newton did not converge for length errors {dl.tolist()}")


def accuracy_table(
    g: Geometry3PPaPa,
    q: np.ndarray,
    p: np.ndarray,
    signs: np.ndarray,
    angles: np.ndarray,
    size: float = 1e-3,
) -> list[dict[str, object]]:
    """One row per link length in error by ``size`` [m]: linear and nonlinear δp [m] and
    their relative difference ‖δp_lin − δp_nl‖ / ‖δp_nl‖ [-]."""
    a_mat, dfdl = a_matrix(g, p, signs), length_jacobian(angles)
    rows = []
    for j, name in enumerate(LENGTHS):
        dl = np.zeros(3)
        dl[j] = size
        lin = linear_error(a_mat, -dfdl @ dl)
        nl = nonlinear_error(g, q, p, signs, dl)
        rel = float(np.linalg.norm(lin - nl) / np.linalg.norm(nl))
        rows.append({"length": name, "linear": lin, "nonlinear": nl, "relative": rel})
    return rows


def report(
    g: Geometry3PPaPa,
    q: np.ndarray,
    p: np.ndarray,
    signs: np.ndarray,
    angles: np.ndarray,
    size: float = 1e-3,
) -> dict[str, object]:
    """The ``accuracy`` hook's table: per link length in error by ``size`` [m] one row per
    component x, y, z [m] and one for the norm |p| (``joint`` names the length), with the
    restored Cramer denominator Δ = det A and the relative difference linear vs nonlinear."""
    rows: list[dict[str, object]] = []
    for r in accuracy_table(g, q, p, signs, angles, size):
        lin, nl = np.asarray(r["linear"]), np.asarray(r["nonlinear"])
        pairs = [(c, float(lin[k]), float(nl[k])) for k, c in enumerate("xyz")]
        pairs.append(("|p|", float(np.linalg.norm(lin)), float(np.linalg.norm(nl))))
        for comp, a, b in pairs:
            rows.append({
                "joint": r["length"], "component": comp, "error": size,
                "linear_output": a, "nonlinear_output": b,
                "relative_difference": abs(a - b) / max(abs(b), 1e-300),
            })  # fmt: skip
    return {
        "point": p,
        "drives": q,
        "denominator": DENOMINATOR,
        "det_a": cramer_denominator(angles),
        "rows": rows,
    }


__all__ = [
    "DENOMINATOR",
    "LENGTHS",
    "accuracy_table",
    "cramer_denominator",
    "length_jacobian",
    "linear_error",
    "nonlinear_error",
    "report",
]
