"""Helpers shared by the worker modules of every venv (numpy only: no rcm-pin here)."""

from __future__ import annotations

from typing import Any

import numpy as np


def reference(traj: dict[str, Any], t: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(p, ṗ, p̈) (..., 3) of a ``CartesianTrajectory`` given as a dict (centre, amplitude,
    omega, phase): p = centre + amplitude ⊙ sin(ω t + phase)."""
    c, a = np.asarray(traj["centre"]), np.asarray(traj["amplitude"])
    w, arg = float(traj["omega"]), float(traj["omega"]) * np.asarray(t, float)[..., None]
    arg = arg + np.asarray(traj["phase"])
    return c + a * np.sin(arg), a * w * np.cos(arg), -a * w**2 * np.sin(arg)


def accuracy_vs(q: np.ndarray, case: dict[str, Any], p: np.ndarray) -> dict[str, float]:
    """Δq (largest |q − q_ref| at the case's samples) and the task error |p − p_ref| at
    the last sample."""
    q_ref = np.asarray(case["q_ref"])
    p_ref = reference(case["traj"], np.asarray(case["t"]))[0]
    return {
        "dq_max": float(np.abs(np.asarray(q) - q_ref).max()),
        "task_error_end_m": float(np.linalg.norm(np.asarray(p)[-1] - p_ref[-1])),
    }


def task_space_ct(
    case: dict[str, Any], t: float, p: np.ndarray, J: np.ndarray, Jdv: np.ndarray,
    v: np.ndarray,
) -> np.ndarray:  # fmt: skip
    """q̈* of rcm-pin's task-space computed torque (square task): J q̈ = a* − J̇q̇ with
    a* = ẍ_T + K_n (x_T − x) + K_c (ẋ_T − J q̇)."""
    x_t, v_t, a_t = reference(case["traj"], t)
    a_star = a_t + case["kn"] * (x_t - p) + case["kc"] * (v_t - J @ v)
    return np.linalg.solve(J, a_star - Jdv)


__all__ = ["accuracy_vs", "reference", "task_space_ct"]
