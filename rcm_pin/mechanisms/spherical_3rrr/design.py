"""Design metrics of the spherical 3-RRR: the regular share of orientation space, conditioning.

For any link angles and base axes (not only the Agile Eye), over ``SAMPLES`` seeded rotations
uniform on SO(3) (scipy's ``Rotation.random``, Haar measure):

* ``regular_share`` [-]: the share of orientations that working mode ``+++`` reaches with
  both singularity measures of :func:`.maps.measures` (type 1: min |B_ii|/(sin θ_i1 sin θ_i2);
  type 2: σ_min/σ_max of A's normalised rows) at least ``MARGIN``: the part of SO(3) the
  mode works in away from its singular sets;
* ``mean_conditioning`` [-]: the mean type-2 measure (κ⁻¹ of A) over those orientations.

Both are Monte Carlo estimates with a standard error of at most 0.5/√SAMPLES ≈ 0.008; tests
check the regular/singular verdict at sampled orientations against Pinocchio's A and B.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from rcm_pin.interfaces.design import DesignMetric
from rcm_pin.mechanisms.spherical_3rrr import geometry, maps
from rcm_pin.model.mechanism import Mechanism

#: Smallest measure of a regular orientation.
MARGIN = 0.05
#: Seeded orientations of the estimate.
SAMPLES = 4000
#: Working mode of the metrics (``+++``).
MODE = 0


def sample_rotations(n: int = SAMPLES, seed: int = 0) -> np.ndarray:
    """n rotation matrices (n, 3, 3), uniform on SO(3), seeded."""
    return np.asarray(Rotation.random(n, random_state=seed).as_matrix())


def regular_mask(mech: Mechanism, rotations: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(regular (N,) bool, type-2 measure (N,)) of working mode ``+++`` at the rotations."""
    type1, type2 = maps.measures(geometry(mech), rotations, MODE)
    with np.errstate(invalid="ignore"):
        ok = (type1 >= MARGIN) & (type2 >= MARGIN)
    return ok, type2


def regular_share(mech: Mechanism) -> float:
    """Share of SO(3) regular in working mode ``+++`` (module docstring)."""
    ok, _ = regular_mask(mech, sample_rotations())
    return float(ok.mean())


def mean_conditioning(mech: Mechanism) -> float:
    """Mean κ⁻¹ of A over the regular orientations (0 when there is none)."""
    ok, type2 = regular_mask(mech, sample_rotations())
    return float(type2[ok].mean()) if ok.any() else 0.0


METRICS: dict[str, DesignMetric] = {
    m.name: m
    for m in (
        DesignMetric(
            "regular_share",
            "-",
            "max",
            "share of SO(3) that mode +++ reaches with both singularity measures >= 0.05",
            regular_share,
        ),
        DesignMetric(
            "mean_conditioning",
            "-",
            "max",
            "mean inverse condition number of A over those orientations",
            mean_conditioning,
        ),
    )
}

__all__ = ["MARGIN", "METRICS", "mean_conditioning", "regular_mask", "regular_share"]
