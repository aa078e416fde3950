"""The result of a tracking OCP: trajectories on the grid and solver diagnostics."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np


@dataclass(frozen=True)
class TrackingResult:
    """OCP solution on the grid: nodes (N + 1) and collocation points (N d)."""

    t: np.ndarray  # node times (N + 1,)
    q: np.ndarray  # (N + 1, nq)
    v: np.ndarray  # (N + 1, nv)
    t_colloc: np.ndarray  # (N d,)
    q_colloc: np.ndarray  # (N d, nq)
    v_colloc: np.ndarray  # (N d, nv)
    a_colloc: np.ndarray  # (N d, nv)
    tau: np.ndarray  # (N d, nv) drive efforts
    p: np.ndarray  # (N d, 3) frame position
    p_ref: np.ndarray  # (N d, 3)
    tracking_error: float  # max |p - p_ref| [m]
    tracking_rms: float  # [m]
    objective: float
    success: bool
    status: str
    iterations: int
    solve_time: float  # [s], wall time of the solver call
    solver: str


def make_result(
    grid: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    q_colloc: np.ndarray,
    outputs: list[np.ndarray],
    p_ref: np.ndarray,
    objective: float,
    stats: dict[str, Any],
    wall: float,
    solver: str,
) -> TrackingResult:
    """Assemble from ``grid = (t, q, v, t_colloc)``, the collocation positions, the
    stage outputs ``(V, A, tau, p)`` at the collocation points and the solver's stats."""
    t, q, v, t_colloc = grid
    v_c, a_c, tau, p = outputs
    err = np.linalg.norm(p - p_ref, axis=1)
    return TrackingResult(
        t, q, v, t_colloc, q_colloc, v_c, a_c, tau, p, p_ref, float(err.max()),
        float(np.sqrt(np.mean(err**2))), objective, bool(stats.get("success", False)),
        str(stats.get("return_status", "unknown")), int(stats.get("iter_count", -1)), wall,
        solver,
    )  # fmt: skip


__all__ = ["TrackingResult", "make_result"]
