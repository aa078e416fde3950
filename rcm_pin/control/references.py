"""References for the computed-torque law: x_T(t), ẋ_T(t), ẍ_T(t) in task coordinates.

A :class:`Reference` is anything with ``evaluate(t) -> (x, ẋ, ẍ)`` (arrays of the task
dimension) and an optional ``start`` (the task value where a simulation starts by
default). Shipped references:

* :class:`CartesianTrajectory`: x(t) = centre + amplitude ⊙ sin(ω t + phase) per axis
  (paper 000's example and a rig circle, :data:`TRAJECTORIES`);
* :class:`CircleWithAngle`: a planar circle of a point with an angle oscillation
  (paper 004's platform tracking);
* :class:`QuinticPath`: a point-to-point quintic with a rest at the end (the five-bar
  path across its type-2 curve).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from rcm_pin.errors import InvalidInputError


class Reference(Protocol):
    """x_T(t), ẋ_T(t), ẍ_T(t) in task coordinates."""

    @property
    def start(self) -> tuple[float, ...] | None:
        """Default initial task position (None: on the reference at t = 0)."""
        ...

    def evaluate(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(x, ẋ, ẍ) at time t [s]."""
        ...


@dataclass(frozen=True)
class CartesianTrajectory:
    """p(t) = centre + amplitude ⊙ sin(ω t + phase), per axis.

    Attributes:
        name: registry name.
        centre: (n,) task coordinates (3 for a tool-centre point) [m | rad].
        amplitude: (n,) [m | rad].
        omega: angular frequency ω [rad/s].
        phase: (n,) [rad].
        start: default initial task position (n,) (None: on the trajectory).
    """

    name: str
    centre: tuple[float, ...]
    amplitude: tuple[float, ...]
    omega: float
    phase: tuple[float, ...] = (0.0, 0.0, 0.0)
    start: tuple[float, ...] | None = None

    def _arg(self, t: np.ndarray | float) -> np.ndarray:
        return self.omega * np.asarray(t, dtype=float)[..., None] + np.asarray(self.phase)

    def position(self, t: np.ndarray | float) -> np.ndarray:
        """p(t) (..., 3) [m]."""
        return np.asarray(self.centre) + np.asarray(self.amplitude) * np.sin(self._arg(t))

    def velocity(self, t: np.ndarray | float) -> np.ndarray:
        """ṗ(t) (..., 3) [m/s]."""
        return np.asarray(self.amplitude) * self.omega * np.cos(self._arg(t))

    def acceleration(self, t: np.ndarray | float) -> np.ndarray:
        """p̈(t) (..., 3) [m/s²]."""
        return -np.asarray(self.amplitude) * self.omega**2 * np.sin(self._arg(t))

    def evaluate(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(p, ṗ, p̈) at time t."""
        return self.position(t), self.velocity(t), self.acceleration(t)


@dataclass(frozen=True)
class CircleWithAngle:
    """A point on a circle of ``radius`` about ``centre`` with an angle φ0 + a·sin(ωt).

    One lap and one angle oscillation per ``period``; task (x [m], y [m], φ [rad]).
    """

    centre: tuple[float, float] = (0.02, 0.01)  # [m]
    radius: float = 0.03  # [m]
    phi0: float = 0.0  # [rad]
    phi_amp: float = 0.1  # [rad]
    period: float = 1.0  # [s]
    start: tuple[float, ...] | None = None

    def evaluate(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """p_T, ṗ_T, p̈_T at time t."""
        w = 2.0 * np.pi / self.period
        c, s = np.cos(w * t), np.sin(w * t)
        r, a = self.radius, self.phi_amp
        p = np.array([self.centre[0] + r * c, self.centre[1] + r * s, self.phi0 + a * s])
        return (
            p,
            np.array([-r * w * s, r * w * c, a * w * c]),
            -(w**2) * (p - [*self.centre, self.phi0]),
        )


@dataclass(frozen=True)
class QuinticPath:
    """Quintic point-to-point motion p0 → p1 in ``duration``, then at rest at p1."""

    p0: tuple[float, ...]
    p1: tuple[float, ...]
    duration: float
    start: tuple[float, ...] | None = None

    def evaluate(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """x_T, ẋ_T, ẍ_T at time t."""
        p0, p1 = np.array(self.p0), np.array(self.p1)
        u = min(max(t / self.duration, 0.0), 1.0)
        h = 10 * u**3 - 15 * u**4 + 6 * u**5
        moving = 0 < t < self.duration
        hd = (30 * u**2 - 60 * u**3 + 30 * u**4) / self.duration if moving else 0.0
        hdd = (60 * u - 180 * u**2 + 120 * u**3) / self.duration**2 if moving else 0.0
        return p0 + h * (p1 - p0), hd * (p1 - p0), hdd * (p1 - p0)


#: Shipped trajectories. ``paper000``: x = 0.1 + 0.01 sin ωt, y = 0.1 + 0.01 cos ωt,
#: z = 0.1 + 0.01 sin ωt, ω = 10 rad/s, start (0.11, 0.12, 0.15) m (paper 000, Fig. 4);
#: ``rig_circle``: a 20 mm circle at z = 0.09 m inside the rig's workspace, 1 Hz.
TRAJECTORIES: dict[str, CartesianTrajectory] = {
    "paper000": CartesianTrajectory(
        "paper000",
        (0.1, 0.1, 0.1),
        (0.01, 0.01, 0.01),
        10.0,
        (0.0, np.pi / 2, 0.0),
        start=(0.11, 0.12, 0.15),
    ),
    "rig_circle": CartesianTrajectory(
        "rig_circle",
        (0.0, 0.0, 0.09),
        (0.02, 0.02, 0.0),
        2 * np.pi,
        (0.0, np.pi / 2, 0.0),
        start=(0.0, 0.0, 0.08),
    ),
}


def get_trajectory(name: str) -> CartesianTrajectory:
    """A shipped trajectory by name.

    Raises:
        InvalidInputError: unknown name (lists the valid ones).
    """
    try:
        return TRAJECTORIES[name]
    except KeyError:
        raise InvalidInputError(
            f"unknown trajectory {name!r}; valid: {', '.join(TRAJECTORIES)}"
        ) from None


__all__ = [
    "TRAJECTORIES",
    "CartesianTrajectory",
    "CircleWithAngle",
    "QuinticPath",
    "Reference",
    "get_trajectory",
]
