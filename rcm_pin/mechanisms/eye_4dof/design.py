"""Paper 002's design chains, computed from the dimensions it gives (SI units).

Pitch (motor 1): the crank–rocker four-bar from its two dead centres
(:mod:`rcm_pin.linkage.synthesis`; up φ towards O1, down γ away from it, from the rocker
perpendicular to O1O2). With d = l0 the printed equations (3), (6) read

    (3)  l0² − l1² + 2 l2 l1 − 2 l3 sin φ · l0 + (l3² − l2²) = 0
    (6)  l0² − l1² − 2 l2 l1 + 2 l3 sin γ · l0 + (l3² − l2²) = 0,

(6) − (3) gives (7) l1 = k l0, k = l3 (sin φ + sin γ) / (2 l2), and (8) is
(1 − k²) l0² + l3 (sin γ − sin φ) l0 + (l3² − l2²) = 0.

Yaw (motor 2): the crank l10 about O3 moves link 5 sideways through the slider 7 in its slot,
the equal rockers l4 (CD, LP) with link 5 a parallelogram: l4 sin α = l10 sin θ2, so the
largest yaw needs l10 = l4 sin α_max. Supports: CL ≥ 2 l10 + 2B + L tan α_max.

Slot of link 5: the paper's dimension chains (9), (10) are horizontal projections in the
pitch plane, with the cradle turned by β from the *up* position (β ∈ [0, φ + γ]) and the
crank's horizontal component l10 cos θ2; the slider's coordinate s along the slot from D is

    l44 sin β + l4 cos α cos β + s cos β = l00 + l10 cos θ2,

so DP = s(0, 0) = l00 + l10 − l4 (9) and MD* = −s(φ + γ, π) (10); the slot must cover
[min s, max s] over the whole motion (:func:`slot_sweep`).

Eyelid (motor 3): ω = V / l, u12 = d2 / d1 = ω1 / ω2, clearance l44 ≥ d1 + d2 / 2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rcm_pin.linkage.synthesis import quadratic, synthesize


@dataclass(frozen=True)
class EyeDesign:
    """The dimensions paper 002 gives [m, rad, m/s] (and the one it does not, l00).

    Attributes:
        up, down: gaze up φ and down γ from straight (the pitch rocker's swing).
        yaw_built: the built yaw drive's ±α (50°); yaw_target: the anthropometric α (60°).
        coupler, rocker: l2, l3 of the pitch four-bar.
        frame_built, crank_built: l0, l1 as published and built.
        l4: the yaw rockers CD, LP; l44: the arm from O2 to the plane of link 5 (H).
        bar_thickness, bar_width: the support bar B × L.
        lid_speed, lid_arm: eyelid speed V and its radius l about O2.
        d1, u12: the lid belt's driving pulley and ratio d2 / d1.
        slot_printed: the printed slot length T ≈ 157 mm (used only to derive l00).
        l00: motor 2's offset from the support axis (not printed; :func:`implied_l00`).
    """

    up: float = math.radians(25.0)
    down: float = math.radians(35.0)
    yaw_built: float = math.radians(50.0)
    yaw_target: float = math.radians(60.0)
    coupler: float = 0.075
    rocker: float = 0.050
    frame_built: float = 0.05419
    crank_built: float = 0.01788
    l4: float = 0.035
    l44: float = 0.080
    bar_thickness: float = 0.010
    bar_width: float = 0.020
    lid_speed: float = 0.015
    lid_arm: float = 0.065
    d1: float = 0.047
    u12: float = 1.37
    slot_printed: float = 0.157
    l00: float | None = None

    @property
    def l10(self) -> float:
        """Crank of the yaw drive for ±yaw_built: l10 = l4 sin α [m]."""
        return self.l4 * math.sin(self.yaw_built)

    @property
    def offset(self) -> float:
        """l00 [m]: the given one, else :func:`implied_l00`."""
        return implied_l00(self) if self.l00 is None else self.l00


#: The paper's design (l00 derived).
PAPER = EyeDesign()


@dataclass(frozen=True)
class PitchEquations:
    """The pitch synthesis of the paper's equations, exactly (lengths [m], areas [m²])."""

    projection_up: float  # O2 b = l3 sin φ (printed 21.13 mm)
    projection_down: float  # l3 sin γ (printed 28.68 mm)
    coefficient_up: float  # 2 l3 sin φ in (3) (printed 42.26, and 43.26 before it)
    coefficient_down: float  # 2 l3 sin γ in (6) (printed 57.35)
    constant: float  # l3² − l2² in (3), (6), (8) (printed −3024 mm²)
    k: float  # l1 / l0 of (7) (printed 0.33)
    a: float  # (8): 1 − k² (printed 0.89)
    b: float  # (8): l3 (sin γ − sin φ) (printed 7.24)
    frame: float  # the positive root of (8)
    crank: float  # k × frame


def pitch_equations(d: EyeDesign = PAPER) -> PitchEquations:
    """Every coefficient of (1)–(8) and the paper's root (O1 on the up side)."""
    k, a, b, c = quadratic(d.up, d.down, d.coupler, d.rocker)
    root = next(r for r in synthesize(d.up, d.down, d.coupler, d.rocker) if r.d > 0)
    s_up, s_down = d.rocker * math.sin(d.up), d.rocker * math.sin(d.down)
    return PitchEquations(s_up, s_down, 2 * s_up, 2 * s_down, c, k, a, b, root.frame, root.crank)


def positive_root(a: float, b: float, c: float) -> float:
    """The positive root of a x² + b x + c = 0 with a > 0 > c (the printed (8))."""
    return (-b + math.sqrt(b * b - 4.0 * a * c)) / (2.0 * a)


def support_spacing(d: EyeDesign = PAPER, yaw: float | None = None) -> float:
    """CL_min = 2 l10 + 2B + L tan α [m] for the yaw range α (default the built one), with
    l10 = l4 sin α."""
    alpha = d.yaw_built if yaw is None else yaw
    return 2 * d.l4 * math.sin(alpha) + 2 * d.bar_thickness + d.bar_width * math.tan(alpha)


def slot_formula(d: EyeDesign, l4_coefficient: float, l44_coefficient: float) -> float:
    """T = 3 l10 − l00 + c44 l44 + c4 l4 [m], the printed form with given coefficients."""
    return 3 * d.l10 - d.offset + l44_coefficient * d.l44 + l4_coefficient * d.l4


def implied_l00(d: EyeDesign) -> float:
    """l00 [m] from the printed T ≈ 157 mm and the printed coefficients 1.73, 0.36:
    l00 = 3 l10 + 1.73 l44 + 0.36 l4 − T (the only place the paper's numbers fix it)."""
    return 3 * d.l10 + 1.73 * d.l44 + 0.36 * d.l4 - d.slot_printed


def slot_coordinate(d: EyeDesign, beta: np.ndarray, theta2: np.ndarray) -> np.ndarray:
    """s(β, θ2) [m] (module docstring); cos α = √(1 − (l10 sin θ2 / l4)²)."""
    cos_alpha = np.sqrt(1.0 - (d.l10 * np.sin(theta2) / d.l4) ** 2)
    num = d.offset + d.l10 * np.cos(theta2) - d.l44 * np.sin(beta) - d.l4 * cos_alpha * np.cos(beta)
    return num / np.cos(beta)


def slot_parts(d: EyeDesign = PAPER) -> tuple[float, float]:
    """(DP, MD*) [m] of (9), (10) at φ + γ."""
    total = d.up + d.down
    dp = d.offset + d.l10 - d.l4
    md = (d.l44 * math.sin(total) + d.l4 * math.cos(total) - d.offset + d.l10) / math.cos(total)
    return dp, md


def slot_sweep(d: EyeDesign = PAPER, n: int = 721) -> tuple[float, float, float]:
    """(min s, max s, T = max − min) [m] over β ∈ [0, φ + γ] × θ2 ∈ [0, 2π) (grid n × n,
    both corners of (9), (10) on it)."""
    beta = np.linspace(0.0, d.up + d.down, n)[:, None]
    theta2 = np.linspace(0.0, 2 * math.pi, 2 * (n // 2) + 1)[None, :]
    s = slot_coordinate(d, beta, theta2)
    return float(s.min()), float(s.max()), float(s.max() - s.min())


@dataclass(frozen=True)
class LidDrive:
    """The eyelid belt drive (SI)."""

    omega_lid: float  # ω = V / l [rad/s]
    d2: float  # driven pulley d2 = u12 d1 [m]
    omega_motor: float  # ω1 = u12 ω [rad/s]
    motor_rpm: float  # n1 = 30 ω1 / π [1/min]
    clearance_bound: float  # d1 + d2 / 2 [m] (l44 must not be smaller)


def lid_drive(d: EyeDesign = PAPER) -> LidDrive:
    """ω, d2, the motor speed and the clearance bound of the lid drive."""
    omega = d.lid_speed / d.lid_arm
    d2 = d.u12 * d.d1
    omega1 = d.u12 * omega
    return LidDrive(omega, d2, omega1, 30.0 * omega1 / math.pi, d.d1 + d2 / 2)


__all__ = [
    "PAPER",
    "EyeDesign",
    "LidDrive",
    "PitchEquations",
    "implied_l00",
    "lid_drive",
    "pitch_equations",
    "positive_root",
    "slot_coordinate",
    "slot_formula",
    "slot_parts",
    "slot_sweep",
    "support_spacing",
]
