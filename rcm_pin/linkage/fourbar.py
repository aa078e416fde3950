"""The planar four-bar O1–A–B–O2 in closed form: positions, Grashof class, performance.

Frame and angles (the same as every four-bar model in rcm-pin)::

    O1 = (0, 0), O2 = (l0, 0)                 frame line O1 → O2 (x axis)
    A  = l1 (cos θ, sin θ)                    crank tip, θ the crank angle
    B  = O2 + l3 (cos ψ, sin ψ)               rocker tip, ψ the rocker angle
    |B − A| = l2                              the loop equation

θ and ψ are absolute, counter-clockwise from the frame line. B is taken above the frame line
(y > 0, the *upper circuit*: B left of the line A → O2); the mirror image is the other
circuit. The rocker is *straight* at ψ = π/2 (perpendicular to O1O2); its swing *up* is
measured from straight towards O1 and *down* away from O1:

    ψ = π/2 + up  (B leans towards O1),     ψ = π/2 − down (B leans away from O1).

Dead centres of a crank–rocker (the rocker's extreme positions): crank and coupler aligned,
folded (A–O1–B, |O1 B| = l2 − l1, ψ = ψ_max) or extended (O1–A–B, |O1 B| = l2 + l1,
ψ = ψ_min). Transmission angle μ ∈ [0, π]: the angle at B between B→A and B→O2,

    cos μ = (l2² + l3² − l0² − l1² + 2 l0 l1 cos θ) / (2 l2 l3),

monotone in cos θ: its extremes over a crank turn are at θ = 0 and θ = π. Time ratio: the
crank arcs between the dead centres, the slower stroke over the faster at constant crank
speed (≥ 1). Grashof: s + l ≤ p + q (s, l the shortest and longest of l0..l3).

The one Grashof rule of rcm-pin (the four-bar family and the eye linkage use it): the
boundary s + l = p + q (to :data:`GRASHOF_TOL` relative) is the *change-point* class, a
class of its own: the links fold flat there (all four collinear, a type-2 pose on the
crank's turn), so no tie is a crank–rocker, e.g. (l0, l1, l2, l3) = (3, 1, 2, 2) with the
crank strictly the shortest, or a parallelogram. A *crank–rocker* is strictly Grashof
(s + l < p + q) with the crank strictly the shortest link (a crank tied with the frame is
a double-crank, tied with the coupler or the rocker no crank–rocker).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from rcm_pin.errors import InvalidInputError
from rcm_pin.geometry import circle_intersections, circle_points
from rcm_pin.rotations import wrap_angle

#: Grashof classes by the shortest link (s + l < p + q), then the boundary and the rest.
GRASHOF_CLASSES = {
    1: "crank-rocker",  # the crank is the shortest: it turns fully, the rocker swings
    0: "double-crank",  # the frame is the shortest: both side links turn fully
    2: "double-rocker",  # the coupler is the shortest: the coupler turns fully
    3: "rocker-crank",  # the rocker is the shortest: the output turns fully
}
CHANGE_POINT = "change-point"  # s + l = p + q: the links can fold flat
NON_GRASHOF = "non-Grashof triple-rocker"  # s + l > p + q: no link turns fully
#: Relative tolerance of the Grashof equality s + l = p + q (round-off of the lengths), and
#: of |cos μ| ≤ 1 in :func:`transmission_angle`.
GRASHOF_TOL = 1e-12


class DeadCentre(NamedTuple):
    """A dead centre: crank angle θ [rad] in [−π, π) and rocker angle ψ [rad]."""

    crank: float
    rocker: float


@dataclass(frozen=True)
class FourBar:
    """Link lengths [m]: frame l0 = |O1 O2|, crank l1 = |O1 A|, coupler l2 = |A B|,
    rocker l3 = |O2 B|."""

    l0: float
    l1: float
    l2: float
    l3: float

    def __post_init__(self) -> None:
        lengths = (self.l0, self.l1, self.l2, self.l3)
        if not all(math.isfinite(v) and v > 0.0 for v in lengths):
            raise InvalidInputError(
                f"four-bar lengths (frame, crank, coupler, rocker) = {lengths} [m]; valid: "
                "finite lengths > 0"
            )

    @property
    def lengths(self) -> tuple[float, float, float, float]:
        """(l0, l1, l2, l3) [m]."""
        return (self.l0, self.l1, self.l2, self.l3)

    @property
    def assemblable(self) -> bool:
        """The loop closes somewhere: the longest link is shorter than the other three."""
        s = sorted(self.lengths)
        return s[3] < s[0] + s[1] + s[2]

    @property
    def grashof_margin(self) -> float:
        """(p + q) − (s + l) [m]: ≥ 0 for a Grashof linkage."""
        s = sorted(self.lengths)
        return (s[1] + s[2]) - (s[0] + s[3])

    @property
    def grashof(self) -> bool:
        """s + l ≤ p + q (to :data:`GRASHOF_TOL` relative)."""
        return self.grashof_margin >= -GRASHOF_TOL * max(self.lengths)

    @property
    def grashof_class(self) -> str:
        """``crank-rocker``, ``double-crank``, ``double-rocker``, ``rocker-crank``,
        ``change-point`` or ``non-Grashof triple-rocker`` (:data:`GRASHOF_CLASSES`)."""
        if abs(self.grashof_margin) <= GRASHOF_TOL * max(self.lengths):
            return CHANGE_POINT
        if not self.grashof:
            return NON_GRASHOF
        shortest = min(range(4), key=lambda i: self.lengths[i])
        return GRASHOF_CLASSES[shortest]

    @property
    def crank_rocker(self) -> bool:
        """Strictly Grashof with the crank strictly the shortest link (module docstring:
        a change-point linkage is not a crank–rocker)."""
        return self.grashof_class == GRASHOF_CLASSES[1] and self.l1 < min(self.l0, self.l2, self.l3)


def crank_point(g: FourBar, theta: ArrayLike) -> np.ndarray:
    """A(θ) (…, 2) [m]."""
    t = np.asarray(theta, dtype=float)
    return g.l1 * np.stack([np.cos(t), np.sin(t)], axis=-1)


def rocker_point(g: FourBar, psi: ArrayLike) -> np.ndarray:
    """B(ψ) (…, 2) [m]."""
    t = np.asarray(psi, dtype=float)
    return np.stack([g.l0 + g.l3 * np.cos(t), g.l3 * np.sin(t)], axis=-1)


def rocker_angle(g: FourBar, theta: np.ndarray) -> np.ndarray:
    """ψ(θ) [rad] on the upper circuit (B left of A → O2); NaN where the loop does not close.

    B is on the circles (A, l2) and (O2, l3), the intersection left of A → O2
    (:func:`rcm_pin.geometry.circle_intersections`).
    """
    b = circle_intersections(crank_point(g, theta), g.l2, (g.l0, 0.0), g.l3)[..., 0, :]
    return np.arctan2(b[..., 1], b[..., 0] - g.l0)


def rocker_angles(g: FourBar, theta: float) -> list[float]:
    """ψ [rad] of every assembly mode at crank angle θ (0, 1 or 2), the upper circuit
    (B left of the line A → O2) first."""
    a = crank_point(g, theta)
    return [float(np.arctan2(b[1], b[0] - g.l0)) for b in circle_points(a, g.l2, (g.l0, 0.0), g.l3)]


def crank_angles(g: FourBar, psi: float) -> list[float]:
    """θ [rad] of every working mode at rocker angle ψ (0, 1 or 2): A on the circles
    (O1, l1) and (B, l2), left of the line O1 → B first."""
    b = rocker_point(g, psi)
    return [float(np.arctan2(a[1], a[0])) for a in circle_points((0.0, 0.0), g.l1, b, g.l2)]


def coupler_angle(g: FourBar, theta: ArrayLike, psi: ArrayLike) -> np.ndarray:
    """The coupler's angle relative to the crank, ∠(B − A) − θ [rad] (not wrapped)."""
    u = rocker_point(g, psi) - crank_point(g, theta)
    return np.arctan2(u[..., 1], u[..., 0]) - np.asarray(theta, dtype=float)


def transmission_angle(g: FourBar, theta: np.ndarray) -> np.ndarray:
    """μ(θ) [rad] in [0, π] (module docstring); NaN where the loop does not close, i.e.
    |cos μ| > 1 + :data:`GRASHOF_TOL` (within it: round-off at a type-2 pose, μ = 0 or π)."""
    c = (g.l2**2 + g.l3**2 - g.l0**2 - g.l1**2 + 2.0 * g.l0 * g.l1 * np.cos(theta)) / (
        2.0 * g.l2 * g.l3
    )
    return np.where(np.abs(c) <= 1.0 + GRASHOF_TOL, np.arccos(np.clip(c, -1.0, 1.0)), np.nan)


def transmission_range(g: FourBar) -> tuple[float, float]:
    """(μ_min, μ_max) [rad] over the crank angles where the loop closes: μ grows as cos θ
    falls, so μ_min = μ(0) and μ_max = μ(π), each clipped to [0, π] where the crank stops
    short of θ = 0 or π (there μ reaches 0 or π, a type-2 pose)."""
    k = g.l2**2 + g.l3**2 - g.l0**2 - g.l1**2
    c0 = (k + 2.0 * g.l0 * g.l1) / (2.0 * g.l2 * g.l3)
    c1 = (k - 2.0 * g.l0 * g.l1) / (2.0 * g.l2 * g.l3)
    return math.acos(max(-1.0, min(1.0, c0))), math.acos(max(-1.0, min(1.0, c1)))


def crank_band_below(g: FourBar, mu: float) -> float | None:
    """θ* [rad] in [0, π] with μ(θ) < mu exactly for |θ| < θ* (μ grows with |θ|):
    cos θ* = (2 l2 l3 cos mu − (l2² + l3² − l0² − l1²)) / (2 l0 l1); None when μ ≥ mu over
    the whole turn (θ* = 0), π when μ < mu everywhere."""
    k = g.l2**2 + g.l3**2 - g.l0**2 - g.l1**2
    c = (2.0 * g.l2 * g.l3 * math.cos(mu) - k) / (2.0 * g.l0 * g.l1)
    if c >= 1.0:
        return None
    return math.pi if c <= -1.0 else math.acos(c)


def dead_centres(g: FourBar) -> tuple[DeadCentre, DeadCentre]:
    """(folded, extended) dead centres of a crank–rocker on the upper circuit.

    Folded: |O1 B| = l2 − l1 with A = −l1 B / |B| (θ = ∠B + π), ψ = ψ_max; extended:
    |O1 B| = l2 + l1 with A = l1 B / |B| (θ = ∠B), ψ = ψ_min.

    Raises:
        InvalidInputError: not a crank–rocker (the crank stops before a full turn).
    """
    if not g.crank_rocker:
        raise InvalidInputError(
            f"links {g.lengths} [m] are a {g.grashof_class} linkage, not a crank-rocker; "
            "valid: Grashof (s + l < p + q) with the crank strictly the shortest link"
        )
    out = []
    for sign in (-1.0, 1.0):
        b = circle_intersections((0.0, 0.0), g.l2 + sign * g.l1, (g.l0, 0.0), g.l3)[0]
        theta = math.atan2(b[1], b[0]) + (math.pi if sign < 0 else 0.0)
        out.append(DeadCentre(float(wrap_angle(theta)), math.atan2(b[1], b[0] - g.l0)))
    return out[0], out[1]


@dataclass(frozen=True)
class Performance:
    """What a crank–rocker does over a full crank turn (angles [rad]).

    Attributes:
        linkage: the link lengths.
        grashof_class: :attr:`FourBar.grashof_class`.
        crank_rocker: the crank turns fully and the rocker swings.
        transmission_angle: (μ_min, μ_max) over the crank's range.
        up, down: the swing reached, from straight (ψ = π/2), towards / away from the
            side named by ``up_towards_o1`` (None unless a crank–rocker).
        rocker_range: (ψ_min, ψ_max) on the upper circuit (None unless a crank–rocker).
        folded, extended: the dead centres (None unless a crank–rocker).
        stroke: crank arc [rad] in (0, 2π) turned counter-clockwise from the extended to the
            folded dead centre (ψ_min → ψ_max); the other stroke is 2π − stroke.
        time_ratio: max / min of the two strokes (≥ 1; None unless a crank–rocker).
        up_towards_o1: True when *up* leans B towards O1 (ψ = π/2 + up).
    """

    linkage: FourBar
    grashof_class: str
    crank_rocker: bool
    transmission_angle: tuple[float, float]
    up: float | None
    down: float | None
    rocker_range: tuple[float, float] | None
    folded: DeadCentre | None
    extended: DeadCentre | None
    stroke: float | None
    time_ratio: float | None
    up_towards_o1: bool = True


def performance(g: FourBar, up_towards_o1: bool = True) -> Performance:
    """The Grashof class, transmission-angle range, dead centres, swing and time ratio.

    Args:
        g: the linkage.
        up_towards_o1: whether *up* leans the rocker towards O1 (the default, ψ = π/2 + up);
            False for a layout with O1 on the *down* side (ψ = π/2 − up).
    """
    mu = transmission_range(g)
    if not g.crank_rocker:
        return Performance(
            g, g.grashof_class, False, mu, None, None, None, None, None, None, None, up_towards_o1
        )
    folded, extended = dead_centres(g)
    lo, hi = extended.rocker, folded.rocker
    towards, away = hi - math.pi / 2, math.pi / 2 - lo
    up, down = (towards, away) if up_towards_o1 else (away, towards)
    stroke = (folded.crank - extended.crank) % (2.0 * math.pi)
    ratio = max(stroke, 2.0 * math.pi - stroke) / min(stroke, 2.0 * math.pi - stroke)
    return Performance(
        g, g.grashof_class, True, mu, up, down, (lo, hi), folded, extended, stroke, ratio,
        up_towards_o1,
    )  # fmt: skip


__all__ = [
    "CHANGE_POINT",
    "GRASHOF_CLASSES",
    "NON_GRASHOF",
    "DeadCentre",
    "FourBar",
    "Performance",
    "coupler_angle",
    "crank_angles",
    "crank_band_below",
    "crank_point",
    "dead_centres",
    "performance",
    "rocker_angle",
    "rocker_angles",
    "rocker_point",
    "transmission_angle",
    "transmission_range",
]
