"""Report section: paper 000's velocity/acceleration example, both wrist conventions."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rcm_pin.analysis.velocity import (
    forward,
    inverse_acceleration,
    inverse_velocity,
    omega_from_angle_rates,
)
from rcm_pin.catalog import load
from rcm_pin.errors import SingularConfigurationError
from rcm_pin.mechanisms.rcm.closed_form import WristType
from rcm_pin.mechanisms.rcm.velocity import closed_form_jacobian, coupling_terms
from rcm_pin.report.framework import Comparison, Section, comparison_table

Q = np.array([0.0, 0.0, -0.1, 0.0, 0.0, 0.0])  # x = y = 0, z = -0.1 m
V = np.ones(3)  # [m/s]
A = 0.2 * np.ones(3)  # [m/s²]
OMEGA = 0.52 * np.ones(3)  # [rad/s], read from the paper (see text)
EPS = np.ones(3)  # [rad/s²]

PUBLISHED_QD = (10.0, -10.0, 1.0, 0.52, 10.52, -9.48)
PUBLISHED_QDD = (410.0, -210.0, -19.0, 9.132, -200.87, 400.33)
PUBLISHED_EPS16 = (-10.67, -10.13, 10.13)
UNITS = ("rad/s", "rad/s", "m/s", "rad/s", "rad/s", "rad/s")


def _solve(wrist: WristType) -> tuple[np.ndarray, np.ndarray, str]:
    mech = load("rcm_bevel", q3_lower=-0.2, wrist_type=wrist)
    try:
        qd = inverse_velocity(mech, Q, V, OMEGA)
        qdd = inverse_acceleration(mech, Q, qd, A, EPS)
        return qd, qdd, ""
    except SingularConfigurationError as exc:
        # position rows are regular: exact q̇1..3, q̈1..3; the wrist by minimum-norm least squares
        J = closed_form_jacobian(Q, wrist)
        qd = np.zeros(6)
        qd[:3] = np.linalg.solve(J[:3, :3], V)
        qd[3:] = np.linalg.lstsq(J[3:, 3:], OMEGA - J[3:, :3] @ qd[:3], rcond=None)[0]
        bias = forward(mech, Q, qd)
        qdd = np.zeros(6)
        qdd[:3] = np.linalg.solve(J[:3, :3], A - bias.a)
        rhs = EPS - bias.epsilon - J[3:, :3] @ qdd[:3]
        qdd[3:] = np.linalg.lstsq(J[3:, 3:], rhs, rcond=None)[0]
        res = np.linalg.norm(J @ qd - np.r_[V, OMEGA])
        return qd, qdd, f"{exc}. Least-squares values, residual |J q̇ − [v; ω]| = {res:.3g}"


def section(out_dir: Path) -> Section:
    """Velocity/acceleration example of paper 000 (SEEDS.md), computed both ways."""
    rpy_qd, rpy_qdd, _ = _solve("rpy")
    zyz_qd, zyz_qdd, zyz_note = _solve("zyz")
    rows: list[Comparison] = []
    pos_reason = {
        0: "",
        1: "",
        2: "printed unit rad/s; it is m/s",
    }
    acc_reason = {
        0: "at q = 0, ÿ = −q3 q̈1 − 2 q̇1 q̇3: 0.2 = 0.1 q̈1 − 20, q̈1 = 202",
        1: "the paper's own printed ẍ formula gives 0.2 = −0.1 q̈2 + 2 q̇2 q̇3, q̈2 = −202",
        2: "z̈ = q̈3 − q3 (q̇1² + q̇2²) gives −19.8; printed −19 (and unit rad/s²)",
        3: "sign: the printed values fit q̈4 = ε16z − εz (ours: εz − ε16z)",
        4: "our q̈5 = εy − ε16y − q̈2; printed fits q̈2 − ε16y − εy",
        5: "our q̈6 = εx − ε16x − q̈1; printed fits q̈1 + ε16x + εx",
    }
    for k in range(6):
        unit = UNITS[k]
        reason = "rpy wrist (q6 about tool x), ω = (0.52, 0.52, 0.52) given directly"
        rows.append(
            Comparison(
                f"q̇{k + 1} (rpy)",
                PUBLISHED_QD[k],
                float(rpy_qd[k]),
                unit,
                "; ".join(r for r in (pos_reason.get(k, ""), reason if k >= 3 else "") if r),
                tolerance=0.005,
            )
        )
    for k in range(6):
        rows.append(
            Comparison(
                f"q̈{k + 1} (rpy)",
                PUBLISHED_QDD[k],
                float(rpy_qdd[k]),
                UNITS[k] + "²" if k != 2 else "m/s²",
                acc_reason[k],
                tolerance=0.005,
            )
        )
    eps16 = coupling_terms(Q, rpy_qd, "rpy")
    for k, axis in enumerate("xyz"):
        rows.append(
            Comparison(
                f"ε1-6{axis} (rpy)",
                PUBLISHED_EPS16[k],
                float(eps16[k]),
                "rad/s²",
                "Σ_{j<i} ωj × ωi with the rpy rates",
                tolerance=0.005,
            )
        )
    for k in range(6):
        rows.append(
            Comparison(
                f"q̇{k + 1} (zyz)",
                PUBLISHED_QD[k],
                float(zyz_qd[k]),
                UNITS[k],
                "zyz wrist singular here (sin q5 = 0): minimum-norm least squares, "
                f"ω residual {zyz_note.split('= ')[-1]}"
                if k >= 3
                else "position rows regular: same as rpy",
                tolerance=0.005,
            )
        )
    w2, e2 = omega_from_angle_rates([0, 0, 0], [0.52] * 3, [1, 1, 1])
    mech = load("rcm_bevel", q3_lower=-0.2, wrist_type="rpy")
    qdd_angles = inverse_acceleration(mech, Q, rpy_qd, A, e2)
    check = forward(mech, Q, rpy_qd, rpy_qdd)
    body = f"""
Paper 000, velocity and acceleration example: x = y = 0, z = −0.1 m (q3 = −0.1 m, all
other q = 0; loaded with `q3_lower=-0.2`), ẋ = ẏ = ż = 1 m/s, ẍ = ÿ = z̈ = 0.2 m/s²,
α = β = γ = 0, angular accelerations 1 rad/s².

**Reading of the angular velocity.** The paper gives no angular velocity, only
ω_x = ω_y = ω_z = 0.52 rad/s as a result, and sets e_α = e1, e_β = e2, e_γ = e4. At
q = 0 these are x, y, z, so ω = (α̇, β̇, γ̇): the example assumes α̇ = β̇ = γ̇ = 0.52 rad/s
(≈ π/6, the q5 of the position example). With R = Rz(γ)Ry(β)Rx(α) the same ω follows
from those rates at α = β = γ = 0 ({np.round(w2, 6).tolist()}). The angular acceleration
is read as ε = (1, 1, 1) rad/s² given directly, as in the paper's equation
ε_x = Σ q̈i e_ix + ε_{{1-6x}}. (Differentiating ω of the absolute angles instead gives
ε = {np.round(e2, 4).tolist()} and q̈ = {np.round(qdd_angles, 4).tolist()}.)

**Wrist convention.** The published q̇4..6 are exactly the roll–pitch–yaw wrist
(`wrist_type=rpy`: q6 about the tool x axis, e6 = [cβ cγ, cβ sγ, −sβ] as printed): at q = 0,
e4 = z, e5 = y, e6 = x, so q̇4 = ω_z, q̇5 = ω_y − q̇2, q̇6 = ω_x − q̇1. With the default
`zyz` wrist the configuration is singular (e6 = e4 at sin q5 = 0): rcm-pin raises
`SingularConfigurationError` ("{zyz_note.split(". Least")[0]}") and the ω_x component is
unreachable; the zyz rows below are least-squares values, shown for completeness.

The position rates are regular for both wrists. The printed dy/dt has a sign typo in its
first term (+q̇1 q3 c1 c2 instead of −q̇1 q3 c1 c2); with the printed sign q̇1 would be −10,
the published +10 uses the correct sign. ε_{{1-6}} (the Σ ωj × ωi terms) agrees with the
rpy rates to the printed precision; the published q̈ do not, and the pattern of the
differences (column "reason") points to sign slips in the paper's elimination; q̈1..3
contradict the paper's own printed ẍ formula. Forward check (Pinocchio, rpy, the
computed q̇, q̈): v = {np.round(check.v, 9).tolist()}, a = {np.round(check.a, 9).tolist()},
ω = {np.round(check.omega, 9).tolist()}, ε = {np.round(check.epsilon, 9).tolist()}.

{comparison_table(rows)}

zyz least-squares q̈: {np.round(zyz_qdd, 4).tolist()}.
"""
    return Section("Velocity and acceleration problems (paper 000)", body)
