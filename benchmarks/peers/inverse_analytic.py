"""Row ``inverse``, the floor: the scalar analytic IK ``analytic_ik.ik_pose(T)`` (all 8
branches, the fast path of ``rcm_pin.mechanisms.rcm.ik_scalar``) on the same poses."""

from __future__ import annotations

from typing import Any

import numpy as np
from inverse_rcm import fk_error, poses

from rcm_pin.mechanisms.rcm.analytic_ik import ik_pose


def setup(case: dict[str, Any]) -> dict[str, Any]:
    return {"poses": poses(case)}


def run_once(state: dict[str, Any]) -> list[Any]:
    return [ik_pose(T) for T in state["poses"]]


def accuracy(state: dict[str, Any], out: list[Any]) -> dict[str, Any]:
    qs = [np.asarray(s.q).reshape(-1, 6) for s in out]
    qs = [q[~np.isnan(q).any(axis=1)] for q in qs]
    return {"fk_error_max": fk_error(state["poses"], qs),
            "branches": int(sum(len(q) for q in qs))}  # fmt: skip
