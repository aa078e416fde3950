"""Paper 004's dynamic singularity criterion: the first natural frequency near a type-2 set.

For each of the three parallel mechanisms a straight output path x(s) = x* + s (x₀ − x*)
(for the spherical mechanism R(s) = R* exp(s θ₀ [n]×)) ends on a singular pose x* of the
working mode; x* is refined on the path by Brent's method on det J_c,p (the passive
columns of Pinocchio's world closure Jacobian, a signed function along the path: it
vanishes where the locked drives leave an output motion). The distance to the set is the
path length d = s |x₀ − x*| [m] (spherical: s θ₀ [rad]). At d = d₀ and d₀·{1e-1, 1e-2,
1e-3} the study computes ω₁ (:func:`rcm_pin.dynamics.vibrations.natural_frequencies`,
all drive stiffnesses c) and σ_min(Ã) (the dimensionless type-2 measure of
:func:`rcm_pin.analysis.loop_velocity.velocity_matrices`); the drop ratio is ω₁(d₀)/ω₁(d)
and the law is the log–log slope of ω₁ against d (and against σ_min(Ã)).

Why ω₁ ∝ d: near x* the tangent basis S = [I; −J_c,p⁻¹ J_c,a] grows as 1/d along the
singular direction, M_q = SᵀMS as 1/d², hence ω₁ = √(c/μ) ∝ d ∝ σ_min.

The spherical 3-RRR is the Agile Eye: its type-2 poses all lie on the type-1 set (a
folded leg, v_i = ±u_i), so its path ends on a type 1+2 pose.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin
from scipy.optimize import brentq

import rcm_pin
from rcm_pin.analysis.loop_velocity import velocity_matrices
from rcm_pin.dynamics.constrained import world_closure
from rcm_pin.dynamics.vibrations import natural_frequencies
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.studies.working_mode import configuration_at

#: Fractions of the start distance d₀ at which the drop is measured.
FRACTIONS = (1.0, 1e-1, 1e-2, 1e-3)
#: Fractions of d₀ of the log–log curve (d, ω₁, σ_min(Ã)).
CURVE = np.logspace(0.0, -3.0, 19)


@dataclass(frozen=True)
class PathSetup:
    """A path of one mechanism towards its singular set (SI units; rotations as 3×3)."""

    name: str
    mode: str
    singular: np.ndarray  # x* guess (output coordinates) or R*
    start: np.ndarray  # x₀ or the rotation vector θ₀ n [rad]
    stiffness: float  # c of every drive [N·m/rad or N/m]

    def pose(self, s: float) -> np.ndarray:
        """Output target at path parameter s (0: the singular end, 1: the start)."""
        if self.singular.shape == (3, 3):
            return (self.singular @ pin.exp3(s * self.start)).reshape(9)
        return self.singular + s * (self.start - self.singular)

    @property
    def length(self) -> float:
        """|x₀ − x*| [m] or θ₀ [rad]."""
        if self.singular.shape == (3, 3):
            return float(np.linalg.norm(self.start))
        return float(np.linalg.norm(self.start - self.singular))


def setups() -> list[PathSetup]:
    """The three paths (x* from each family's singular-set routines)."""
    from rcm_pin.mechanisms.planar_3rrr import geometry as g_planar
    from rcm_pin.mechanisms.planar_3rrr import workspace as ws_planar
    from rcm_pin.mechanisms.spherical_3rrr import geometry as g_sph
    from rcm_pin.mechanisms.spherical_3rrr import maps as maps_sph

    planar = rcm_pin.load("planar_3rrr")
    x_p = ws_planar.type2_points(g_planar(planar), 0.0, 0, max_points=1)[0]
    sph = rcm_pin.load("spherical_3rrr")
    r_s = maps_sph.curve_rotations(g_sph(sph), 0, 1.0, np.array([0.4]))[0]
    return [
        PathSetup("planar_3rrr", "+++", np.asarray(x_p), np.array([0.02, 0.01, 0.0]), 1000.0),
        PathSetup("spherical_3rrr", "+++", r_s, np.array([0.15, 0.1, 0.05]), 200.0),
        PathSetup(
            "translational_3ppapa",
            "++/++/++",
            np.array([0.1, 0.12, 0.36]),
            np.array([0.1, 0.12, 0.15]),
            1e5,
        ),
    ]


def passive_det(mech: Mechanism, q: np.ndarray) -> float:
    """det J_c,p: Pinocchio's world closure Jacobian, passive columns."""
    _, jc, _ = world_closure(mech, q, np.zeros(mech.model.nv))
    return float(np.linalg.det(jc[:, mech.require_loops().passive_v]))


def _q(mech: Mechanism, p: PathSetup, s: float) -> np.ndarray:
    return configuration_at(mech, p.pose(s), p.mode)[0]


def singular_parameter(mech: Mechanism, p: PathSetup, lo: float = 1e-3) -> float:
    """s* where det J_c,p changes sign on the path (Brent, xtol 1e-15), searched in
    [−lo, 1]; 0 (the family's x* itself) when it does not change sign there (the Agile
    Eye's type 1+2 poses: the inverse problem has no solution beyond them)."""
    grid = np.r_[-lo, np.linspace(lo, 1.0, 40)]
    vals = []
    for s in grid:
        try:
            vals.append(passive_det(mech, _q(mech, p, float(s))))
        except rcm_pin.RcmPinError:
            vals.append(np.nan)
    vals_a = np.array(vals)
    for i in range(len(grid) - 1):
        if np.isfinite(vals_a[i]) and np.isfinite(vals_a[i + 1]) and vals_a[i] * vals_a[i + 1] < 0:
            return float(
                brentq(
                    lambda s: passive_det(mech, _q(mech, p, s)),
                    grid[i],
                    grid[i + 1],
                    xtol=1e-15,
                    rtol=1e-15,
                )
            )
    return 0.0


def approach(p: PathSetup) -> dict[str, Any]:
    """ω₁ and σ_min(Ã) at d₀·FRACTIONS on one path (``rows``), drop ratios, log–log slopes
    (fits over the three nearest rows), and the curve (d, ω₁, σ_min(Ã)) at d₀·CURVE."""
    mech = rcm_pin.load(p.name)
    s_star = singular_parameter(mech, p)
    d0 = (1.0 - s_star) * p.length
    rows = []
    for f in FRACTIONS:
        s = s_star + f * (1.0 - s_star)
        q = _q(mech, p, s)
        vib = natural_frequencies(mech, q, p.stiffness)
        rows.append(
            {
                "fraction": f,
                "distance": f * d0,
                "omega": vib.frequencies.tolist(),
                "omega1": float(vib.frequencies[0]),
                "sigma_min_A": float(velocity_matrices(mech, q).measure_type2),
            }
        )
    curve = []
    for f in CURVE:
        q = _q(mech, p, s_star + float(f) * (1.0 - s_star))
        w1 = float(natural_frequencies(mech, q, p.stiffness).frequencies[0])
        curve.append((float(f) * d0, w1, float(velocity_matrices(mech, q).measure_type2)))
    w = np.array([r["omega1"] for r in rows])
    d = np.array([r["distance"] for r in rows])
    sig = np.array([r["sigma_min_A"] for r in rows])
    return {
        "mechanism": p.name,
        "mode": p.mode,
        "stiffness": p.stiffness,
        "d0": d0,
        "s_star": s_star,
        "crossing": s_star != 0.0,
        "rows": rows,
        "drop": {str(f): float(w[0] / wi) for f, wi in zip(FRACTIONS[1:], w[1:], strict=True)},
        "slope_distance": float(np.polyfit(np.log(d[1:]), np.log(w[1:]), 1)[0]),
        "slope_sigma": float(np.polyfit(np.log(sig[1:]), np.log(w[1:]), 1)[0]),
        "omega1_over_sigma": (w / sig).tolist(),
        "curve": curve,
    }


def frequency_map(
    name: str,
    mode: str,
    pose: Callable[[float, float], np.ndarray],
    u: np.ndarray,
    v: np.ndarray,
    stiffness: float,
) -> np.ndarray:
    """ω₁ (len(v), len(u)) [rad/s] over a workspace section pose(u, v) of working mode
    ``mode``; NaN where the pose is unreachable or type-2 singular."""
    mech = rcm_pin.load(name)
    out = np.full((len(v), len(u)), np.nan)
    for j, vj in enumerate(v):
        for i, ui in enumerate(u):
            try:
                q = configuration_at(mech, pose(float(ui), float(vj)), mode)[0]
                out[j, i] = natural_frequencies(mech, q, stiffness).frequencies[0]
            except rcm_pin.RcmPinError:
                continue
    return out


def criterion() -> list[dict[str, Any]]:
    """:func:`approach` on the three paths."""
    return [approach(p) for p in setups()]


__all__ = [
    "FRACTIONS",
    "PathSetup",
    "approach",
    "criterion",
    "frequency_map",
    "passive_det",
    "setups",
]
