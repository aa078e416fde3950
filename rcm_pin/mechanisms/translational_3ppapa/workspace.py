"""Workspace of the 3-PPaPa per working mode, from the explicit inverse solution.

A platform point P is reachable in a working mode when every leg's square roots are real
(|b_i| ≤ l2, |c_i| ≤ l1: so |x|, |y|, |z| ≤ min(l1, l2), the same box in every mode) and the
drives q_i (:func:`~.closed_form.leg_angles`) lie within their limits; the crank angles
have no limits inside ±2π. Inside the reach the type-2 surface det A = 0 splits each mode's
workspace into det A > 0 and det A < 0; the reach boundary is the type-1 set (a stretched
parallelogram, cos φ_i = 0 or cos θ_i = 0).

Volumes [m³] by two routes: Monte Carlo over the box |p_k| ≤ :data:`BOX_FACTOR` · min(l1,
l2) (with the standard error √(p(1 − p)/N) · V_box) and the midpoint rule on a grid over
the same box (22 or 44 cells a side put the reach's faces on cell faces for BOX_FACTOR = 1.1, so
the grid's reach is exact); the reach also has the closed form (2 min(l1, l2))³ while the
drive limits do not bind.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rcm_pin.mechanisms.translational_3ppapa.closed_form import (
    MODES,
    SIGN_PATTERNS,
    Geometry3PPaPa,
    a_matrix,
    drives,
)

#: Half-width of the sampling box, in units of min(l1, l2) (it contains the reach).
BOX_FACTOR = 1.1
#: A point is well conditioned when σ_min/σ_max of A is at least this [-].
CONDITION = 0.1
#: Every working mode's signs (64, 3, 2).
SIGNS = np.array(SIGN_PATTERNS, dtype=float)


def measures(
    g: Geometry3PPaPa, p: np.ndarray, drive_limits: tuple[float, float]
) -> dict[str, np.ndarray]:
    """Per mode (64, N) for points p (N, 3): ``reach`` (bool), ``det`` (det A, NaN out of
    reach) and ``conditioned`` (reach and σ_min/σ_max(A) ≥ :data:`CONDITION`)."""
    s = np.broadcast_to(SIGNS[:, None], (64, len(p), 3, 2))
    pp = np.broadcast_to(p, (64, len(p), 3))
    q = drives(g, pp, s)
    lo, hi = drive_limits
    reach = np.isfinite(q).all(-1) & (q >= lo).all(-1) & (q <= hi).all(-1)
    a = a_matrix(g, pp, s)
    finite = reach & np.isfinite(a).all((-1, -2))
    det = np.full(reach.shape, np.nan)
    det[finite] = np.linalg.det(a[finite])
    cond = np.zeros(reach.shape, dtype=bool)
    sv = np.linalg.svd(a[finite], compute_uv=False)
    cond[finite] = sv[:, -1] >= CONDITION * sv[:, 0]
    return {"reach": reach, "det": det, "conditioned": cond}


def _fractions(
    g: Geometry3PPaPa, p: np.ndarray, drive_limits: tuple[float, float], chunk: int = 8192
) -> dict[str, np.ndarray]:
    """Per-mode fractions of the points p (N, 3): reach, det A > 0, det A < 0, well
    conditioned (in chunks of ``chunk`` points: 64 modes × 9 entries each)."""
    keys = ("reach", "det_positive", "det_negative", "conditioned")
    total = {k: np.zeros(64) for k in keys}
    for k in range(0, len(p), chunk):
        m = measures(g, p[k : k + chunk], drive_limits)
        with np.errstate(invalid="ignore"):
            total["reach"] += m["reach"].sum(1)
            total["det_positive"] += (m["det"] > 0).sum(1)
            total["det_negative"] += (m["det"] < 0).sum(1)
            total["conditioned"] += m["conditioned"].sum(1)
    return {k: v / len(p) for k, v in total.items()}


#: Most Monte Carlo samples of :func:`volumes` (each is solved in all 64 working modes).
MAX_SAMPLES = 250_000


def volumes(
    g: Geometry3PPaPa,
    drive_limits: tuple[float, float],
    samples: int = 20_000,
    grid: int = 22,
    seed: int = 0,
) -> dict[str, Any]:
    """Volumes [m³] per working mode by Monte Carlo (with standard errors) and by a grid.

    Returns:
        ``modes`` (64 labels), ``box`` (its volume), ``exact_reach`` ((2 min(l1, l2))³),
        ``monte_carlo`` / ``grid``: {measure: (64,) volumes}, ``standard_error``:
        {measure: (64,)}, ``samples``, ``grid_points``, and the reach's extremes over the
        modes (``reach_monte_carlo_min`` ...).
    """
    half = BOX_FACTOR * min(g.l1, g.l2)
    box = (2.0 * half) ** 3
    rng = np.random.default_rng(seed)
    mc = _fractions(g, rng.uniform(-half, half, (samples, 3)), drive_limits)
    axis = -half + (np.arange(grid) + 0.5) * (2.0 * half / grid)
    pts = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), -1).reshape(-1, 3)
    gr = _fractions(g, pts, drive_limits)
    se = {k: box * np.sqrt(v * (1.0 - v) / samples) for k, v in mc.items()}
    return {
        "modes": list(MODES),
        "box": box,
        "exact_reach": (2.0 * min(g.l1, g.l2)) ** 3,
        "monte_carlo": {k: box * v for k, v in mc.items()},
        "standard_error": se,
        "grid": {k: box * v for k, v in gr.items()},
        "samples": samples,
        "grid_points": grid**3,
        "reach_monte_carlo_min": float(box * mc["reach"].min()),
        "reach_monte_carlo_max": float(box * mc["reach"].max()),
        "reach_standard_error": float(se["reach"].max()),
        "reach_grid_min": float(box * gr["reach"].min()),
        "reach_grid_max": float(box * gr["reach"].max()),
    }


def section(
    g: Geometry3PPaPa, axis: int, offset: float, mode: str, n: int = 161
) -> dict[str, np.ndarray]:
    """det A on the plane p_axis = offset [m] in one mode: ``u``, ``v`` (n,) the other two
    coordinates (in cyclic order), ``det`` (n, n) [-], NaN out of reach."""
    half = BOX_FACTOR * min(g.l1, g.l2)
    u = np.linspace(-half, half, n)
    uu, vv = np.meshgrid(u, u, indexing="ij")
    p = np.zeros((n, n, 3))
    p[..., axis], p[..., (axis + 1) % 3], p[..., (axis + 2) % 3] = offset, uu, vv
    s = np.broadcast_to(SIGNS[MODES.index(mode)], (n, n, 3, 2))
    a = a_matrix(g, p, s)
    det = np.full((n, n), np.nan)
    ok = np.isfinite(a).all((-1, -2))
    det[ok] = np.linalg.det(a[ok])
    return {"u": u, "v": u, "det": det}


__all__ = ["BOX_FACTOR", "CONDITION", "SIGNS", "measures", "section", "volumes"]
