"""Workspace and singular curves of the planar 3-RRR (paper 004 Figs. 2–3), vectorised.

* Constant-orientation workspace W(φ): poses (x, y, φ) where every leg reaches its vertex,
  |l1_i − l2_i| ≤ |A_i C_i| ≤ l1_i + l2_i (inverse problem, as in the paper).
* Total-orientation workspace: points (x, y) reachable for *every* φ in a range; the
  dexterous count of reachable φ samples is also returned (maximal-orientation map).
* Singular curves for one working mode at fixed φ: zero sets of det A (type 2) and det B
  (type 1) of the closed form, sampled on the grid; :func:`type2_points` refines sign
  changes of det A along grid rows with ``scipy.optimize.brentq`` (exact curve points).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from rcm_pin.mechanisms.planar_3rrr import closed_form as p3


@dataclass(frozen=True)
class Grid:
    """Regular (x, y) grid [m]."""

    x: np.ndarray
    y: np.ndarray

    @classmethod
    def around(cls, g: p3.Geometry3RRR, n: int = 241) -> Grid:
        """Square grid of half-width max(l1 + l2) + r_p (covers the workspace) [m]."""
        r = float(np.max(g.l1 + g.l2)) + g.rp
        return cls(np.linspace(-r, r, n), np.linspace(-r, r, n))

    def poses(self, phi: float) -> np.ndarray:
        """(ny, nx, 3) poses at orientation φ [rad]."""
        xx, yy = np.meshgrid(self.x, self.y)
        return np.stack([xx, yy, np.full_like(xx, phi)], axis=-1)


def constant_orientation(g: p3.Geometry3RRR, grid: Grid, phi: float) -> np.ndarray:
    """Boolean (ny, nx) map of W(φ) (reachability only, :func:`.closed_form.reachable`)."""
    return p3.reachable(g, grid.poses(phi))


def orientation_count(g: p3.Geometry3RRR, grid: Grid, phis: np.ndarray) -> np.ndarray:
    """(ny, nx) number of φ samples reachable at each point (total = all, reachable = > 0)."""
    count = np.zeros((len(grid.y), len(grid.x)), dtype=int)
    for phi in phis:
        count += constant_orientation(g, grid, float(phi))
    return count


def det_maps(g: p3.Geometry3RRR, grid: Grid, phi: float, mode: int) -> tuple[np.ndarray, ...]:
    """Normalised det A, det B (ny, nx) for working mode ``mode`` (NaN outside W(φ)).

    det A / (8 l2³ r_p) and det B / (8 l1³ l2³) are dimensionless.
    """
    poses = grid.poses(phi)
    qs, ok = p3.inverse_position(g, poses)
    q = qs[..., mode, :]
    a_mat, b_mat = p3.ab_matrices(g, poses, np.nan_to_num(q))
    da = np.linalg.det(a_mat) / (8 * np.prod(g.l2) * g.rp)
    db = np.linalg.det(b_mat) / (8 * np.prod(g.l1) * np.prod(g.l2))
    da[~ok] = np.nan
    db[~ok] = np.nan
    return da, db


def _det_a_at(g: p3.Geometry3RRR, x: float, y: float, phi: float, mode: int) -> float:
    pose = np.array([x, y, phi])
    qs, ok = p3.inverse_position(g, pose)
    return float(np.linalg.det(p3.ab_matrices(g, pose, qs[mode])[0])) if ok else np.nan


def type2_points(
    g: p3.Geometry3RRR, phi: float, mode: int, n: int = 121, max_points: int | None = None
) -> np.ndarray:
    """Points (N, 3) exactly on the type-2 curve (det A = 0) of a working mode at φ.

    Sign changes of det A between neighbouring reachable samples of each grid row are
    refined by Brent's method (xtol 1e-16 m, rtol 1e-15).
    """
    grid = Grid.around(g, n)
    da, _ = det_maps(g, grid, phi, mode)
    pts = []
    for iy, y in enumerate(grid.y):
        row = da[iy]
        for ix in range(len(grid.x) - 1):
            a, b = row[ix], row[ix + 1]
            if np.isfinite(a) and np.isfinite(b) and a * b < 0:

                def f(x: float, y: float = float(y)) -> float:
                    return _det_a_at(g, x, y, phi, mode)

                try:
                    x0 = brentq(f, grid.x[ix], grid.x[ix + 1], xtol=1e-16, rtol=1e-15)
                except ValueError:
                    continue
                pts.append((x0, float(y), phi))
        if max_points and len(pts) >= max_points:
            break
    return np.array(pts).reshape(-1, 3)


def type1_points(g: p3.Geometry3RRR, phi: float, n: int = 720) -> np.ndarray:
    """Poses (N, 3) with some leg stretched or folded (A_i, B_i, C_i aligned), reachable.

    C_i = A_i + ρ (cos ψ, sin ψ), ρ ∈ {l1_i + l2_i, |l1_i − l2_i|}, O = C_i − r_p e(φ + b_i).
    """
    out = []
    psi = np.linspace(-np.pi, np.pi, n, endpoint=False)
    for i in range(3):
        for rho in (g.l1[i] + g.l2[i], abs(g.l1[i] - g.l2[i])):
            c = g.base[i] + rho * np.stack([np.cos(psi), np.sin(psi)], axis=-1)
            ang = phi + g.b[i]
            o = c - g.rp * np.array([np.cos(ang), np.sin(ang)])
            poses = np.column_stack([o, np.full(n, phi)])
            ok = p3.inverse_position(g, poses)[1]
            dist = np.linalg.norm(g.vertices(poses) - g.base, axis=-1)
            others = np.ones(n, dtype=bool)
            for j in range(3):
                if j != i:  # strictly inside the other legs' annuli (one singular leg)
                    others &= (dist[:, j] < g.l1[j] + g.l2[j] - 1e-6) & (
                        dist[:, j] > abs(g.l1[j] - g.l2[j]) + 1e-6
                    )
            out.append(np.column_stack([poses[ok & others], np.full((ok & others).sum(), i)]))
    return np.vstack(out)
