"""Row ``rcm_step``, rcm-pin only: the programmable RCM's 1 kHz loop on the case's arm at
its chosen trocar (``rcm_comparison.make_setup``), ``rcm_loop.track`` along the first
``steps`` samples of the circle path, one :meth:`RcmQP.step` (``method="qp"``: qpsolvers +
daqp) or :meth:`RcmQP.step_pink` (``"pink"``: the same QP through pin-pink) per sample,
plus the state read-out of each step; accuracy: RCM and tip errors along the run."""

from __future__ import annotations

from typing import Any

import numpy as np

from rcm_pin.control.rcm_loop import track
from rcm_pin.studies.rcm_comparison import controller, make_setup, start_configuration
from rcm_pin.studies.surgical_paths import surgical_path


def setup(case: dict[str, Any]) -> dict[str, Any]:
    s = make_setup(case["arm"])
    p = surgical_path("circle", s.cone, rate=1000.0).p[: case["steps"] + 1]
    return {"ctrl": controller(s, 1e-3), "q0": start_configuration(s, p[0]), "p": p,
            "method": case["method"]}  # fmt: skip


def run_once(state: dict[str, Any]) -> Any:
    return track(state["ctrl"], state["q0"], state["p"], method=state["method"])


def accuracy(state: dict[str, Any], run: Any) -> dict[str, Any]:
    return {"rcm_error_max_m": float(run.rcm_error.max()),
            "tip_error_max_m": float(run.tip_error.max()),
            "step_median_us": float(1e6 * np.median(run.step_time))}  # fmt: skip
