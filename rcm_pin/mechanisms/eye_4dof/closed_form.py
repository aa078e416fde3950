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

from rcm_pin.geometry import circle_offsets
from rcm_pin.linkage.fourbar import FourBar, coupler_angle, rocker_angle, rocker_point
from rcm_pin.rotations import rot_x, rot_y, rot_z, wrap_angle

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
    theta_a = float(coupler_angle(g.pitch, t1, psi))
    e = psi - math.pi / 2
    p_e = rot_y(-e) @ np.array([-g.l4 * math.cos(alpha), -g.l4 * math.sin(alpha), -g.l44])
    p_k = rot_y(-g.up) @ np.array(
        [-(g.l00 + g.l10 * math.cos(t2)), -g.l10 * math.sin(t2), -(g.l44 + g.h)]
    )
    basis = np.column_stack(
        [(rot_y(-e) @ [-1.0, 0, 0])[[0, 2]], (rot_y(-g.up) @ [0, 0, 1.0])[[0, 2]]]
    )
    s, u = np.linalg.solve(basis, (p_k - p_e)[[0, 2]])
    theta_a, psi = (float(wrap_angle(x)) for x in (theta_a, psi))
    return {
        "O1": t1, "A": theta_a, "O2": psi, "C": alpha, "D": -alpha,
        "E": float(s), "F": e - g.up, "U": float(u), "L": alpha, "roll": roll,
        "O3": t2, "lid": lid,
    }  # fmt: skip


def gaze_angles(rot: np.ndarray) -> tuple[float, float, float]:
    """(elevation e, azimuth α, roll ρ) [rad] of a frame R = Ry(−e) Rz(α) Rx(ρ)."""
    d = rot[:, 0]
    alpha = math.asin(max(-1.0, min(1.0, float(d[1]))))
    e = math.atan2(float(d[2]), float(d[0]))
    m = rot_z(-alpha) @ rot_y(e) @ rot
    return e, alpha, math.atan2(float(m[2, 1]), float(m[2, 2]))


def camera_rotation(g: EyeGeometry, drives: np.ndarray) -> np.ndarray | None:
    """Eye 2's camera frame Ry(−e) Rz(α) Rx(ρ) (None when the loops cannot close)."""
    j = joint_values(g, drives)
    if j is None:
        return None
    return rot_y(-(j["O2"] - math.pi / 2)) @ rot_z(j["L"]) @ rot_x(j["roll"])


def pitch_cranks(g: EyeGeometry, elevation: float) -> list[float]:
    """Crank angles θ1 of both working modes for a gaze elevation: A on the circles
    (O1, l1) and (B, l2), left of O1 → B first, θ1 = ∠B ± atan2(h, a) (not wrapped, so
    each mode's θ1 is continuous in the elevation; :mod:`rcm_pin.geometry`)."""
    b = rocker_point(g.pitch, elevation + math.pi / 2)
    along, across = (float(x) for x in circle_offsets(np.hypot(*b), g.crank, g.coupler))
    if not math.isfinite(along):
        return []
    base, delta = math.atan2(b[1], b[0]), math.atan2(across, along)
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
    "yaw_angle",
    "yaw_cranks",
]
