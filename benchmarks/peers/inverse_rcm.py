"""Row ``inverse``, rcm-pin: ``rcm_pin.inverse(mech, T)`` of rcm_bevel (all 8 branches),
one pose per call, on the case's seeded random reachable poses (as bench_ik.py), in the
steady state of a loop (as bench_ik.py): the ``serial_branches`` kernel built and compiled
in ``setup`` (a loop reaches it after 100 requests, compiled after 1000 kernel calls)."""

from __future__ import annotations

from typing import Any

import numpy as np

import rcm_pin
from rcm_pin.mechanisms.rcm.closed_form import tool_pose
from rcm_pin.model import serial_branches


def poses(case: dict[str, Any]) -> np.ndarray:
    """The case's poses: q uniform in ±π (q3 in [0.05, 0.12] m), their tool poses."""
    rng = np.random.default_rng(case["seed"])
    q = rng.uniform(-np.pi, np.pi, (case["poses"], 6))
    q[:, 2] = rng.uniform(0.05, 0.12, case["poses"])  # [m]
    return np.asarray(tool_pose(q))


def fk_error(Ts: np.ndarray, qs: list[np.ndarray]) -> float:
    """Largest |FK(IK(T)) − T| over every branch of every pose."""
    return max(float(np.abs(tool_pose(q) - T).max()) for T, q in zip(Ts, qs) if len(q))


def setup(case: dict[str, Any]) -> dict[str, Any]:
    mech = rcm_pin.load(case["mechanism"])
    shared = getattr(serial_branches.warm(mech), "shared", None)
    if shared is not None and shared.compile_after is not None:
        shared.compile()
    return {"mech": mech, "poses": poses(case)}


def run_once(state: dict[str, Any]) -> list[Any]:
    mech = state["mech"]
    return [rcm_pin.inverse(mech, T) for T in state["poses"]]


def accuracy(state: dict[str, Any], out: list[Any]) -> dict[str, Any]:
    qs = [np.array([s.q for s in r.solutions]) for r in out]
    return {"fk_error_max": fk_error(state["poses"], qs),
            "branches": int(sum(len(q) for q in qs))}  # fmt: skip
