"""The planar four-bar O1–A–B–O2 (crank–rocker), paper 002's pitch drive: the family.

Geometry (``xacro/four_bar.urdf.xacro``)::

    O1 = (0, 0), O2 = (l0, 0)                         frame line O1 → O2
    A  = l1 (cos q1, sin q1)                          crank, driven (joint O1)
    B  = O2 + l3 (cos ψ, sin ψ)                       rocker, the output (joint O2)
    F(q1, ψ) = |B − A|² − l2² = 0                     the loop equation

Angles are absolute, measured counter-clockwise from the frame line; the coupler joint A
is relative (θ_A = ∠(B − A) − q1). Direct problem: B on the circles (A, l2) and (O2, l3),
two assembly modes; inverse problem: A on the circles (O1, l1) and (B, l2), two working
modes labelled by the side of A with respect to the line O1 → B (``+``: left).

Angeles–Gosselin form A ψ̇ = −B q̇1 with u = B − A::

    A = ∂F/∂ψ = 2 u·l3 (−sin ψ, cos ψ),   B = ∂F/∂q1 = −2 u·l1 (−sin q1, cos q1)

type 2 (A = 0): coupler and rocker aligned (transmission angle 0 or π); type 1 (B = 0):
crank and coupler aligned (the rocker's extreme positions).

Positions, transmission angle μ, the Grashof class and the dead centres are
:mod:`rcm_pin.linkage.fourbar`'s (one Grashof rule: a change-point linkage, s + l = p + q,
is not a crank–rocker); this module adapts them to the family's model.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rcm_pin.analysis.capabilities import Assemblies, Branches, NumericPosition
from rcm_pin.analysis.singularity_model import ABMatrices, NumericSingularity
from rcm_pin.analysis.workspace import NumericWorkspace
from rcm_pin.errors import UnreachablePoseError
from rcm_pin.interfaces.design import DesignMetric, MetricSource
from rcm_pin.linkage.fourbar import (
    FourBar,
    coupler_angle,
    crank_angles,
    crank_point,
    dead_centres,
    performance,
    rocker_angles,
    rocker_point,
    transmission_angle,
)
from rcm_pin.model.family import Branch, Family
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output
from rcm_pin.rotations import wrap_angle

#: Working-mode labels of the inverse problem.
MODES = ("+", "-")

#: The geometry of the family: the linkage layer's four-bar (l0 frame, l1 crank, l2
#: coupler, l3 rocker [m]; ``grashof``, ``grashof_class``, ``crank_rocker``).
GeometryFourBar = FourBar
#: Rocker angles ψ of every assembly mode at a crank angle, B left of A → O2 first.
direct_position = rocker_angles
#: Crank angles of the working modes ``+``, ``-`` at a rocker angle (A left of O1 → B first).
inverse_position = crank_angles


def full_q(g: FourBar, q1: float, psi: float) -> np.ndarray:
    """Pinocchio configuration (O1, A, O2) [rad] for crank q1 and rocker ψ."""
    return wrap_angle(np.array([q1, coupler_angle(g, q1, psi), psi]))


def ab_matrices(g: FourBar, q1: float, psi: float) -> tuple[np.ndarray, np.ndarray]:
    """A = ∂F/∂ψ and B = ∂F/∂q1 (1 × 1) of the loop equation [m²/rad]."""
    u = rocker_point(g, psi) - crank_point(g, q1)
    dA = 2.0 * u @ (g.l3 * np.array([-np.sin(psi), np.cos(psi)]))
    dB = -2.0 * u @ (g.l1 * np.array([-np.sin(q1), np.cos(q1)]))
    return np.array([[dA]]), np.array([[dB]])


def rocker_range(g: FourBar) -> tuple[float, float]:
    """Smallest and largest rocker angle ψ [rad] of a crank–rocker, exactly: the extended
    and the folded dead centre (:func:`rcm_pin.linkage.fourbar.dead_centres`; the
    intersection above the frame line, the assembly mode of ``home``).

    Raises:
        InvalidInputError: not a crank–rocker (the crank does not turn fully).
    """
    folded, extended = dead_centres(g)
    return extended.rocker, folded.rocker


def geometry(mech: Mechanism) -> FourBar:
    """The closed-form geometry of a loaded four-bar (from its sidecar parameters)."""
    p = mech.require_loops().params
    return FourBar(float(p["frame"]), float(p["crank"]), float(p["coupler"]), float(p["rocker"]))


class FourBarPosition(NumericPosition):
    """Closed-form position problems of the family (the numeric route where none applies)."""

    def inverse(self, mech: Mechanism, target: np.ndarray, output: Output) -> Branches:
        """Crank angles of both working modes for a rocker angle."""
        if output.coords != ("rz",):
            return super().inverse(mech, target, output)
        g, psi = geometry(mech), float(target[0])
        cranks = inverse_position(g, psi)
        if not cranks:
            valid = "a rocker angle the coupler reaches"
            if g.crank_rocker:
                lo, hi = rocker_range(g)
                valid = f"rocker angles in [{lo:.6g}, {hi:.6g}] rad"
            raise UnreachablePoseError(
                f"{mech.name}: rocker angle {psi:.6g} rad is outside the rocker's range "
                f"(the crank circle and the coupler circle about B do not meet); valid: {valid}"
            )
        return Branches.of(
            mech, [Branch(full_q(g, c, psi), MODES[i]) for i, c in enumerate(cranks)]
        )

    def direct(self, mech: Mechanism, drives: np.ndarray) -> Assemblies:
        """Both assembly modes (B above the line A → O2 first)."""
        g = geometry(mech)
        return Assemblies.of(
            [full_q(g, float(drives[0]), psi) for psi in direct_position(g, float(drives[0]))]
        )

    def mode_labels(self, mech: Mechanism) -> tuple[str, ...]:
        """``+``, ``-``."""
        return MODES


class FourBarWorkspace(NumericWorkspace):
    """The rocker's range and swing, the Grashof class, the transmission-angle range (no
    options); the sampled figure."""

    options = ()

    def summary(
        self, mech: Mechanism, samples: int | None, seed: int, **options: Any
    ) -> dict[str, Any]:
        g = geometry(mech)
        lo, hi = rocker_range(g)
        mu = transmission_angle(g, np.linspace(-np.pi, np.pi, 3601))
        return {
            "rocker_min": lo,
            "rocker_max": hi,
            "swing": hi - lo,
            "grashof": g.grashof,
            "crank_rocker": g.crank_rocker,
            "transmission_angle_min": float(mu.min()),
            "transmission_angle_max": float(mu.max()),
        }


class FourBarMetrics(MetricSource):
    """Swing, worst transmission angle and time ratio over a crank turn (NaN unless a
    crank–rocker), by :func:`rcm_pin.linkage.fourbar.performance`."""

    def metrics(self) -> dict[str, DesignMetric]:
        def perf(mech: Mechanism) -> Any:
            return performance(geometry(mech))

        def swing(mech: Mechanism) -> float:
            r = perf(mech).rocker_range
            return float(np.rad2deg(r[1] - r[0])) if r else float("nan")

        def worst_mu(mech: Mechanism) -> float:
            p = perf(mech)
            lo, hi = p.transmission_angle
            return float(np.rad2deg(min(lo, np.pi - hi))) if p.crank_rocker else float("nan")

        def ratio(mech: Mechanism) -> float:
            r = perf(mech).time_ratio
            return float("nan") if r is None else float(r)

        return {
            m.name: m
            for m in (
                DesignMetric("swing", "deg", "max", "rocker swing ψ_max − ψ_min", swing),
                DesignMetric(
                    "worst_transmission", "deg", "max", "min(μ_min, 180° − μ_max)", worst_mu
                ),
                DesignMetric("time_ratio", "-", "min", "slower / faster stroke", ratio),
            )
        }


class FourBarSingularity(NumericSingularity):
    """A/B of the loop equation (no named causes, the numeric map)."""

    def ab_matrices(self, mech: Mechanism, q: np.ndarray) -> ABMatrices:
        """A / (2 l2 l3) and B / (2 l1 l2) (dimensionless)."""
        g, loops = geometry(mech), mech.require_loops()
        psi = float(mech.output_value(q)[0])
        a_mat, b_mat = ab_matrices(g, float(q[loops.drive_q[0]]), psi)
        return ABMatrices(a_mat / (2.0 * g.l2 * g.l3), b_mat / (2.0 * g.l1 * g.l2), paper=True)


class FourBarFamily(Family):
    """Hooks of the four-bar: both assembly and working modes, A/B, the rocker's swing."""

    name = "four_bar"
    description = "planar four-bar linkages (paper 002)"
    closed = True
    capabilities = (
        FourBarPosition(),
        FourBarWorkspace(),
        FourBarMetrics(),
        FourBarSingularity(),
    )

    def configurations(self, mech: Mechanism) -> dict[str, np.ndarray]:
        """``home``: crank along the frame line (q1 = 0), rocker above it."""
        g = geometry(mech)
        psi = max(direct_position(g, 0.0))
        return {"home": full_q(g, 0.0, psi)}


FAMILY = FourBarFamily()

__all__ = [
    "FAMILY",
    "MODES",
    "FourBarFamily",
    "GeometryFourBar",
    "ab_matrices",
    "direct_position",
    "full_q",
    "geometry",
    "inverse_position",
    "rocker_range",
    "transmission_angle",
]
