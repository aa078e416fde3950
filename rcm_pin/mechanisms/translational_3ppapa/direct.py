"""Batched direct problem of the 3-PPaPa: drives q (M, 3) → every assembly mode P.

Legs 1 and 2 reduce, at a fixed height z, to two circles in the (x, y) plane
(:mod:`.closed_form`, F_1 and F_2):

    x = C_1 − s_12 √(l2² − y²),  C_1 = q_1 − l3 − s_11 √(l1² − z²):  (x − C_1)² + y² = l2²,
    y = C_2 − s_21 √(l1² − x²),  C_2 = q_2 − l3 − s_22 √(l2² − z²):  x² + (y − C_2)² = l1²,

whose two intersections (branch β = ±1) are explicit; the signs s_12 = sign(C_1 − x),
s_21 = sign(C_2 − y) are read off the point. Leg 3 leaves one scalar equation per curve
σ = (s_11, s_22, β, s_31, s_32) (32 curves):

    g_σ(z) = q_3 − z − l3 − s_32 √(l2² − x(z)²) − s_31 √(l1² − y(z)²) = 0,
    |z| ≤ min(l1, l2).

Its roots are bracketed on a grid of :data:`GRID` heights. Where a curve stops being real
inside a grid interval (circles tangent, |x| = l2 or |y| = l1: there it meets its partner
curve) the end is located by bisection and the stretch up to it resampled :data:`SUB`
times, densely toward the end (g behaves like √(z* − z) there). Where a sample lies within
one grid step of 0 the two intervals around it are resampled :data:`SUB` times, and at a
local extremum of the fine samples a ternary search finds whether g crosses 0 twice (two
assembly modes about to merge, next to a type-2 singularity). Three roots merging inside
one fine interval (a cusp of the type-2 surface) or a double root can still be missed.
Each bracket is refined by bisection and the point polished by Newton on F in its working
mode; accepted below :data:`ACCEPT` [m].
The fully squared system (each F_i squared twice: degree 4 in x, y, z, no root at
infinity) has 4³ = 64 complex roots, so at most 64 real assemblies over all 64 modes.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rcm_pin.errors import InvalidInputError
from rcm_pin.mechanisms.translational_3ppapa.closed_form import (
    MODES,
    Geometry3PPaPa,
    a_matrix,
    residual,
)

#: Heights z sampled per curve for the brackets.
GRID = 512
#: Fine samples per suspicious pair of grid intervals (:func:`_root_pairs`).
SUB = 65
#: A polished point is an assembly when max |F| is below this [m].
ACCEPT = 1e-13
#: Samples of drive values handled at once (memory: CHUNK · 32 · GRID floats per array).
CHUNK = 32
#: Discrete signs (s_11, s_22, β, s_31, s_32) of the 32 curves, shape (32, 5).
CURVES = np.array(
    [[a, b, c, d, e] for a in (1, -1) for b in (1, -1) for c in (1, -1)
     for d in (1, -1) for e in (1, -1)], dtype=float)  # fmt: skip


class DirectSolutions(NamedTuple):
    """Every assembly mode of M drive inputs, flattened.

    Attributes:
        sample: (K,) index of the drive input of each solution.
        point: (K, 3) platform point P [m].
        mode: (K,) index into :data:`~.closed_form.MODES` (working-mode label).
        residual: (K,) max |F| at the polished point [m].
    """

    sample: np.ndarray
    point: np.ndarray
    mode: np.ndarray
    residual: np.ndarray

    def labels(self) -> list[str]:
        """The working-mode labels ``s11s12/s21s22/s31s32`` of the solutions."""
        return [MODES[int(k)] for k in self.mode]


def _curve(
    g: Geometry3PPaPa, q: np.ndarray, z: np.ndarray, sig: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(g_σ, valid, x, y, (s_12, s_21)) at heights z; q, z, sig broadcast (..., 3 / 5).

    Square-root arguments are clamped at 0 (the value at the end of a real stretch);
    ``valid`` says where they are all ≥ 0 unclamped.
    """
    s11, s22, beta, s31, s32 = (sig[..., k] for k in range(5))
    r1z, r2z = g.l1**2 - z * z, g.l2**2 - z * z
    c1 = q[..., 0] - g.l3 - s11 * np.sqrt(np.maximum(r1z, 0.0))
    c2 = q[..., 1] - g.l3 - s22 * np.sqrt(np.maximum(r2z, 0.0))
    d2 = c1 * c1 + c2 * c2
    d = np.sqrt(d2)
    dd = np.where(d > 0.0, d, 1.0)
    a = (g.l2**2 - g.l1**2 + d2) / (2.0 * dd)  # from centre A = (C_1, 0) toward B = (0, C_2)
    h2 = g.l2**2 - a * a
    h = np.sqrt(np.maximum(h2, 0.0))
    ux, uy = -c1 / dd, c2 / dd  # unit vector A → B
    x = c1 + a * ux - beta * h * uy
    y = a * uy + beta * h * ux
    rx, ry = g.l2**2 - x * x, g.l1**2 - y * y
    val = q[..., 2] - z - g.l3 - s32 * np.sqrt(np.maximum(rx, 0.0))
    val = val - s31 * np.sqrt(np.maximum(ry, 0.0))
    valid = (d > 0.0) & (h2 >= 0.0) & (rx >= 0.0) & (ry >= 0.0) & (r1z >= 0.0) & (r2z >= 0.0)
    signs = np.stack([np.where(c1 - x >= 0.0, 1.0, -1.0), np.where(c2 - y >= 0.0, 1.0, -1.0)])
    return val, valid, x, y, signs


def _brackets(
    g: Geometry3PPaPa, q: np.ndarray, zs: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(sample, curve, z_lo, z_hi) of every sign change of g_σ, q (m, 3)."""
    qb, sig = q[:, None, None, :], CURVES[None, :, None, :]
    val, valid, *_ = _curve(g, qb, zs[None, None, :], sig)
    lo_v, hi_v, lo_ok, hi_ok = val[..., :-1], val[..., 1:], valid[..., :-1], valid[..., 1:]
    both = lo_ok & hi_ok & (lo_v * hi_v <= 0.0)
    ends = lo_ok ^ hi_ok  # a real stretch ends inside the interval: find its end
    i, c, k = np.nonzero(ends)
    good_z = np.where(lo_ok[i, c, k], zs[k], zs[k + 1])
    bad_z = np.where(lo_ok[i, c, k], zs[k + 1], zs[k])
    for _ in range(60):
        mid = 0.5 * (good_z + bad_z)
        ok = _curve(g, q[i], mid, CURVES[c])[1]
        good_z, bad_z = np.where(ok, mid, good_z), np.where(ok, bad_z, mid)
    start = np.where(lo_ok[i, c, k], zs[k], zs[k + 1])
    # near its end a curve behaves like √(z* − z): samples dense toward z* (quadratic)
    u = 1.0 - (1.0 - np.linspace(0.0, 1.0, SUB)) ** 2
    zf = start[:, None] + (good_z - start)[:, None] * u
    ji, jc, jz_lo, jz_hi = _fine(g, q, i, c, zf)
    bi, bc, bk = np.nonzero(both)
    pi, pc, pz_lo, pz_hi = _root_pairs(g, q, zs, val, valid)
    sample = np.concatenate([bi, ji, pi])
    curve = np.concatenate([bc, jc, pc])
    z_lo = np.concatenate([zs[bk], np.minimum(jz_lo, jz_hi), pz_lo])
    z_hi = np.concatenate([zs[bk + 1], np.maximum(jz_lo, jz_hi), pz_hi])
    return sample, curve, z_lo, z_hi


def _root_pairs(
    g: Geometry3PPaPa, q: np.ndarray, zs: np.ndarray, val: np.ndarray, valid: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Close roots hidden inside grid intervals: where a sample g_k is within one grid step
    of 0 (|g_k| < max |g_k±1 − g_k|: a parabola through the samples may dip across 0),
    [z_k−1, z_k+1] is resampled :data:`SUB` times finer (:func:`_fine`)."""
    left, mid, right = val[..., :-2], val[..., 1:-1], val[..., 2:]
    ok = valid[..., :-2] & valid[..., 1:-1] & valid[..., 2:]
    step = np.maximum(np.abs(mid - left), np.abs(right - mid))
    i, c, k = np.nonzero(ok & (np.abs(mid) < step))
    zf = zs[k, None] + (zs[k + 2] - zs[k])[:, None] * np.linspace(0.0, 1.0, SUB)
    return _fine(g, q, i, c, zf)


def _fine(
    g: Geometry3PPaPa, q: np.ndarray, i: np.ndarray, c: np.ndarray, zf: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Brackets on fine grids zf (n, S) of curves c of samples i: every sign change, and at
    each local extremum of the samples whose true extremum (ternary search) has the
    opposite sign, the two brackets on either side. Returns (sample, curve, z_lo, z_hi)."""
    vf, okf = _curve(g, q[i][:, None, :], zf, CURVES[c][:, None, :])[:2]
    r, j = np.nonzero(okf[:, :-1] & okf[:, 1:] & (vf[:, :-1] * vf[:, 1:] <= 0.0))
    lo_f, mi_f, hi_f = vf[:, :-2], vf[:, 1:-1], vf[:, 2:]
    ext = okf[:, :-2] & okf[:, 1:-1] & okf[:, 2:] & ((mi_f - lo_f) * (hi_f - mi_f) < 0.0)
    er, ej = np.nonzero(ext)
    sign = np.where(mi_f[er, ej] > lo_f[er, ej], 1.0, -1.0)  # +1: a maximum, −1: a minimum
    a, b = zf[er, ej].copy(), zf[er, ej + 2].copy()
    for _ in range(80):
        u, w = a + (b - a) / 3.0, b - (b - a) / 3.0
        fu, fw = (sign * _curve(g, q[i[er]], z, CURVES[c[er]])[0] for z in (u, w))
        a, b = np.where(fu < fw, u, a), np.where(fu < fw, b, w)
    z_e = 0.5 * (a + b)
    f_e, ok_e = _curve(g, q[i[er]], z_e, CURVES[c[er]])[:2]
    split = (f_e * mi_f[er, ej] < 0.0) & ok_e
    er, ej, z_e = er[split], ej[split], z_e[split]
    rows = np.concatenate([r, er, er])
    return (
        i[rows],
        c[rows],
        np.concatenate([zf[r, j], zf[er, ej], z_e]),
        np.concatenate([zf[r, j + 1], z_e, zf[er, ej + 2]]),
    )


def _refine(
    g: Geometry3PPaPa, q: np.ndarray, sig: np.ndarray, lo: np.ndarray, hi: np.ndarray
) -> np.ndarray:
    """Bisection of g_σ on [lo, hi] (sign change) to the last bit [m]."""
    f_lo = _curve(g, q, lo, sig)[0]
    for _ in range(64):
        mid = 0.5 * (lo + hi)
        f_mid = _curve(g, q, mid, sig)[0]
        left = f_lo * f_mid <= 0.0
        hi, lo = np.where(left, mid, hi), np.where(left, lo, mid)
        f_lo = np.where(left, f_lo, f_mid)
    return 0.5 * (lo + hi)


def _polish(
    g: Geometry3PPaPa, q: np.ndarray, p: np.ndarray, signs: np.ndarray, steps: int = 4
) -> tuple[np.ndarray, np.ndarray]:
    """Newton on F(P) = 0 (K points, their sign arrays (K, 3, 2)); (P, max |F|)."""
    for _ in range(steps):
        f = residual(g, q.T, p, signs)  # q.T[i]: drive i of every point
        jac = a_matrix(g, p, signs)
        ok = np.isfinite(f).all(-1) & (np.abs(np.linalg.det(jac)) > 1e-14)
        if not ok.any():
            break
        step = np.zeros_like(p)
        step[ok] = np.linalg.solve(jac[ok], -f[ok][..., None])[..., 0]
        p = p + step
    f = residual(g, q.T, p, signs)
    return p, np.where(np.isfinite(f).all(-1), np.max(np.abs(f), axis=-1), np.inf)


def _solve_chunk(g: Geometry3PPaPa, q: np.ndarray, zs: np.ndarray) -> DirectSolutions:
    sample, curve, lo, hi = _brackets(g, q, zs)
    sig, qs = CURVES[curve], q[sample]
    z = _refine(g, qs, sig, lo, hi)
    _, _, x, y, s = _curve(g, qs, z, sig)
    p = np.stack([x, y, z], axis=-1)
    signs = np.stack(
        [np.stack([sig[:, 0], s[0]], -1), np.stack([s[1], sig[:, 1]], -1),
         np.stack([sig[:, 3], sig[:, 4]], -1)], axis=1)  # fmt: skip
    p, res = _polish(g, qs, p, signs)
    keep = (res < ACCEPT) & (np.max(np.abs(p - np.stack([x, y, z], -1)), axis=-1) < 1e-6)
    leg = 2 * (signs[..., 0] < 0) + (signs[..., 1] < 0)  # index in LEG_SIGNS, (K, 3)
    mode = (16 * leg[:, 0] + 4 * leg[:, 1] + leg[:, 2]).astype(int)  # SIGN_PATTERNS order
    return _dedupe(DirectSolutions(sample[keep], p[keep], mode[keep], res[keep]))


def _dedupe(sol: DirectSolutions, tol: float = 1e-9) -> DirectSolutions:
    """One entry per (sample, mode, point), sorted by sample then mode."""
    order = np.lexsort((sol.point[:, 2], sol.mode, sol.sample))
    keep: list[int] = []
    for j in order:
        twins = (
            k for k in keep[-8:] if (sol.sample[k], sol.mode[k]) == (sol.sample[j], sol.mode[j])
        )
        if all(np.max(np.abs(sol.point[k] - sol.point[j])) >= tol for k in twins):
            keep.append(int(j))
    idx = np.array(keep, dtype=int)
    return DirectSolutions(sol.sample[idx], sol.point[idx], sol.mode[idx], sol.residual[idx])


def direct_batch(g: Geometry3PPaPa, drives: np.ndarray, grid: int = GRID) -> DirectSolutions:
    """Every assembly mode of each drive input (M, 3) [m] (module docstring).

    Raises:
        InvalidInputError: drives not of shape (M, 3) or not finite.
    """
    q = np.asarray(drives, dtype=float)
    if q.ndim != 2 or q.shape[1] != 3 or not np.isfinite(q).all():
        raise InvalidInputError(
            f"3-PPaPa drives have shape {q.shape} (or are not finite); valid: finite (M, 3) [m]"
        )
    r = min(g.l1, g.l2)
    zs = np.linspace(-r, r, grid)
    parts = [_solve_chunk(g, q[k : k + CHUNK], zs) for k in range(0, len(q), CHUNK)]
    if not parts:
        return DirectSolutions(np.zeros(0, int), np.zeros((0, 3)), np.zeros(0, int), np.zeros(0))
    offset = range(0, len(q), CHUNK)
    return DirectSolutions(
        np.concatenate([p.sample + o for p, o in zip(parts, offset, strict=True)]),
        np.concatenate([p.point for p in parts]),
        np.concatenate([p.mode for p in parts]),
        np.concatenate([p.residual for p in parts]),
    )


def direct_all(g: Geometry3PPaPa, drives: np.ndarray) -> list[tuple[str, np.ndarray]]:
    """Every assembly mode of one drive input: (label, P (3,) [m]), ``++/++/++`` first."""
    sol = direct_batch(g, np.asarray(drives, dtype=float).reshape(1, 3))
    out = [(MODES[int(m)], p.copy()) for m, p in zip(sol.mode, sol.point, strict=True)]
    out.sort(key=lambda item: (MODES.index(item[0]) != 0, float(np.linalg.norm(item[1]))))
    return out


__all__ = ["ACCEPT", "CURVES", "GRID", "DirectSolutions", "direct_all", "direct_batch"]
