"""Two design studies on the RCM mechanisms (the report's design section).

1. **Which joint limits cover the rig's cone with the best worst-case conditioning?**
   rcm_bevel with q2_limit (the tilt range ±q2_limit [rad]) and q3_lower (the shortest
   insertion [m]) on a grid; constraint: the whole rig region is reached
   (``cone_coverage >= 1``); objective: the largest ``worst_conditioning``. Second route:
   the closed form. Coverage needs q1_limit, q2_limit ≥ 60° (the cone's directions reach
   |q1| = |q2| = 60°) and q3_lower ≤ 0.05 m, and κ⁻¹_min = (q3_lower/q3_upper)·cos q2_limit,
   so the optimum is q2_limit = 60°, q3_lower = 0.05 m: κ⁻¹ = (0.05/0.12)·cos 60° = 0.2083.
2. **Which manufacturing error dominates the RCM drift?** The share of every part-placement
   error component in E|c|² (first order, :func:`rcm_pin.mechanisms.rcm.design.drift_contributions`)
   for the bevel and the belt variants, and the RMS drift checked against a nonlinear
   Monte Carlo over perturbed models.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from rcm_pin.catalog import load
from rcm_pin.design import Study, Vary
from rcm_pin.design.study import Constraint
from rcm_pin.mechanisms.rcm import design as rd
from rcm_pin.mechanisms.rcm.accuracy import outputs
from rcm_pin.mechanisms.rcm.workspace import SPEC_HALF_ANGLE, SPEC_R_MIN

if TYPE_CHECKING:  # the frames come from rcm_pin.design.run, which needs pandas
    import pandas as pd

RIG_STUDY = Study(
    "rcm_bevel",
    (Vary("q2_limit", 0.8, 1.4, 7), Vary("q3_lower", 0.02, 0.07, 6)),
    ("cone_coverage", "worst_conditioning"),
    constraints=(Constraint("cone_coverage", ">=", 1.0),),
)
#: Variants of the tolerance study.
TOLERANCE_VARIANTS = ("rcm_bevel", "rcm_belt")


@dataclass(frozen=True)
class RigAnswer:
    """The best feasible grid design and the closed-form optimum of study 1."""

    grid_q2_limit: float  # [rad]
    grid_q3_lower: float  # [m]
    grid_conditioning: float
    closed_q2_limit: float  # [rad]
    closed_q3_lower: float  # [m]
    closed_conditioning: float
    closed_check: float  # the metric evaluated at the closed-form optimum


def rig_answer(frame: pd.DataFrame) -> RigAnswer:
    """Study 1's answer from its table, beside the closed form (module docstring)."""
    best = frame[frame["feasible"]].sort_values("worst_conditioning").iloc[-1]
    mech = load("rcm_bevel", q2_limit=repr(float(SPEC_HALF_ANGLE)), q3_lower=repr(SPEC_R_MIN))
    closed = SPEC_R_MIN / mech.upper[2] * np.cos(SPEC_HALF_ANGLE)
    return RigAnswer(
        float(best["arg.q2_limit"]),
        float(best["arg.q3_lower"]),
        float(best["worst_conditioning"]),
        float(SPEC_HALF_ANGLE),
        SPEC_R_MIN,
        float(closed),
        rd.worst_conditioning(mech),
    )


def monte_carlo_drift(name: str, samples: int = 400, seed: int = 7) -> tuple[float, float]:
    """(first-order RMS |c|, nonlinear Monte Carlo RMS |c|) [m] at the ``mid`` pose."""
    mech = load(name)
    q = mech.configurations["mid"]
    names, sens = rd.drift_sensitivities(mech, q)
    sig = rd.sigmas()
    linear = float(np.sqrt(np.sum(sig**2 * np.sum(sens**2, axis=1))))
    joints = [n.split()[0] for n in names[::6]]
    model = mech.model.copy()
    data = model.createData()
    ids = [model.getJointId(j) for j in joints]
    nominal = [model.jointPlacements[i].copy() for i in ids]
    rng = np.random.default_rng(seed)
    qp = mech.to_pin(q)
    drift = np.empty(samples)
    for k in range(samples):
        delta = rng.normal(0.0, sig).reshape(-1, 6)
        for i, m0, d in zip(ids, nominal, delta, strict=True):
            model.jointPlacements[i] = m0 * pin.exp6(d)
        drift[k] = np.linalg.norm(outputs(model, data, qp)[6:9])
    return linear, float(np.sqrt(np.mean(drift**2)))


def tolerance_table(name: str, top: int = 6) -> list[tuple[str, float]]:
    """The ``top`` largest shares of E|c|² at the ``mid`` pose."""
    mech = load(name)
    return rd.drift_contributions(mech, mech.configurations["mid"])[:top]


__all__ = [
    "RIG_STUDY",
    "TOLERANCE_VARIANTS",
    "RigAnswer",
    "monte_carlo_drift",
    "rig_answer",
    "tolerance_table",
]
