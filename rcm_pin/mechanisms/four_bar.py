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

Angeles–Gosselin form A ψ̇ = −B q̇1 with u = B − A:
    A = ∂F/∂ψ = 2 u·l3 (−sin ψ, cos ψ),   B = ∂F/∂q1 = −2 u·l1 (−sin q1, cos q1);
type 2 (A = 0): coupler and rocker aligned (transmission angle 0 or π); type 1 (B = 0):
crank and coupler aligned (the rocker's extreme positions).

Transmission angle μ (between coupler and rocker at B):
    cos μ = (l2² + l3² − l0² − l1² + 2 l0 l1 cos q1) / (2 l2 l3).
Grashof: s + l ≤ p + q (s, l the shortest and longest link); a crank–rocker when, in
addition, the crank is the shortest link.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from rcm_pin.analysis.capabilities import Assemblies, Branches, NumericPosition
from rcm_pin.errors import UnreachablePoseError
from rcm_pin.model.family import Branch, Family
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output
from rcm_pin.rotations import wrap_angle

#: Working-mode labels of the inverse problem.
MODES = ("+", "-")


@dataclass(frozen=True)
class GeometryFourBar:
    """Link lengths [m]: frame l0, crank l1, coupler l2, rocker l3."""

    l0: float
    l1: float
    l2: float
    l3: float

    @classmethod
    def from_params(cls, p: Mapping[str, float]) -> GeometryFourBar:
        """From the sidecar ``params``."""
        return cls(float(p["frame"]), float(p["crank"]), float(p["coupler"]), float(p["rocker"]))

    @property
    def grashof(self) -> bool:
        """s + l ≤ p + q: some link turns fully."""
        links = sorted((self.l0, self.l1, self.l2, self.l3))
        return links[0] + links[3] <= links[1] + links[2]

    @property
    def crank_rocker(self) -> bool:
        """Grashof with the crank strictly the shortest link (it turns fully, the rocker
        swings); a tie (e.g. a parallelogram) is a change-point linkage, not a crank–rocker."""
        return self.grashof and self.l1 < min(self.l0, self.l2, self.l3)


def _circles(c0: np.ndarray, r0: float, c1: np.ndarray, r1: float) -> list[np.ndarray]:
    """Intersections of two circles, left of c0 → c1 first (0, 1 or 2 points)."""
    d_vec = c1 - c0
    d = float(np.hypot(*d_vec))
    if d == 0.0 or d > r0 + r1 or d < abs(r0 - r1):
        return []
    a = (d * d + r0 * r0 - r1 * r1) / (2.0 * d)
    h = np.sqrt(max(r0 * r0 - a * a, 0.0))
    e = d_vec / d
    mid, n = c0 + a * e, np.array([-e[1], e[0]])
    return [mid] if h == 0.0 else [mid + h * n, mid - h * n]


def full_q(g: GeometryFourBar, q1: float, psi: float) -> np.ndarray:
    """Pinocchio configuration (O1, A, O2) [rad] for crank q1 and rocker ψ."""
    a = g.l1 * np.array([np.cos(q1), np.sin(q1)])
    b = np.array([g.l0 + g.l3 * np.cos(psi), g.l3 * np.sin(psi)])
    theta_a = np.arctan2(b[1] - a[1], b[0] - a[0]) - q1
    return wrap_angle(np.array([q1, theta_a, psi]))


def direct_position(g: GeometryFourBar, q1: float) -> list[float]:
    """Rocker angles ψ of every assembly mode for crank angle q1 (0, 1 or 2), B left of
    the line A → O2 (above it) first."""
    a = g.l1 * np.array([np.cos(q1), np.sin(q1)])
    o2 = np.array([g.l0, 0.0])
    return [float(np.arctan2(b[1], b[0] - g.l0)) for b in _circles(a, g.l2, o2, g.l3)]


def inverse_position(g: GeometryFourBar, psi: float) -> list[float]:
    """Crank angles q1 of the working modes ``+``, ``-`` for rocker angle ψ."""
    b = np.array([g.l0 + g.l3 * np.cos(psi), g.l3 * np.sin(psi)])
    return [float(np.arctan2(a[1], a[0])) for a in _circles(np.zeros(2), g.l1, b, g.l2)]


def transmission_angle(g: GeometryFourBar, q1: np.ndarray) -> np.ndarray:
    """μ(q1) [rad] in [0, π] (module docstring)."""
    c = (g.l2**2 + g.l3**2 - g.l0**2 - g.l1**2 + 2.0 * g.l0 * g.l1 * np.cos(q1)) / (
        2.0 * g.l2 * g.l3
    )
    return np.arccos(np.clip(c, -1.0, 1.0))


def ab_matrices(g: GeometryFourBar, q1: float, psi: float) -> tuple[np.ndarray, np.ndarray]:
    """A = ∂F/∂ψ and B = ∂F/∂q1 (1 × 1) of the loop equation [m²/rad]."""
    a = g.l1 * np.array([np.cos(q1), np.sin(q1)])
    b = np.array([g.l0 + g.l3 * np.cos(psi), g.l3 * np.sin(psi)])
    u = b - a
    dA = 2.0 * u @ (g.l3 * np.array([-np.sin(psi), np.cos(psi)]))
    dB = -2.0 * u @ (g.l1 * np.array([-np.sin(q1), np.cos(q1)]))
    return np.array([[dA]]), np.array([[dB]])


def rocker_range(g: GeometryFourBar) -> tuple[float, float]:
    """Smallest and largest rocker angle ψ [rad] of a crank–rocker, exactly: at the dead
    centres the crank and the coupler are aligned, |O1 B| = l2 ∓ l1, so B is on the circles
    (O1, l2 ∓ l1) and (O2, l3) (the intersection above the frame line, the assembly mode of
    ``home``).

    Raises:
        InvalidInputError: the crank does not turn fully (not a crank–rocker).
    """
    if not g.crank_rocker:
        from rcm_pin.errors import InvalidInputError

        raise InvalidInputError(
            f"links {g.l0, g.l1, g.l2, g.l3} are not a crank-rocker (the crank does not turn "
            "fully); valid: Grashof with the crank strictly the shortest link"
        )
    o2 = np.array([g.l0, 0.0])
    angles = []
    for r in (g.l2 - g.l1, g.l2 + g.l1):
        b = max(_circles(np.zeros(2), r, o2, g.l3), key=lambda p: p[1])
        angles.append(float(np.arctan2(b[1], b[0] - g.l0)))
    return min(angles), max(angles)


def geometry(mech: Mechanism) -> GeometryFourBar:
    """The closed-form geometry of a loaded four-bar (from its sidecar parameters)."""
    return GeometryFourBar.from_params(mech.require_loops().params)


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


class FourBarFamily(Family):
    """Hooks of the four-bar: both assembly and working modes, A/B, the rocker's swing."""

    name = "four_bar"
    description = "planar four-bar linkages (paper 002)"
    closed = True
    workspace_options: tuple[str, ...] = ()
    capabilities = (FourBarPosition(),)

    def configurations(self, mech: Mechanism) -> dict[str, np.ndarray]:
        """``home``: crank along the frame line (q1 = 0), rocker above it."""
        g = geometry(mech)
        psi = max(direct_position(g, 0.0))
        return {"home": full_q(g, 0.0, psi)}

    def ab_matrices(self, mech: Mechanism, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """A / (2 l2 l3) and B / (2 l1 l2) (dimensionless)."""
        g, loops = geometry(mech), mech.require_loops()
        psi = float(mech.output_value(q)[0])
        a_mat, b_mat = ab_matrices(g, float(q[loops.drive_q[0]]), psi)
        return a_mat / (2.0 * g.l2 * g.l3), b_mat / (2.0 * g.l1 * g.l2)

    def design_metrics(self) -> dict[str, Any]:
        """Swing, worst transmission angle and time ratio over a crank turn (NaN unless a
        crank–rocker), by :func:`rcm_pin.linkage.fourbar.performance`."""
        from rcm_pin.linkage.fourbar import FourBar, performance
        from rcm_pin.model.metric import DesignMetric

        def perf(mech: Mechanism) -> Any:
            g = geometry(mech)
            return performance(FourBar(g.l0, g.l1, g.l2, g.l3))

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

    def workspace_summary(self, mech: Mechanism, **options: Any) -> dict[str, Any]:
        """The rocker's range and swing, the Grashof class, the transmission-angle range."""
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
