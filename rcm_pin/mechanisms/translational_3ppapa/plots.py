"""The 3-PPaPa workspace sections (matplotlib, Agg backend).

Planes x = const, y = const, z = const through P = 0 (the centre of the paper's control
reference) and through the diagonal type-2 point x = y = z = t*: sign of det A filled, the
type-2 surface det A = 0 (red), the type-1 set (a stretched parallelogram: |b_i| = l2 or
|c_i| = l1, the reach boundary, blue dashed) and the reference segment t (0.1, 0.12, 0.15)
m, |t| ≤ 1, projected on the plane (green).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from rcm_pin.mechanisms.translational_3ppapa import workspace as ws
from rcm_pin.mechanisms.translational_3ppapa.closed_form import Geometry3PPaPa

#: The paper's control-reference amplitudes (x, y, z) [m].
REFERENCE = np.array([0.1, 0.12, 0.15])
NAMES = "xyz"


def _type1(ax: plt.Axes, g: Geometry3PPaPa) -> None:
    """The stretched-parallelogram lines |coordinate| = l2 and l1 inside the frame."""
    for length, style in ((g.l2, "--"), (g.l1, ":")):
        for s in (-1.0, 1.0):
            ax.axvline(s * length, color="tab:blue", ls=style, lw=1.0)
            ax.axhline(s * length, color="tab:blue", ls=style, lw=1.0)


def sections_figure(
    g: Geometry3PPaPa, path: Path, t_star: float, mode: str = "++/++/++", n: int = 161
) -> Path:
    """Six sections (two offsets × three planes) of one working mode; returns ``path``."""
    fig, axes = plt.subplots(2, 3, figsize=(14, 8.6))
    for row, offset in enumerate((0.0, t_star)):
        for axis in range(3):
            ax = axes[row, axis]
            sec = ws.section(g, axis, offset, mode, n)
            u, v = NAMES[(axis + 1) % 3], NAMES[(axis + 2) % 3]
            sign = np.sign(sec["det"]).T
            ax.contourf(sec["u"], sec["v"], sign, levels=[-1.5, 0, 1.5],
                        colors=["#f5d7c8", "#cfe3f5"])  # fmt: skip
            if np.nanmin(sec["det"]) < 0 < np.nanmax(sec["det"]):
                ax.contour(sec["u"], sec["v"], np.ma.masked_invalid(sec["det"].T),
                           levels=[0.0], colors="tab:red", linewidths=1.6)  # fmt: skip
            _type1(ax, g)
            if row == 1:
                ax.plot([t_star], [t_star], "ko", ms=4)  # the diagonal type-2 point
            ref = np.outer(np.linspace(-1, 1, 2), REFERENCE)
            ax.plot(ref[:, (axis + 1) % 3], ref[:, (axis + 2) % 3], "-", color="tab:green", lw=2)
            half = ws.BOX_FACTOR * min(g.l1, g.l2)
            ax.set(xlim=(-half, half), ylim=(-half, half), aspect="equal",
                   xlabel=f"{u} [m]", ylabel=f"{v} [m]",
                   title=f"{NAMES[axis]} = {offset:.4g} m")  # fmt: skip
    fig.suptitle(
        f"3-PPaPa, mode {mode}: det A > 0 (blue) / < 0 (salmon), det A = 0 (red), stretched "
        "parallelogram |.| = l2 (blue --), l1 (blue :),\nreference (green), diagonal type-2 "
        "point x = y = z = t* (dot)"
    )
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


__all__ = ["REFERENCE", "sections_figure"]
