"""Row ``rcm_ik``, rcm-pin: :class:`ocp.RcmIK` (its default: the RCM as an equality,
solved by the compiled projected LM; tol 1e-12) of the case's arm at its trocar, the
targets in turn, each solve from the previous solution (the first from the case's start
configuration)."""

from __future__ import annotations

import itertools
from typing import Any

import numpy as np

from ocp import RcmIK
from rcm_pin.studies.rcm_comparison import make_setup


def setup(case: dict[str, Any]) -> dict[str, Any]:
    s = make_setup(case["arm"])
    assert s.chain is not None
    return {"ik": RcmIK(s.chain.model, s.chain.tool, tol=case["tol"]),
            "q0": np.asarray(case["q0"]), "targets": np.asarray(case["targets"])}  # fmt: skip


def run_once(state: dict[str, Any]) -> list[Any]:
    q, out = state["q0"], []
    for p in state["targets"]:
        r = state["ik"].solve(p, q, raise_on_failure=False)
        q = r.ik.q
        out.append(r)
    return out


def accuracy(state: dict[str, Any], out: list[Any]) -> dict[str, Any]:
    return {"rcm_error_max_m": max(r.rcm_error for r in out),
            "rcm_error_median_m": float(np.median([r.rcm_error for r in out])),
            "tip_error_max_m": max(r.tip_error for r in out),
            "failures": sum(not r.ik.success for r in out),
            "step_dq_max": float(max(np.abs(b.ik.q - a.ik.q).max()
                                     for a, b in itertools.pairwise(out)))}  # fmt: skip
