"""Closed form of the translational 3-PPaPa of paper 004 (Fig. 4): positions and A, B.

Geometry (``xacro/translational_3ppapa.urdf.xacro``): leg i works in the frame
(e_i, e_i+1, e_i+2) (indices cyclic), where the platform point P = (x, y, z) has the
coordinates (a, b, c) = (p_i, p_i+1, p_i+2). The drive q_i slides along e_i; the crank of
parallelogram 1 (length l1, joint ``c<i>1``, angle θ_i) and of parallelogram 2 (l2, joint
``c<i>2``, angle φ_i) point along −e_i at θ = φ = 0; the rigid offset l3 ends at P::

    a = q_i − l3 − l2 cos φ_i − l1 cos θ_i,   b = −l2 sin φ_i,   c = l1 sin θ_i.

Paper 004's position equation (F_1 printed, F_2, F_3 cyclic in x, y, z):

    F_i = q_i − a − l3 − s_i2 √(l2² − b²) − s_i1 √(l1² − c²) = 0,

so the inverse problem is explicit with two signs per leg: s_i1 = sign cos θ_i, s_i2 =
sign cos φ_i. A working mode is labelled ``s11s12/s21s22/s31s32`` (e.g. ``++/+-/++``,
64 modes); the paper's cos(arcsin ...) is the mode ``++/++/++``. The direct problem
(drives → P) is solved for every sign pattern by a vectorised Newton from a grid of seeds
(every assembly mode that the grid finds; no polynomial is known for it).

Velocities, A ṗ = −B q̇ with A = ∂F/∂p and B = ∂F/∂q: B = I (the paper's claim, exact:
q_i enters F_i alone and linearly), and in the leg's columns (a, b, c)

    A_i = (−1, s_i2 b/√(l2² − b²), s_i1 c/√(l1² − c²)) = (−1, −tan φ_i, tan θ_i).

Row i is along n_i, the leg's constraint-force direction (normal to both crank
velocities). Singular sets: det A = 0 (type 2, uncontrolled platform translation; e.g. on
the diagonal x = y = z = t in mode ``++/++/++``, where A is circulant and its eigenvalue
along (1, 1, 1), −1 + t/√(l2² − t²) + t/√(l1² − t²), vanishes at t = 0.198 m for the
defaults). A parallelogram whose crank is normal to its drive (|b| = l2 or |c| = l1, the
reach boundary: "stretched") sends an entry of A to infinity while B = I stays regular:
that set is *not* revealed by A and B in the paper's form (multiply row i by
cos θ_i cos φ_i and B loses rank: type 1, as Pinocchio's B and the screws show).
Screw form: V·r_i = V_i1 (r_i·e_i) with r_i along n_i (the printed right-hand side
V_i1 (r_ix + r_iy + r_iz) is a misprint; ``tests/test_translational_3ppapa.py``).
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

#: Signs (s_i1, s_i2) of one leg.
LEG_SIGNS = ((1, 1), (1, -1), (-1, 1), (-1, -1))
#: Every working mode: (s11, s12), (s21, s22), (s31, s32).
SIGN_PATTERNS = tuple(itertools.product(LEG_SIGNS, repeat=3))


def label(pattern: tuple[tuple[int, int], ...]) -> str:
    """``++/+-/--`` for a sign pattern."""
    return "/".join("".join("+" if s > 0 else "-" for s in leg) for leg in pattern)


#: Working-mode labels, in the order of :data:`SIGN_PATTERNS` (``++/++/++`` first).
MODES = tuple(label(p) for p in SIGN_PATTERNS)


@dataclass(frozen=True)
class Geometry3PPaPa:
    """Crank lengths l1, l2, offset l3 and widths w1, w2 [m]."""

    l1: float
    l2: float
    l3: float
    w1: float
    w2: float

    @classmethod
    def from_params(cls, p: Mapping[str, float]) -> Geometry3PPaPa:
        """From the sidecar ``params``."""
        keys = ("side_1", "side_2", "offset", "width_1", "width_2")
        return cls(*(float(p[k]) for k in keys))


def local(p: np.ndarray, i: int) -> np.ndarray:
    """(a, b, c) = (p_i, p_i+1, p_i+2) of P (..., 3) in leg i's frame (i = 0, 1, 2)."""
    return np.asarray(p)[..., [i, (i + 1) % 3, (i + 2) % 3]]


def leg_angles(
    g: Geometry3PPaPa, p: np.ndarray, i: int, s: tuple[int, int]
) -> tuple[float, float, float] | None:
    """(q_i [m], θ_i, φ_i [rad]) of leg i in signs s, or None where P is out of its reach."""
    a, b, c = local(p, i)
    if abs(c) > g.l1 or abs(b) > g.l2:
        return None
    r1, r2 = s[0] * np.sqrt(g.l1**2 - c * c), s[1] * np.sqrt(g.l2**2 - b * b)
    return float(a + g.l3 + r2 + r1), float(np.arctan2(c, r1)), float(np.arctan2(-b, r2))


def inverse_position(g: Geometry3PPaPa, p: np.ndarray) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """Every working mode reaching P: (label, drives q (3,) [m], angles (3, 2) θ_i, φ_i)."""
    legs = [[leg_angles(g, p, i, s) for s in LEG_SIGNS] for i in range(3)]
    out = []
    for pattern in SIGN_PATTERNS:
        sols = [legs[i][LEG_SIGNS.index(pattern[i])] for i in range(3)]
        if any(x is None for x in sols):
            continue
        q = np.array([x[0] for x in sols if x is not None])
        out.append((label(pattern), q, np.array([x[1:] for x in sols if x is not None])))
    return out


def platform_point(g: Geometry3PPaPa, q: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """P from leg 1 (drive q_1, θ_1, φ_1): the forward map of one leg (module docstring)."""
    th, ph = angles[0]
    return np.array(
        [q[0] - g.l3 - g.l2 * np.cos(ph) - g.l1 * np.cos(th), -g.l2 * np.sin(ph), g.l1 * np.sin(th)]
    )


def drives(g: Geometry3PPaPa, p: np.ndarray, signs: np.ndarray) -> np.ndarray:
    """Drives q (..., 3) [m] of points p (..., 3) in signs (..., 3, 2); NaN out of reach."""
    out = []
    for i in range(3):
        a, b, c = np.moveaxis(local(p, i), -1, 0)
        with np.errstate(invalid="ignore"):
            r1 = signs[..., i, 0] * np.sqrt(g.l1**2 - c * c)
            r2 = signs[..., i, 1] * np.sqrt(g.l2**2 - b * b)
        out.append(a + g.l3 + r2 + r1)
    return np.stack(out, axis=-1)


def residual(g: Geometry3PPaPa, q: np.ndarray, p: np.ndarray, signs: np.ndarray) -> np.ndarray:
    """F = q − drives(p) (..., 3) at points p (..., 3) for sign arrays signs (..., 3, 2);
    NaN out of reach. ``q[i]`` is drive i (a number, or one per point: q is (3, ...))."""
    return np.moveaxis(np.asarray(q, dtype=float), 0, -1) - drives(g, p, signs)


def a_matrix(g: Geometry3PPaPa, p: np.ndarray, signs: np.ndarray) -> np.ndarray:
    """A = ∂F/∂p (..., 3, 3) [-] (module docstring); B = ∂F/∂q = I."""
    p = np.asarray(p, dtype=float)
    out = np.zeros(p.shape[:-1] + (3, 3))
    for i in range(3):
        _, b, c = np.moveaxis(local(p, i), -1, 0)
        with np.errstate(invalid="ignore", divide="ignore"):
            out[..., i, i] = -1.0
            out[..., i, (i + 1) % 3] = b / (signs[..., i, 1] * np.sqrt(g.l2**2 - b * b))
            out[..., i, (i + 2) % 3] = c / (signs[..., i, 0] * np.sqrt(g.l1**2 - c * c))
    return out


def a_from_angles(angles: np.ndarray) -> np.ndarray:
    """A from the crank angles (3, 2) θ_i, φ_i: row i = (−1, −tan φ_i, tan θ_i) in (a, b, c)."""
    out = np.zeros((3, 3))
    for i, (th, ph) in enumerate(angles):
        out[i, i], out[i, (i + 1) % 3], out[i, (i + 2) % 3] = -1.0, -np.tan(ph), np.tan(th)
    return out


def direct_position(
    g: Geometry3PPaPa,
    q: np.ndarray,
    modes: tuple[str, ...] = MODES,
    grid: int = 6,
    tol: float = 1e-13,
) -> list[tuple[str, np.ndarray]]:
    """Every assembly mode the seeds find: (working-mode label, P (3,) [m]).

    Newton on F(P) = 0 for each sign pattern of ``modes`` (default all 64) from a grid³
    of seeds in the reach box |p| < min(l1, l2); solutions with |F| < tol [m], deduplicated
    to 1e-9 m, the mode ``++/++/++`` first, then by the distance of P from the origin.
    Seeds cannot prove that no mode is missed (no polynomial form is known).
    """
    r = 0.999 * min(g.l1, g.l2)
    axis = np.linspace(-r, r, grid)
    seeds = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), -1).reshape(-1, 3)
    signs = np.array([SIGN_PATTERNS[MODES.index(m)] for m in modes], dtype=float)
    p = np.broadcast_to(seeds, (len(signs), len(seeds), 3)).copy()
    s = np.broadcast_to(signs[:, None], (len(signs), len(seeds), 3, 2))
    box = 0.9999999 * min(g.l1, g.l2)
    for _ in range(30):
        f = residual(g, q, p, s)
        jac = a_matrix(g, p, s)
        ok = np.isfinite(f).all(-1) & np.isfinite(jac).all((-1, -2))
        f[~ok], jac[~ok] = 0.0, np.eye(3)
        step = np.linalg.solve(jac, -f[..., None])[..., 0]
        step[~np.isfinite(step).all(-1)] = 0.0
        norm = np.linalg.norm(step, axis=-1, keepdims=True)
        p = np.clip(p + step * np.minimum(1.0, 0.25 * r / np.maximum(norm, 1e-300)), -box, box)
        if np.max(norm) < 1e-15:
            break
    f = residual(g, q, p, s)
    good = np.isfinite(f).all(-1) & (np.max(np.abs(f), axis=-1) < tol)
    found: list[tuple[str, np.ndarray]] = []
    for k, j in zip(*np.nonzero(good), strict=True):
        name = modes[k]
        if not any(m == name and np.max(np.abs(x - p[k, j])) < 1e-9 for m, x in found):
            found.append((name, p[k, j].copy()))
    found.sort(key=lambda item: (MODES.index(item[0]) != 0, float(np.linalg.norm(item[1]))))
    return found


__all__ = [
    "LEG_SIGNS",
    "MODES",
    "SIGN_PATTERNS",
    "Geometry3PPaPa",
    "a_from_angles",
    "a_matrix",
    "direct_position",
    "drives",
    "inverse_position",
    "label",
    "leg_angles",
    "local",
    "platform_point",
    "residual",
]
