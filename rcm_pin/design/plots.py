"""Pictures of a study: a metric over two varied arguments, the Pareto front of two metrics."""

from __future__ import annotations

import io
from pathlib import Path
from typing import TYPE_CHECKING

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from rcm_pin.errors import InvalidInputError
from rcm_pin.processes import atomic_write

if TYPE_CHECKING:
    import pandas as pd


def _save(fig: plt.Figure, path: Path) -> None:
    """The figure as PNG by atomic rename (a killed run never leaves half a picture)."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=120)
    atomic_write(Path(path), buffer.getvalue())


def metric_map(frame: pd.DataFrame, x: str, y: str, metric: str, path: Path) -> Path:
    """Colour map of ``metric`` over the arguments ``x`` and ``y`` (a grid study); infeasible
    designs hatched over, designs that could not be built left blank."""
    cols = [f"arg.{x}", f"arg.{y}", metric]
    missing = [c for c in cols if c not in frame]
    if missing:
        raise InvalidInputError(
            f"no column {missing[0]!r} in the table; valid: {', '.join(map(str, frame.columns))}"
        )
    grid = frame.pivot_table(index=cols[1], columns=cols[0], values=metric, aggfunc="first")
    fig, ax = plt.subplots(figsize=(6.4, 5.0), layout="constrained")
    mesh = ax.pcolormesh(grid.columns, grid.index, grid.to_numpy(float), shading="nearest")
    fig.colorbar(mesh, ax=ax, label=metric)
    bad = frame[~frame["feasible"]]
    ax.scatter(bad[cols[0]], bad[cols[1]], marker="x", color="white", s=18, label="infeasible")
    ax.set_xlabel(x)
    ax.set_ylabel(y)
    # the marks are explained in the title: a legend inside the map covered a corner's marks
    marks = "; white ×: infeasible" if len(bad) else ""
    ax.set_title(f"{frame['mechanism'].iloc[0]}: {metric}{marks}")
    _save(fig, path)
    plt.close(fig)
    return Path(path)


def pareto_front(frame: pd.DataFrame, a: str, b: str, path: Path) -> Path:
    """Every evaluated design in the (a, b) plane, the Pareto-optimal ones joined."""
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    ok = frame["status"] == "ok"
    ax.scatter(frame[a][ok], frame[b][ok], s=12, color="0.6", label="evaluated")
    front = frame[frame["pareto"]].sort_values(a)
    ax.plot(front[a], front[b], "o-", color="C3", label="Pareto front")
    ax.set_xlabel(a)
    ax.set_ylabel(b)
    ax.legend()
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    _save(fig, path)
    plt.close(fig)
    return Path(path)


__all__ = ["metric_map", "pareto_front"]
