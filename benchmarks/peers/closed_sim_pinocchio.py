"""Row ``closed_sim``, the floor: the Pinocchio calls of one closed right-hand side
(``bench_dynamics.closed_pin``: kinematics, closure frames' Jacobians and classical
accelerations, rnea, crba, nonLinearEffects) on states of an rcm-pin run, as many times
as that run evaluates its right-hand side."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench_dynamics import closed_pin
from closed_sim_rcm import run_once as simulate_once
from closed_sim_rcm import setup as simulate_setup


def setup(case: dict[str, Any]) -> dict[str, Any]:
    sim = simulate_setup(case)
    r = simulate_once(sim)
    calls = closed_pin(sim["mech"], r, 1)
    n = max(round(r.nfev / calls()), 1)  # closed_pin does n × (its 10 states) calls
    return {"calls": closed_pin(sim["mech"], r, n), "nfev": int(r.nfev)}


def run_once(state: dict[str, Any]) -> dict[str, Any]:
    return {"right_hand_sides": state["calls"](), "of_the_run": state["nfev"]}
