"""The 3-RRR workspace figure (paper 004 Figs. 2–3; matplotlib, Agg backend)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from rcm_pin.mechanisms.planar_3rrr import closed_form as p3
from rcm_pin.mechanisms.planar_3rrr import workspace as ws


def _draw_mechanism(ax: plt.Axes, g: p3.Geometry3RRR, pose: np.ndarray, mode: int) -> np.ndarray:
    """Draw the legs and the platform; return the drawn points (k, 2) [m]."""
    qs, ok = p3.inverse_position(g, pose)
    if not ok:
        return np.zeros((0, 2))
    c = g.vertices(pose)
    b = g.elbows(qs[mode])
    for i in range(3):
        ax.plot(*np.array([g.base[i], b[i], c[i]]).T, "k-o", ms=3, lw=1.2)
    ax.fill(*c.T, color="0.6", alpha=0.6)
    return np.vstack([g.base, b, c])


def workspace_figure(
    g: p3.Geometry3RRR, path: Path, phi: float = 0.0, mode: int = 3, n: int = 301
) -> Path:
    """Constant-orientation workspace with type-1/type-2 curves, and total orientation."""
    grid = ws.Grid.around(g, n)
    fig, axes = plt.subplots(1, 2, figsize=(12, 6.0), layout="constrained")
    w = ws.constant_orientation(g, grid, phi)
    da, _ = ws.det_maps(g, grid, phi, mode)
    ax = axes[0]
    ax.contourf(grid.x, grid.y, w, levels=[0.5, 1.5], colors=["#cfe3f5"])
    ax.contour(grid.x, grid.y, da, levels=[0.0], colors="tab:red", linewidths=1.6)
    ax.contour(grid.x, grid.y, w.astype(float), levels=[0.5], colors="tab:blue", linewidths=0.8)
    drawn = _draw_mechanism(ax, g, np.array([0.0, 0.0, phi]), mode)
    ax.plot([], [], color="tab:red", label="type 2: det A = 0")
    ax.plot([], [], color="tab:blue", label="boundary: a leg stretched/folded, det B = 0 (type 1)")
    label = f"{mode:03b}".replace("0", "+").replace("1", "−")
    ax.set_title(f"constant orientation φ = {np.degrees(phi):.0f}°, working mode {label}")
    # below the axes: inside, it covered a leg
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), fontsize=8)
    phis = np.radians(np.arange(-180, 180, 2.0))
    count = ws.orientation_count(g, grid, phis)
    ax = axes[1]
    frac = np.where(count > 0, count * 2.0, np.nan)
    im = ax.pcolormesh(grid.x, grid.y, frac, shading="auto", cmap="viridis")
    fig.colorbar(im, ax=ax, label="reachable orientation range [deg]")
    dex = ws.orientation_count(g, grid, np.radians(np.arange(-30, 31, 2.0)))
    ax.contour(grid.x, grid.y, dex, levels=[30.5], colors="w", linewidths=1.2)
    ax.set_title("total workspace; white: every |φ| ≤ 30° reachable")
    inside = np.argwhere(count > 0)
    lo = min(grid.x[inside[:, 1].min()], grid.y[inside[:, 0].min()]) - 0.02
    hi = max(grid.x[inside[:, 1].max()], grid.y[inside[:, 0].max()]) + 0.02
    for a in axes:
        a.set_xlim(lo, hi)
        a.set_ylim(lo, hi)
        a.set_aspect("equal")
        a.set_xlabel("x [m]")
        a.set_ylabel("y [m]")
        a.plot(*g.base.T, "k^", ms=7)
    if len(drawn):  # the drawn legs may reach beyond the workspace: show them whole
        lo_m = min(lo, float(drawn.min()) - 0.02)
        hi_m = max(hi, float(drawn.max()) + 0.02)
        axes[0].set_xlim(lo_m, hi_m)
        axes[0].set_ylim(lo_m, hi_m)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return path


__all__ = ["workspace_figure"]
