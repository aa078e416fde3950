"""Radau IIA / Legendre collocation on one interval: points, derivative and quadrature.

On an interval of length ``h`` a state is the polynomial through ``Z_0`` (the interval's
start) and ``Z_1..Z_d`` (the collocation points ``tau_1..tau_d`` in (0, 1]); then

    z'(tau_r) = (1/h) sum_j D[j, r] Z_j,   z(1) = sum_j E[j] Z_j,
    integral over the interval of l(z) ~ h sum_r B[r] l(Z_r).

Radau IIA (``tau_d = 1``, order 2d - 1, stiffly accurate: ``z(1) = Z_d``) is the default.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import casadi as ca
import numpy as np

Scheme = Literal["radau", "legendre"]


@dataclass(frozen=True)
class Collocation:
    """Coefficients of one collocation scheme."""

    degree: int
    scheme: str
    tau: np.ndarray  # (d + 1,) with tau[0] = 0
    D: np.ndarray  # (d + 1, d): derivative of basis j at point r (1-based r)
    E: np.ndarray  # (d + 1,): basis values at tau = 1
    B: np.ndarray  # (d,): quadrature weights (sum 1)


def collocation(degree: int = 3, scheme: Scheme = "radau") -> Collocation:
    """Lagrange-basis coefficients for ``degree`` points of ``scheme``."""
    if degree < 1 or scheme not in ("radau", "legendre"):
        raise ValueError(f"need degree >= 1 and scheme radau|legendre, got {degree}, {scheme}")
    tau = np.append(0.0, ca.collocation_points(degree, scheme))
    d = degree
    D, E, B = np.zeros((d + 1, d)), np.zeros(d + 1), np.zeros(d)
    for j in range(d + 1):
        basis = np.poly1d([1.0])
        for r in range(d + 1):
            if r != j:
                basis *= np.poly1d([1.0, -tau[r]]) / (tau[j] - tau[r])
        E[j] = basis(1.0)
        deriv = np.polyder(basis)
        D[j] = [deriv(tau[r]) for r in range(1, d + 1)]
        if j > 0:
            B[j - 1] = np.polyint(basis)(1.0)
    if scheme == "radau":  # stiffly accurate: the last point is the interval's end
        E = np.eye(d + 1)[d]
    return Collocation(degree, scheme, tau, D, E, B)


__all__ = ["Collocation", "Scheme", "collocation"]
