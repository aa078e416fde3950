"""Maps of the singularity measures of a closed mechanism over its workspace.

The family's :class:`.singularity_model.SingularityModel` draws the map: a vectorised
closed form (normalised det A and det B of one working mode over a grid of the first two
output coordinates) where it has one; otherwise the numeric default: the inverse problem
in every cell and Pinocchio's A/B measures (σ_min/σ_max) of the chosen working mode. NaN
outside the workspace. Summaries: reachable area, sign changes of det A along grid rows
(type-2 curve crossings) and the smallest |det A|, |det B| (or measures).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from rcm_pin.analysis.singularity_model import singularity_model
from rcm_pin.errors import InvalidInputError
from rcm_pin.model.mechanism import Mechanism


def singularity_map(mech: Mechanism, mode: int = 0, phi: float = 0.0, n: int = 121) -> dict:
    """Closed-form (or numeric) det A / det B maps of one working mode (module docstring).

    Raises:
        InvalidInputError: n < 5, or no map for this mechanism's outputs.
    """
    if n < 5:
        raise InvalidInputError(f"grid size {n}; valid: >= 5 points per side")
    res = singularity_model(mech).workspace_map(mech, mode, phi, n)
    x, y, da, db = res.x, res.y, np.asarray(res.det_a), np.asarray(res.det_b)
    finite = np.isfinite(da)
    cell = float((x[1] - x[0]) * (y[1] - y[0]))
    return {
        "mechanism": mech.name,
        **res.to_dict(),
        "reachable_area": float(finite.sum()) * cell,
        "type2_sign_changes": int(np.sum((da[:, 1:] * da[:, :-1]) < 0)),
        "min_abs_det_A": float(np.min(np.abs(da[finite]))) if finite.any() else None,
        "min_abs_det_B": float(np.min(np.abs(db[finite]))) if finite.any() else None,
    }


def plot_singularity_map(result: dict[str, Any], path: str | Path) -> Path:
    """PNG: det A (red zero contour: type 2) and det B (blue zero contour: type 1)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x, y = np.asarray(result["x"]), np.asarray(result["y"])
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.4))
    for ax, key, colour, label in (
        (axes[0], "det_A", "tab:red", "type 2: det A = 0"),
        (axes[1], "det_B", "tab:blue", "type 1: det B = 0 (workspace boundary)"),
    ):
        z = np.asarray(result[key], dtype=float)
        lim = float(np.nanmax(np.abs(z))) if np.isfinite(z).any() else 1.0
        im = ax.pcolormesh(x, y, z, shading="auto", cmap="coolwarm", vmin=-lim, vmax=lim)
        fig.colorbar(im, ax=ax, label=f"normalised {key.replace('_', ' ')}")
        if np.isfinite(z).any() and np.nanmin(z) < 0 < np.nanmax(z):
            ax.contour(x, y, z, levels=[0.0], colors=colour, linewidths=1.6)
        ax.plot([], [], color=colour, label=label)
        ax.legend(loc="lower left", fontsize=8)
        ax.set(xlabel="x [m]", ylabel="y [m]", aspect="equal")
    where = f"φ = {np.degrees(result['phi']):.3g}°, " if result["phi"] is not None else ""
    fig.suptitle(f"{result['mechanism']}: {where}working mode {result['mode']}")
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


__all__ = ["plot_singularity_map", "singularity_map"]
