"""Paper 002's printed numbers beside rcm-pin's computations (rows of the eye section).

Published values are typed in from G. N. Chusovitin, N. A. Chusovitin (paper 002, see the
report's sources) with the equation or sentence they come from; every computed value comes
from :mod:`rcm_pin.mechanisms.eye_4dof.design` and :mod:`rcm_pin.linkage`. Tolerances are
half a unit of the last printed digit.
"""

from __future__ import annotations

import math

from rcm_pin.linkage.fourbar import FourBar, performance
from rcm_pin.mechanisms.eye_4dof import design as dz
from rcm_pin.studies.comparison import Comparison

MM, DEG = 1e3, 180.0 / math.pi


def pitch_rows(d: dz.EyeDesign = dz.PAPER) -> list[Comparison]:
    """Equations (1)–(8), the built l0, l1, their swing and the Grashof check."""
    e = dz.pitch_equations(d)
    built = performance(FourBar(d.frame_built, d.crank_built, d.coupler, d.rocker))
    assert built.up is not None and built.down is not None  # the built linkage turns
    printed8 = dz.positive_root(0.89, 7.24, -3024.0)
    with_3024 = dz.positive_root(e.a, e.b * MM, -3024.0)
    g = built.linkage
    rows = [
        Comparison("O2 b = l3 sin φ in (1)", 21.13, e.projection_up * MM, "mm", "", 0.005),
        Comparison(
            "2 l3 sin φ in the step before (3)", 43.26, e.coefficient_up * MM, "mm",
            "misprint: 2 × 21.13 = 42.26, as (3) itself prints", 0.005,
        ),
        Comparison("2 l3 sin φ in (3)", 42.26, e.coefficient_up * MM, "mm", "", 0.005),
        Comparison("l3 sin γ in (4)", 28.68, e.projection_down * MM, "mm", "", 0.005),
        Comparison(
            "2 l3 sin γ in (6)", 57.35, e.coefficient_down * MM, "mm",
            "rounding: 2 × 28.679 = 57.358 is printed truncated", 0.005,
        ),
        Comparison(
            "constant l3² − l2² in (3), (6), (8)", -3024.0, e.constant * MM**2, "mm²",
            "arithmetic slip: 50² − 75² = 2500 − 5625 = −3125", 0.5,
        ),
        Comparison("k = l1 / l0 in (7)", 0.33, e.k, "", "", 0.005),
        Comparison("1 − k² in (8)", 0.89, e.a, "", "", 0.005),
        Comparison(
            "l3 (sin γ − sin φ) in (8)", 7.24, e.b * MM, "mm",
            "k rounded to 0.33 before substituting: 150 × 0.33 − 42.26 = 7.24", 0.005,
        ),
        Comparison(
            "root of (8) as printed", 54.19, printed8, "mm",
            "the published l0 is not the root of the printed (8) either", 0.005,
        ),
        Comparison(
            "root with the slip −3024 but unrounded k", 54.19, with_3024, "mm",
            "closest reconstruction of the published l0 (the slip −3024 kept)", 0.005,
        ),
        Comparison(
            "frame l0 (positive root of the correct (8))", 54.19, e.frame * MM, "mm",
            "the published l0 carries the constant's slip (−3024 for −3125)", 0.005,
        ),
        Comparison(
            "crank l1 = k l0", 17.88, e.crank * MM, "mm",
            "published l1 = 0.33 × 54.19: rounded k times the slipped l0", 0.005,
        ),
        Comparison(
            "gaze up φ reached by the built l0, l1", 25.0, built.up * DEG, "deg",
            "the built l0, l1 carry the constant's slip and the rounded k", 0.5,
        ),
        Comparison(
            "gaze down γ reached by the built l0, l1", 35.0, built.down * DEG, "deg",
            "the built l0, l1 carry the constant's slip and the rounded k", 0.5,
        ),
        Comparison(
            "printed 'Grashof' margin (l2 + l3) − (l1 + l0), built", None,
            (g.l2 + g.l3 - g.l1 - g.l0) * MM, "mm",
            "the printed l1 + l0 ≤ l2 + l3 is not Grashof's inequality (s + l ≤ p + q)",
        ),
        Comparison(
            "Grashof margin (p + q) − (s + l) = (l0 + l3) − (l1 + l2), built", None,
            g.grashof_margin * MM, "mm", "the correct test: holds, a crank–rocker",
        ),
    ]  # fmt: skip
    return rows


def yaw_rows(d: dz.EyeDesign = dz.PAPER) -> list[Comparison]:
    """The yaw crank, the support spacing, the slot length (formula and sweep)."""
    dp, md = dz.slot_parts(d)
    lo, hi, sweep = dz.slot_sweep(d)
    printed_t = dz.slot_formula(d, 0.36, 1.73)
    t_exact = dz.slot_formula(d, 0.0, math.sqrt(3.0))
    return [
        Comparison("yaw crank l10 = l4 sin α (α = 50°)", 26.8, d.l10 * MM, "mm", "", 0.05),
        Comparison(
            "l10 for the anthropometric α = 60°", None,
            d.l4 * math.sin(d.yaw_target) * MM, "mm",
            "the built ±50° drive cannot give the ±60° the conclusion claims",
        ),
        Comparison(
            "support spacing CL ≥ 2 l10 + 2B + L tan α", 100.0, dz.support_spacing(d) * MM, "mm",
            "the paper rounds the bound up to the built spacing (≈ 100 mm)", 0.5,
        ),
        Comparison(
            "CL bound for α = 60°", None, dz.support_spacing(d, d.yaw_target) * MM, "mm",
            "the spacing the anthropometric range would need",
        ),
        Comparison(
            "l00 (motor 2 offset; not printed)", None, d.offset * MM, "mm",
            "derived: the only value for which the printed T formula gives the printed 157 mm",
        ),
        Comparison("DP = l00 + l10 − l4 (9)", None, dp * MM, "mm", "with the derived l00"),
        Comparison("MD* (10) at φ + γ = 60°", None, md * MM, "mm", "with the derived l00"),
        Comparison(
            "coefficient of l4 in T = DP + MD*", 0.36, 0.0, "",
            "l4 cancels in (9) + (10); 0.36 = 1 − cos 50° comes from DP_min = l00 + l10 − "
            "l4 cos α, which the text itself rejects", 0.005,
        ),
        Comparison(
            "coefficient of l44 in T: sin(φ+γ) / cos(φ+γ)", 1.73, math.tan(d.up + d.down), "",
            "", 0.005,
        ),
        Comparison(
            "slot T by the printed formula", 157.0, printed_t * MM, "mm",
            "equal by construction: l00 is derived from it", 0.5,
        ),
        Comparison(
            "slot T = DP + MD* (corrected formula)", 157.0, t_exact * MM, "mm",
            "the printed formula's spurious 0.36 l4 (= 12.6 mm)", 0.5,
        ),
        Comparison(
            "slot T swept over pitch × crank turn (max s − min s)", 157.0, sweep * MM, "mm",
            f"the sweep's extremes are the corners of (9), (10): s in [{lo * MM:.2f}, "
            f"{hi * MM:.2f}] mm; the printed 157 mm includes the spurious 0.36 l4", 0.5,
        ),
    ]  # fmt: skip


def lid_rows(d: dz.EyeDesign = dz.PAPER) -> list[Comparison]:
    """The eyelid belt drive and its clearance condition."""
    lid = dz.lid_drive(d)
    return [
        Comparison("lid speed ω = V / l", 0.23, lid.omega_lid, "1/s", "", 0.005),
        Comparison("driven pulley d2 = u12 d1", None, lid.d2 * MM, "mm", "not printed"),
        Comparison("motor 3 speed ω1 = u12 ω", None, lid.omega_motor, "rad/s", "not printed"),
        Comparison(
            "motor 3 speed n1 = 30 ω1 / π", None, lid.motor_rpm, "1/min",
            "the printed u12 = π n1 / 0.23 drops the 1/30 of ω = π n / 30",
        ),
        Comparison(
            "clearance bound d1 + d2 / 2 (≤ l44 = 80 mm)", None, lid.clearance_bound * MM, "mm",
            f"holds, margin {(d.l44 - lid.clearance_bound) * MM:.2f} mm",
        ),
    ]  # fmt: skip


__all__ = ["lid_rows", "pitch_rows", "yaw_rows"]
