"""PNG plots of a :class:`~rcm_pin.control.simulate.SimulationResult` (paper 000 Fig. 4 style)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from rcm_pin.control.result import SimulationResult


def _finish(fig: Any, ax: Any, path: Path) -> Path:
    """Grid, tight layout, save at 120 dpi, close."""
    import matplotlib.pyplot as plt

    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_deviation(
    result: SimulationResult,
    path: Path,
    axis: int = 0,
    prediction: np.ndarray | None = None,
    title: str = "",
) -> Path:
    """Deviation e_axis(t) = x_ref − x (paper 000 Fig. 4a), optional linear prediction."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 3.6))
    ax.plot(result.t, 1e3 * result.error[:, axis], label="simulated (Pinocchio)")
    if prediction is not None:
        ax.plot(result.t, 1e3 * prediction, "--", label="linear error dynamics")
    ax.set_xlabel("t [s]")
    ax.set_ylabel(f"Dev {'xyz'[axis]} = {'xyz'[axis]}_t − {'xyz'[axis]} [mm]")
    ax.set_title(title or f"{result.mechanism}: deviation along {'xyz'[axis]}")
    ax.legend()
    return _finish(fig, ax, path)


def plot_phase(result: SimulationResult, path: Path, axis: int = 0, title: str = "") -> Path:
    """Phase trajectory (p_axis, ṗ_axis) with the desired one (paper 000 Fig. 4b)."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.0, 4.2))
    ax.plot(result.x[:, axis], result.xd[:, axis], label="simulated")
    ax.plot(result.x_ref[:, axis], result.xd_ref[:, axis], "--", label="desired")
    ax.plot(result.x[0, axis], result.xd[0, axis], "o", label="start")
    c = "xyz"[axis]
    ax.set_xlabel(f"{c} [m]")
    ax.set_ylabel(f"d{c}/dt [m/s]")
    ax.set_title(title or f"{result.mechanism}: phase trajectory along {c}")
    ax.legend()
    return _finish(fig, ax, path)


def plot_efforts(result: SimulationResult, path: Path, title: str = "") -> Path:
    """Drive efforts τ_i(t) of an RCM mechanism (q3, a force in N, on the right axis)."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 3.6))
    for i in range(result.tau.shape[1]):
        if i != 2:
            ax.plot(result.t, result.tau[:, i], label=f"τ{i + 1} [N·m]")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("torque [N·m]")
    ax2 = ax.twinx()
    ax2.plot(result.t, result.tau[:, 2], "k", lw=1.0, label="F3 [N]")
    ax2.set_ylabel("force F3 [N]")
    lines = ax.get_legend_handles_labels()
    lines2 = ax2.get_legend_handles_labels()
    ax.legend(lines[0] + lines2[0], lines[1] + lines2[1], fontsize=8, loc="upper right")
    ax.set_title(title or f"{result.mechanism}: drive efforts")
    return _finish(fig, ax, path)


__all__ = ["plot_deviation", "plot_efforts", "plot_phase"]
