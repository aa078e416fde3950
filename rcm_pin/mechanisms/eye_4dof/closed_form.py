"""Closed forms of the eye linkage's sub-linkages (``xacro/eye_4dof.urdf.xacro``).

World: X forward, Y left (the pitch axis O2), Z up; drives θ1 (pitch crank O1), θ2 (yaw
crank O3), the lid angle λ and the camera roll ρ [rad]. Each sub-linkage in closed form:

    pitch four-bar:  ψ(θ1) on the upper circuit (:func:`rcm_pin.linkage.fourbar.rocker_angle`),
                     gaze elevation e = ψ − π/2, cradle R_c = Ry(−e)
    yaw yoke:        l4 sin α = l10 sin θ2 (link 5's sideways shift equals the crank pin's;
                     the pitch axis is parallel to it), principal α = asin((l10/l4) sin θ2)
    parallelogram:   both eyes turn by α (joints C = L = α, D = −α)
    Assur group:     F = e − φ (link 8 stays parallel to motor 2's axis Ry(−φ) z), and the
                     slot coordinate s (pair E, along −x) and u (pair U) from the 2 × 2
                     system in the X–Z plane  p_K − p_E = −s Ry(−e) x + u Ry(−φ) z
                     (determinant cos(e − φ))
    outputs:         eye i's gaze frame Ry(−e) Rz(α), eye 2's camera Ry(−e) Rz(α) Rx(ρ)

with p_E = Ry(−e) (−l4 cos α, −l4 sin α, −l44) and p_K = Ry(−φ) (−l00 − l10 cos θ2,
−l10 sin θ2, −(l44 + h)) (the rockers and motor 2 behind O2): projected on the up pose's −x
this is the paper's chain (9), (10): l44 sin β + (l4 cos α + s) cos β = l00 + l10 cos θ2,
β = φ − e. Gaze angles of a frame R (Helmholtz: elevation outside, azimuth inside): with
d = R x, α = asin d_y, e = atan2(d_z, d_x), ρ = atan2(M₂₁, M₂₂) of M = Rz(−α) Ry(e) R.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from rcm_pin.linkage.fourbar import FourBar, rocker_angle

#: Drive joints in input order.
DRIVES = ("O1", "O3", "lid", "roll")


@dataclass(frozen=True)
class EyeGeometry:
    """Dimensions [m, rad] of the model (the sidecar ``params``)."""

    frame: float
    crank: float
    coupler: float
    rocker: float
    l4: float
    l44: float
    l10: float
    eye_spacing: float
    l00: float
    h: float
    up: float

    @classmethod
    def from_params(cls, p: Mapping[str, float]) -> EyeGeometry:
        """From the sidecar ``params``."""
        return cls(**{k: float(p[k]) for k in cls.__dataclass_fields__})

    @property
    def pitch(self) -> FourBar:
        """The pitch four-bar."""
        return FourBar(self.frame, self.crank, self.coupler, self.rocker)


def ry(t: float) -> np.ndarray:
    """Rotation about Y."""
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rz(t: float) -> np.ndarray:
    """Rotation about Z."""
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rx(t: float) -> np.ndarray:
    """Rotation about X."""
    c, s = math.cos(t), math.sin(t)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def yaw_angle(g: EyeGeometry, theta2: float) -> float:
    """Principal α [rad] of the yoke; NaN when l10 |sin θ2| > l4."""
    ratio = g.l10 * math.sin(theta2) / g.l4
    return math.asin(ratio) if abs(ratio) <= 1.0 else math.nan


def joint_values(g: EyeGeometry, drives: np.ndarray) -> dict[str, float] | None:
    """Every tree joint for the drives (θ1, θ2, λ, ρ); None when a sub-linkage cannot close."""
    t1, t2, lid, roll = (float(v) for v in drives)
    psi = float(rocker_angle(g.pitch, np.array(t1)))
    alpha = yaw_angle(g, t2)
    if not (math.isfinite(psi) and math.isfinite(alpha)):
        return None
    a = g.crank * np.array([math.cos(t1), math.sin(t1)])
    b = np.array([g.frame + g.rocker * math.cos(psi), g.rocker * math.sin(psi)])
    theta_a = math.atan2(b[1] - a[1], b[0] - a[0]) - t1
    e = psi - math.pi / 2
    p_e = ry(-e) @ np.array([-g.l4 * math.cos(alpha), -g.l4 * math.sin(alpha), -g.l44])
    p_k = ry(-g.up) @ np.array(
        [-(g.l00 + g.l10 * math.cos(t2)), -g.l10 * math.sin(t2), -(g.l44 + g.h)]
    )
    basis = np.column_stack([(ry(-e) @ [-1.0, 0, 0])[[0, 2]], (ry(-g.up) @ [0, 0, 1.0])[[0, 2]]])
    s, u = np.linalg.solve(basis, (p_k - p_e)[[0, 2]])
    wrap = lambda x: (x + math.pi) % (2 * math.pi) - math.pi  # noqa: E731
    return {
        "O1": t1, "A": wrap(theta_a), "O2": wrap(psi), "C": alpha, "D": -alpha,
        "E": float(s), "F": e - g.up, "U": float(u), "L": alpha, "roll": roll,
        "O3": t2, "lid": lid,
    }  # fmt: skip


def gaze_angles(rot: np.ndarray) -> tuple[float, float, float]:
    """(elevation e, azimuth α, roll ρ) [rad] of a frame R = Ry(−e) Rz(α) Rx(ρ)."""
    d = rot[:, 0]
    alpha = math.asin(max(-1.0, min(1.0, float(d[1]))))
    e = math.atan2(float(d[2]), float(d[0]))
    m = rz(-alpha) @ ry(e) @ rot
    return e, alpha, math.atan2(float(m[2, 1]), float(m[2, 2]))


def camera_rotation(g: EyeGeometry, drives: np.ndarray) -> np.ndarray | None:
    """Eye 2's camera frame Ry(−e) Rz(α) Rx(ρ) (None when the loops cannot close)."""
    j = joint_values(g, drives)
    if j is None:
        return None
    return ry(-(j["O2"] - math.pi / 2)) @ rz(j["L"]) @ rx(j["roll"])


def pitch_cranks(g: EyeGeometry, elevation: float) -> list[float]:
    """Crank angles θ1 of both working modes for a gaze elevation (A on the circles
    (O1, l1) and (B, l2), left of O1 → B first)."""
    psi = elevation + math.pi / 2
    b = np.array([g.frame + g.rocker * math.cos(psi), g.rocker * math.sin(psi)])
    d = float(np.hypot(*b))
    r0, r1 = g.crank, g.coupler
    if d == 0.0 or d > r0 + r1 or d < abs(r0 - r1):
        return []
    x = (d * d + r0 * r0 - r1 * r1) / (2 * d)
    hh = math.sqrt(max(r0 * r0 - x * x, 0.0))
    base = math.atan2(b[1], b[0])
    delta = math.atan2(hh, x)
    return [base + delta, base - delta]


def yaw_cranks(g: EyeGeometry, azimuth: float) -> list[float]:
    """θ2 of both modes (crank pin ahead / behind) for an azimuth: sin θ2 = l4 sin α / l10."""
    ratio = g.l4 * math.sin(azimuth) / g.l10
    if abs(ratio) > 1.0:
        return []
    t = math.asin(ratio)
    return [t, math.pi - t]


__all__ = [
    "DRIVES",
    "EyeGeometry",
    "camera_rotation",
    "gaze_angles",
    "joint_values",
    "pitch_cranks",
    "rx",
    "ry",
    "rz",
    "yaw_angle",
    "yaw_cranks",
]
