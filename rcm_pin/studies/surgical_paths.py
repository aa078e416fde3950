"""Surgical tool-tip paths inside a cone below a trocar, at a surgeon's speeds.

The *cone* has its apex at the trocar p_T, its axis along the insertion direction d
(unit), a half-angle θ and an insertion-depth range [ρ_lo, ρ_hi], the depth being the
length of shaft inside, ρ = |p − p_T|. Paths are written in the cone frame (u, w, d),
z the coordinate along d (z_m: the middle of the depth range), and follow a minimum-jerk phase
s(τ) = 10τ³ − 15τ⁴ + 6τ⁵ (τ = t / T) so that they start and end at rest (no stair steps
from the reference itself):

* ``circle``: radius r = 15 mm about the axis at the mid depth z_m, one turn, depth
  oscillating ±10 mm (z = z_m + 0.01 sin φ); T = 4 s (peak tip speed about 45 mm/s);
* ``spiral``: two turns with the radius growing 0 → 20 mm while the depth goes
  z_m − 15 mm → z_m + 15 mm; T = 6 s;
* ``arc``: a suturing-like arc, the half-circle of radius 12 mm in the plane (u, d)
  centred on the axis at z_m, driven from one end to the other; T = 3 s.

The default cone (θ = 30°, depths 0.05–0.12 m) lies inside the rcm_bevel rig's 60° /
0.05–0.12 m workspace, so the same paths suit both kinds of manipulator.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rcm_pin.errors import InvalidInputError

PATHS = ("circle", "spiral", "arc")
#: Default duration of each path [s].
DURATIONS = {"circle": 4.0, "spiral": 6.0, "arc": 3.0}
#: Most control steps of a path (rate × duration): time and memory, see surgical_path.
MAX_STEPS = 100_000


@dataclass(frozen=True)
class Cone:
    """The cone below the trocar (module docstring).

    Attributes:
        apex: p_T (3,) [m].
        direction: d (3,), unit insertion direction.
        half_angle: θ [rad].
        depth: (ρ_lo, ρ_hi) [m], insertion depths |p − p_T|.
    """

    apex: tuple[float, float, float]
    direction: tuple[float, float, float]
    half_angle: float = np.deg2rad(30.0)
    depth: tuple[float, float] = (0.05, 0.12)

    def frame(self) -> np.ndarray:
        """(3, 3) columns u, w, d (right-handed, u from the world axis least along d)."""
        d = np.asarray(self.direction, dtype=float)
        d = d / np.linalg.norm(d)
        helper = np.eye(3)[int(np.argmin(np.abs(d)))]
        u = np.cross(helper, d)
        u /= np.linalg.norm(u)
        return np.column_stack([u, np.cross(d, u), d])

    def to_world(self, local: np.ndarray) -> np.ndarray:
        """Cone-frame points (..., 3) -> world [m]."""
        return np.asarray(self.apex) + np.asarray(local) @ self.frame().T

    def to_local(self, p: np.ndarray) -> np.ndarray:
        """World points (..., 3) -> cone frame (u, w, depth) [m]."""
        return (np.asarray(p, dtype=float) - np.asarray(self.apex)) @ self.frame()

    def check(self, p: np.ndarray) -> None:
        """Every point of ``p`` (N, 3) inside the cone.

        Raises:
            InvalidInputError: the first point outside, with its angle and depth.
        """
        loc = self.to_local(np.atleast_2d(p))
        depth = np.linalg.norm(loc, axis=1)
        angle = np.arctan2(np.hypot(loc[:, 0], loc[:, 1]), loc[:, 2])
        lo, hi = self.depth
        bad = np.flatnonzero((angle > self.half_angle + 1e-12) | (depth < lo) | (depth > hi))
        if bad.size:
            i = int(bad[0])
            raise InvalidInputError(
                f"path point {i} lies outside the cone below the trocar (angle "
                f"{np.rad2deg(angle[i]):.1f} deg, depth {depth[i]:.4f} m); valid: within "
                f"{np.rad2deg(self.half_angle):.1f} deg of the insertion axis at depths in "
                f"[{lo:g}, {hi:g}] m"
            )


@dataclass(frozen=True)
class SurgicalPath:
    """Tip samples of a path.

    Attributes:
        name: circle, spiral or arc.
        t: (N + 1,) times [s].
        p: (N + 1, 3) tip positions, world [m].
        cone: the cone the path lies in.
    """

    name: str
    t: np.ndarray
    p: np.ndarray
    cone: Cone

    @property
    def peak_speed(self) -> float:
        """Largest finite-difference tip speed [m/s]."""
        return float(np.max(np.linalg.norm(np.diff(self.p, axis=0), axis=1) / np.diff(self.t)))


def min_jerk(tau: np.ndarray) -> np.ndarray:
    """s(τ) = 10τ³ − 15τ⁴ + 6τ⁵ on [0, 1]."""
    return np.asarray(tau**3 * (10.0 - 15.0 * tau + 6.0 * tau**2), dtype=float)


def local_path(name: str, s: np.ndarray, z_mid: float) -> np.ndarray:
    """Cone-frame points (u, w, z) [m] of path ``name`` at phases ``s`` in [0, 1]."""
    if name == "circle":
        phi = 2.0 * np.pi * s
        return np.column_stack(
            [0.015 * np.cos(phi), 0.015 * np.sin(phi), z_mid + 0.01 * np.sin(phi)]
        )
    if name == "spiral":
        phi, rho = 4.0 * np.pi * s, 0.02 * s
        return np.column_stack([rho * np.cos(phi), rho * np.sin(phi), z_mid - 0.015 + 0.03 * s])
    if name == "arc":
        phi = np.pi * s
        return np.column_stack(
            [-0.012 * np.cos(phi), np.zeros_like(s), z_mid + 0.012 * np.sin(phi)]
        )
    raise InvalidInputError(f"unknown path {name!r}; valid: {', '.join(PATHS)}")


def surgical_path(
    name: str, cone: Cone, *, rate: float = 1000.0, duration: float | None = None
) -> SurgicalPath:
    """Path ``name`` in ``cone`` sampled at ``rate`` [Hz] (module docstring).

    ``duration`` shorter than the path's own time stops the path early (same speeds).

    Raises:
        InvalidInputError: unknown path, a rate or duration that is not positive, more
            than :data:`MAX_STEPS` steps, or a path that leaves the cone.
    """
    if name not in PATHS:
        raise InvalidInputError(f"unknown path {name!r}; valid: {', '.join(PATHS)}")
    if not (np.isfinite(rate) and 1.0 <= rate <= 1e5):
        raise InvalidInputError(f"rate must lie in [1, 100000] Hz; got {rate!r}")
    total = DURATIONS[name]
    T = total if duration is None else float(duration)
    if not (np.isfinite(T) and 0.0 < T <= total):
        raise InvalidInputError(
            f"duration must lie in (0, {total:g}] s for {name}; got {duration!r}"
        )
    n = max(1, round(T * rate))
    if n > MAX_STEPS:
        raise InvalidInputError(
            f"rate {rate:g} Hz over {T:g} s is {n} control steps; valid: at most {MAX_STEPS} "
            "(measured on panda: about 0.5 ms and 4 kB per step with its JSON output, so "
            f"{MAX_STEPS} steps take about a minute and 400 MB); lower the rate or the duration"
        )
    t = np.arange(n + 1) / rate
    z_mid = 0.5 * (cone.depth[0] + cone.depth[1])
    p = cone.to_world(local_path(name, min_jerk(t / total), z_mid))
    cone.check(p)
    return SurgicalPath(name, t, p, cone)


__all__ = [
    "DURATIONS",
    "MAX_STEPS",
    "PATHS",
    "Cone",
    "SurgicalPath",
    "local_path",
    "min_jerk",
    "surgical_path",
]
