"""Design metrics of the RCM mechanisms: rig coverage, conditioning, RCM drift.

Each metric is one number per design (a loaded Mechanism: its xacro arguments set the
joint limits and the link geometry), vectorised over poses, seeded, so a design gives the
same figure on every worker.

* ``cone_coverage`` [-]: fraction of the rig's specification region (a 60° cone about z
  with apex A between the spheres 0.05 m and 0.12 m, docs/conventions.md) the tool centre
  reaches within the joint limits (20 000 seeded uniform points of the region).
* ``cone_margin`` [deg]: θ_max − 60°, θ_max the largest cone about z inside the limits.
* ``worst_conditioning`` [-]: the smallest inverse condition number κ⁻¹ of the tool-centre
  Jacobian J = ∂p/∂(q1, q2, q3) over the joint box, with the angular columns divided by the
  characteristic length L = q3_upper (so every column is in metres). p = q3·e4(q1, q2) are
  spherical coordinates, the columns are orthogonal with lengths q3·cos q2, q3 and 1, so
  κ⁻¹ = (q3/L)·cos q2 / max(q3/L, 1) = (q3_lower/q3_upper)·cos(max |q2|) at the corner of
  the box; the metric takes the minimum over a 21³ grid of the box (corners included) by
  batched SVD, and tests compare it with that closed form and with Pinocchio's Jacobian.
* ``global_conditioning`` [-]: Gosselin and Angeles' global conditioning index, the mean of
  κ⁻¹ over the workspace weighted by its volume element q3²·cos q2 (Gauss–Legendre in
  q2, q3; tests compare it with the closed form (1/L)·(∫q3³/∫q3²)·(∫cos²q2/∫cos q2));
* ``rcm_drift`` [m]: RMS distance of the insertion line from A when every part placement
  on the chain to the tool (:data:`rcm_pin.mechanisms.rcm.PLACEMENT_JOINTS`) has independent
  normal errors σ_t = 0.05 mm per translation and σ_r = 0.05° per rotation, worst over the
  family's named configurations. To first order c = Σ_k S_k δ_k, so
  E|c|² = Σ_k σ_k² |S_k|² (S_k from :func:`.accuracy.placement_sensitivity`).
"""

from __future__ import annotations

import numpy as np

from rcm_pin.errors import InvalidInputError
from rcm_pin.interfaces.design import DesignMetric
from rcm_pin.mechanisms.rcm import PLACEMENT_JOINTS
from rcm_pin.mechanisms.rcm.accuracy import COMPONENTS, placement_sensitivity
from rcm_pin.mechanisms.rcm.workspace import SPEC_HALF_ANGLE, max_contained_cone, spec_check
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.rotations import FloatArray

#: Standard deviations of the placement errors of the drift metric.
SIGMA_TRANSLATION = 0.05e-3  # [m]
SIGMA_ROTATION = np.deg2rad(0.05)  # [rad]
#: Grid points per joint of the conditioning metric.
GRID = 21
#: Seeded points of the specification region of the coverage metric.
COVERAGE_SAMPLES = 20_000


def point_jacobians(q: FloatArray) -> FloatArray:
    """J = ∂p/∂(q1, q2, q3) of many poses: q (N, ≥3) -> (N, 3, 3) [m/rad, m/rad, -]."""
    q = np.asarray(q, dtype=float)
    s1, c1, s2, c2 = np.sin(q[:, 0]), np.cos(q[:, 0]), np.sin(q[:, 1]), np.cos(q[:, 1])
    e4 = np.stack([s2, -s1 * c2, c1 * c2], axis=-1)  # output axis (N, 3)
    d1 = np.stack([np.zeros_like(s1), -c1 * c2, -s1 * c2], axis=-1)  # ∂e4/∂q1
    d2 = np.stack([c2, s1 * s2, -c1 * s2], axis=-1)  # ∂e4/∂q2
    q3 = q[:, 2:3]
    return np.stack([q3 * d1, q3 * d2, e4], axis=-1)


def worst_conditioning(mech: Mechanism, n: int = GRID) -> float:
    """Smallest κ⁻¹ of the length-normalised tool-centre Jacobian over the joint box."""
    lo, hi = mech.lower[:3], mech.upper[:3]
    if hi[2] <= 0:
        raise InvalidInputError(
            f"{mech.name}: q3_upper = {hi[2]:g} m; valid: a positive insertion range"
        )
    axes = [np.linspace(lo[k], hi[k], n) for k in range(3)]
    q = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    jac = point_jacobians(q)
    jac[:, :, :2] /= hi[2]  # characteristic length L = q3_upper
    s = np.linalg.svd(jac, compute_uv=False)
    return float(np.min(s[:, -1] / s[:, 0]))


def cone_margin(mech: Mechanism) -> float:
    """θ_max − 60° [deg]; 0 when they agree within the bisection's 1e-9 rad."""
    gap = max_contained_cone(mech) - SPEC_HALF_ANGLE
    return 0.0 if abs(gap) < 1e-9 else float(np.rad2deg(gap))


def global_conditioning(mech: Mechanism, nodes: int = 16) -> float:
    """Global conditioning index (Gosselin–Angeles): the mean of κ⁻¹ over the workspace,
    weighted by its volume element |det J| = q3²·cos q2, by Gauss–Legendre quadrature in
    (q2, q3) (κ does not depend on q1)."""
    lo, hi = mech.lower[:3], mech.upper[:3]
    x, w = np.polynomial.legendre.leggauss(nodes)
    q2 = 0.5 * (hi[1] - lo[1]) * x + 0.5 * (hi[1] + lo[1])
    q3 = 0.5 * (hi[2] - lo[2]) * x + 0.5 * (hi[2] + lo[2])
    g2, g3 = np.meshgrid(q2, q3, indexing="ij")
    weight = np.outer(w, w) * g3**2 * np.abs(np.cos(g2))
    q = np.stack([np.zeros(g2.size), g2.ravel(), g3.ravel()], axis=-1)
    jac = point_jacobians(q)
    jac[:, :, :2] /= hi[2]  # characteristic length L = q3_upper
    s = np.linalg.svd(jac, compute_uv=False)
    inv_kappa = (s[:, -1] / s[:, 0]).reshape(g2.shape)
    return float(np.sum(weight * inv_kappa) / np.sum(weight))


def drift_sensitivities(mech: Mechanism, q: FloatArray) -> tuple[list[str], FloatArray]:
    """Names and ∂c/∂δ (K, 3) of every placement-error component at q (RCM offset c [m])."""
    names, rows = [], []
    for joint in PLACEMENT_JOINTS:
        for k, comp in enumerate(COMPONENTS):
            d, _ = placement_sensitivity(mech, q, joint, k)
            names.append(f"{joint} {comp}")
            rows.append(d[6:9])
    return names, np.array(rows)


def sigmas() -> FloatArray:
    """σ of each placement-error component, in the order of :func:`drift_sensitivities`."""
    per_joint = [SIGMA_TRANSLATION] * 3 + [SIGMA_ROTATION] * 3
    return np.array(per_joint * len(PLACEMENT_JOINTS))


def rcm_drift(mech: Mechanism) -> float:
    """Worst RMS |c| [m] over the named configurations (module docstring)."""
    sig = sigmas()
    worst = 0.0
    for q in mech.configurations.values():
        _, sens = drift_sensitivities(mech, q)
        worst = max(worst, float(np.sqrt(np.sum(sig**2 * np.sum(sens**2, axis=1)))))
    return worst


def drift_contributions(mech: Mechanism, q: FloatArray) -> list[tuple[str, float]]:
    """Share of each error component in E|c|² at q, largest first (they sum to 1)."""
    names, sens = drift_sensitivities(mech, q)
    var = sigmas() ** 2 * np.sum(sens**2, axis=1)
    order = np.argsort(-var)
    return [(names[i], float(var[i] / var.sum())) for i in order]


METRICS: dict[str, DesignMetric] = {
    m.name: m
    for m in (
        DesignMetric(
            "cone_coverage",
            "-",
            "max",
            "fraction of the rig's 60° cone (0.05..0.12 m) reached within the limits",
            lambda mech: spec_check(mech, n=COVERAGE_SAMPLES).fraction_reached,
        ),
        DesignMetric(
            "cone_margin",
            "deg",
            "max",
            "largest cone about z inside the limits minus the rig's 60°",
            lambda mech: cone_margin(mech),
        ),
        DesignMetric(
            "worst_conditioning",
            "-",
            "max",
            "smallest inverse condition number of the tool-centre Jacobian (L = q3_upper)",
            worst_conditioning,
        ),
        DesignMetric(
            "global_conditioning",
            "-",
            "max",
            "mean inverse condition number over the workspace (volume-weighted, L = q3_upper)",
            global_conditioning,
        ),
        DesignMetric(
            "rcm_drift",
            "m",
            "min",
            "RMS insertion-line offset from A under 0.05 mm / 0.05° placement errors",
            rcm_drift,
        ),
    )
}

__all__ = [
    "METRICS",
    "cone_margin",
    "drift_contributions",
    "drift_sensitivities",
    "global_conditioning",
    "point_jacobians",
    "rcm_drift",
    "sigmas",
    "worst_conditioning",
]
