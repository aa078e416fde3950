"""Singularity verdicts of the 3-PPaPa from the paper's A and B, and points on each set.

The paper's A (rows (−1, −tan φ_i, tan θ_i) in leg i's columns) and B = I: det A = 0 is
type 2; B never loses rank, and where a parallelogram stretches (cos θ_i = 0 or
cos φ_i = 0) A has an infinite entry. Multiplying row i of A ṗ = −B q̇ by
D_i = cos θ_i cos φ_i gives the same velocity relation with finite matrices
A' = D A, B' = D, and then the stretched set is a rank loss of B' (type 1): that is the
set "not revealed by A and B" in the paper's form. :func:`paper_verdict` uses A', B'
(rows of A' normalised, so both measures are dimensionless in [0, 1]).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rcm_pin.mechanisms.translational_3ppapa.closed_form import Geometry3PPaPa, a_matrix

#: A measure below this is singular (the generic classifier's threshold).
TOL = 1e-8


class PaperVerdict(NamedTuple):
    """Verdict of the scaled paper matrices, and whether the unscaled A, B show it."""

    label: str
    measure_type1: float
    measure_type2: float
    a_finite: bool


def scaled_ab(angles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(A', B') = (D A, D), D = diag(cos θ_i cos φ_i), from the crank angles (3, 2) [-]."""
    th, ph = angles[:, 0], angles[:, 1]
    a = np.zeros((3, 3))
    for i in range(3):
        a[i, i] = -np.cos(th[i]) * np.cos(ph[i])
        a[i, (i + 1) % 3] = -np.cos(th[i]) * np.sin(ph[i])
        a[i, (i + 2) % 3] = np.sin(th[i]) * np.cos(ph[i])
    return a, np.diag(np.cos(th) * np.cos(ph))


def paper_verdict(angles: np.ndarray, tol: float = TOL) -> PaperVerdict:
    """``regular`` / ``type 1`` / ``type 2`` / ``type 1+2`` from A', B' (module docstring)."""
    a, b = scaled_ab(angles)
    rows = a / np.linalg.norm(a, axis=1, keepdims=True)
    m1 = float(np.min(np.abs(np.diag(b))))
    m2 = float(abs(np.linalg.det(rows)))
    t1, t2 = m1 < tol, m2 < tol
    label = "type 1+2" if t1 and t2 else "type 1" if t1 else "type 2" if t2 else "regular"
    with np.errstate(over="ignore"):
        finite = bool(np.all(np.abs(np.tan(angles)) < 1.0 / tol))
    return PaperVerdict(label, m1, m2, finite)


def type2_points(
    g: Geometry3PPaPa, signs: np.ndarray, n: int, rng: np.random.Generator
) -> np.ndarray:
    """n points (n, 3) [m] on det A = 0 in the mode ``signs`` (3, 2): bisection on det A
    along segments between random reach points of opposite det sign (60 halvings)."""
    r = 0.98 * min(g.l1, g.l2)
    out: list[np.ndarray] = []
    while len(out) < n:
        p0, p1 = rng.uniform(-r, r, (2, 64 * n, 3))
        s = np.broadcast_to(signs, (64 * n, 3, 2))
        d0, d1 = np.linalg.det(a_matrix(g, p0, s)), np.linalg.det(a_matrix(g, p1, s))
        pick = np.flatnonzero(d0 * d1 < 0)[: n - len(out)]
        lo, hi, dlo = p0[pick], p1[pick], d0[pick]
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            dm = np.linalg.det(a_matrix(g, mid, s[: len(pick)]))
            left = (dlo * dm <= 0)[:, None]
            hi, lo = np.where(left, mid, hi), np.where(left, lo, mid)
            dlo = np.where(left[:, 0], dlo, dm)
        out += list(0.5 * (lo + hi))
    return np.array(out[:n])


def type1_points(g: Geometry3PPaPa, n: int, rng: np.random.Generator) -> np.ndarray:
    """n points (n, 3) [m] with a parallelogram of a random leg i stretched, the other
    coordinates random inside the reach: for l2 ≤ l1 the second one, |b_i| = l2
    (b_i = p_{i+1}); else the first one, |c_i| = l1 (c_i = p_{i+2}). (The longer
    parallelogram stretches only outside the reach |p_k| ≤ min(l1, l2).)"""
    r = 0.98 * min(g.l1, g.l2)
    p = rng.uniform(-r, r, (n, 3))
    leg = rng.integers(0, 3, n)
    k, length = ((leg + 1) % 3, g.l2) if g.l2 <= g.l1 else ((leg + 2) % 3, g.l1)
    p[np.arange(n), k] = rng.choice([-1.0, 1.0], n) * length
    return p


__all__ = ["TOL", "PaperVerdict", "paper_verdict", "scaled_ab", "type1_points", "type2_points"]
