"""Row ``sim``, rcm-pin: ``simulate`` of the case (rows.sim_case), python or compiled
backend (``case["backend"]``), DOP853 at the case's rtol / atol, 101 output samples."""

from __future__ import annotations

from typing import Any

import numpy as np
from common import accuracy_vs

import rcm_pin
from rcm_pin.control.computed_torque import ComputedTorque, Gains
from rcm_pin.control.references import TRAJECTORIES
from rcm_pin.control.simulate import SimulationOptions, simulate


def setup(case: dict[str, Any]) -> dict[str, Any]:
    mech = rcm_pin.load(case["mechanism"], **case["xacro_args"])
    ctrl = ComputedTorque(
        mech, TRAJECTORIES["paper000"], Gains(case["kn"], case["kc"]),
        limits=np.asarray(case["limits"]),
    )  # fmt: skip
    opts = SimulationOptions(
        rtol=case["rtol"], atol=case["atol"], samples=case["samples"], backend=case["backend"]
    )
    return {"mech": mech, "ctrl": ctrl, "opts": opts, "case": case}


def run_once(state: dict[str, Any]) -> dict[str, Any]:
    mech, case = state["mech"], state["case"]
    r = simulate(mech, state["ctrl"], case["duration"], q0=np.asarray(case["q0"]),
                 options=state["opts"])  # fmt: skip
    return {**accuracy_vs(r.q, case, r.x), "rhs_evaluations": r.nfev, "status": r.status}
