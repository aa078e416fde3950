"""Report section: dynamics and computed-torque control (paper 000 Fig. 4, paper 004).

Every number is simulated here; paper 000 prints no numbers for its example (only the
curves of Fig. 4), so the rows are "new" computations next to the linear theory.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from rcm_pin.catalog import load
from rcm_pin.control.computed_torque import ComputedTorque, Gains, drive_limits
from rcm_pin.control.linear import linear_error
from rcm_pin.control.plots import plot_deviation, plot_efforts, plot_phase
from rcm_pin.control.references import TRAJECTORIES
from rcm_pin.control.result import SimulationResult
from rcm_pin.control.simulate import SimulationOptions, simulate
from rcm_pin.dynamics.tree import inverse_dynamics, with_gravity
from rcm_pin.mechanisms.rcm.point import joint_reference
from rcm_pin.mechanisms.rcm.two_mass import two_mass_args
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.report.framework import Comparison, Section, comparison_table

GAINS = Gains(720.0, 12.0)  # paper 000
L_DEFAULT = 0.2  # [m] = l9, not given by the paper
DURATION = 3.0  # [s]
STEADY_FROM = 2.0  # [s]
SCALES = (0.8, 0.9, 1.1, 1.2)


def load_two_mass(m: float = 0.4, m_d: float = 0.2, L: float = 0.2,
                  **xacro_args: object) -> Mechanism:  # fmt: skip
    """``rcm_two_mass`` with m, m_d, L given directly (see ``two_mass_args``)."""
    args: dict[str, Any] = {**two_mass_args(m, m_d, L), **xacro_args}
    return load("rcm_two_mass", **args)


def _paper_run(feedforward: bool, printed: bool = False, space: str = "task") -> SimulationResult:
    plant = with_gravity(load_two_mass(0.4, 0.2, L_DEFAULT, q3_upper=0.3))
    ctrl = ComputedTorque(
        plant,
        TRAJECTORIES["paper000"],
        GAINS,
        space=space,
        feedforward=feedforward,
        printed_sign=printed,
        limits=drive_limits(plant),
    )
    return simulate(
        plant, ctrl, DURATION, options=SimulationOptions(samples=1501, allow_outside_limits=printed)
    )


def _robustness() -> list[str]:
    traj = TRAJECTORIES["paper000"]
    true = with_gravity(load_two_mass(0.4, 0.2, L_DEFAULT, q3_upper=0.3))
    nominal = simulate(
        true, ComputedTorque(true, traj, GAINS), DURATION, options=SimulationOptions(samples=751)
    )
    rows = [
        "| controller model | RMS error [mm] | change [%] | max steady error t ≥ 2 s [mm] |",
        "| --- | ---: | ---: | ---: |",
        f"| exact (m = 0.4, m_d = 0.2 kg, L = 0.2 m) | {1e3 * nominal.rms_error():.4f} | 0 "
        f"| {1e3 * nominal.steady_error(STEADY_FROM).max():.2e} |",
    ]
    for label in ("m", "m_d", "L", "all"):
        for s in SCALES:
            kw = {"m": 0.4, "m_d": 0.2, "L": L_DEFAULT}
            for key in kw if label == "all" else (label,):
                kw[key] *= s
            model = with_gravity(load_two_mass(q3_upper=0.3, **kw))
            r = simulate(
                true,
                ComputedTorque(model, traj, GAINS),
                DURATION,
                options=SimulationOptions(samples=751),
            )
            change = 100.0 * (r.rms_error() / nominal.rms_error() - 1.0)
            rows.append(
                f"| {label} × {s:g} | {1e3 * r.rms_error():.4f} | {change:+.2f} "
                f"| {1e3 * r.steady_error(STEADY_FROM).max():.4f} |"
            )
    return rows


def _model_gap(g: np.ndarray | None) -> list[str]:
    """Inverse-dynamics efforts of the two-mass model vs the full models on the reference."""
    traj = TRAJECTORIES["paper000"]
    t = np.linspace(0.0, 2 * np.pi / traj.omega, 200)
    two = with_gravity(load_two_mass(0.4, 0.2, L_DEFAULT, q3_upper=0.3), g)
    out = []
    for name in ("rcm_bevel", "rcm_belt"):
        full = with_gravity(load(name, q3_upper=0.3), g)
        diff, ref = [], []
        for ti in t:
            q, qd, qdd = joint_reference(traj, float(ti))
            tau2 = inverse_dynamics(two, q, qd, qdd)
            pad = np.zeros(full.nq - 3)
            tauf = inverse_dynamics(full, np.r_[q, pad], np.r_[qd, pad], np.r_[qdd, pad])[:3]
            diff.append(tau2 - tauf)
            ref.append(tauf)
        d, r = np.array(diff), np.array(ref)
        rms_d, rms_r = np.sqrt(np.mean(d**2, 0)), np.sqrt(np.mean(r**2, 0))
        cells = " | ".join(f"{a:.3g} ({100 * a / b:.0f} %)" for a, b in zip(rms_d, rms_r))
        out.append(f"| {name} | {'yes' if g is not None else 'no'} | {cells} |")
    return out


def section(out_dir: Path) -> Section:
    """Paper 000's dynamic example, feed-forward, printed sign, model gap, robustness."""
    ff, noff = _paper_run(True), _paper_run(False)
    joint = _paper_run(True, space="joint")
    printed = _paper_run(True, printed=True)
    traj = TRAJECTORIES["paper000"]
    pred_ff = linear_error(GAINS, ff.error[0], ff.error_rate[0], ff.t)
    pred_no = linear_error(GAINS, noff.error[0], noff.error_rate[0], noff.t, traj)
    figs = [
        plot_deviation(
            ff,
            out_dir / "dyn_fig4a_deviation_x.png",
            0,
            pred_ff[:, 0],
            "paper 000 Fig. 4a: deviation along x (feed-forward)",
        ),
        plot_phase(
            ff, out_dir / "dyn_fig4b_phase_x.png", 0, "paper 000 Fig. 4b: phase trajectory along x"
        ),
        plot_deviation(
            noff,
            out_dir / "dyn_deviation_x_no_ff.png",
            0,
            pred_no[:, 0],
            "deviation along x without feed-forward",
        ),
        plot_efforts(
            ff, out_dir / "dyn_efforts.png", "drive efforts, two-mass model (feed-forward)"
        ),
    ]
    w = traj.omega
    forced = 0.01 * w**2 / abs(complex(GAINS.kn - w**2, GAINS.kc * w))
    roots = np.roots([1.0, GAINS.kc, -GAINS.kn])
    rows = [
        Comparison(
            "steady |e_x| with feed-forward, t ≥ 2 s",
            None,
            1e3 * ff.steady_error(STEADY_FROM)[0],
            "mm",
        ),
        Comparison(
            "steady |e_x| without feed-forward, t ≥ 2 s",
            None,
            1e3 * noff.steady_error(STEADY_FROM)[0],
            "mm",
        ),
        Comparison(
            "linear theory a_t/|Kn − ω² + iKcω| (no feed-forward)", None, 1e3 * forced, "mm"
        ),
        Comparison(
            "max |simulated − linear| error, feed-forward",
            None,
            float(np.abs(pred_ff - ff.error).max()),
            "m",
        ),
        Comparison(
            "max |simulated − linear| error, no feed-forward",
            None,
            float(np.abs(pred_no - noff.error).max()),
            "m",
        ),
        Comparison(
            "steady |e_x| joint-space law with feed-forward, t ≥ 2 s",
            None,
            1e3 * joint.steady_error(STEADY_FROM)[0],
            "mm",
        ),
        Comparison(
            "peak |τ1|, |τ2| (limit 5 N·m)", None, float(np.abs(ff.tau[:, :2]).max()), "N·m"
        ),
        Comparison("peak |F3| (limit 50 N)", None, float(np.abs(ff.tau[:, 2]).max()), "N"),
        Comparison("printed sign: time to |e| > 0.5 m", None, float(printed.t[-1]), "s"),
    ]
    body = f"""
Paper 000's example on the two-mass model (`rcm_two_mass`, point masses m = 0.4 kg at the
tool centre and m_d = 0.2 kg on the output axis at **L = {L_DEFAULT} m** (= l9; the paper
gives no L)). Desired x_t = 0.1 + 0.01 sin ωt, y_t = 0.1 + 0.01 cos ωt,
z_t = 0.1 + 0.01 sin ωt, ω = 10 rad/s, start (0.11, 0.12, 0.15) m at rest, Kn = 720,
Kc = 12 (τ = {GAINS.tau:.4f} s, ζ = {GAINS.zeta:.3f} in paper 004's form). The trajectory has
|p| ≈ 0.17 m and starts at |p| = 0.216 m, beyond the rig's q3 ≤ 0.12 m: the model is
loaded with **q3_upper = 0.3**. Gravity is off (the paper's equations have none). Drive
limits 5 N·m / 50 N are applied (never reached). Task-space computed torque
a = a_t + Kn(x_t − x) + Kc(v_t − v) (the project's law); Dev = x_t − x.

{comparison_table(rows)}

With a perfect model the simulated error follows ë + Kc ė + Kn e = (1 − f) a_t to
integration accuracy (dashed curves). The roots of s² + 12 s + 720 are
−6 ± 26.2i: the transient decays as e^(−6t), so "steady" means t ≥ 2 s. **The printed
law** a = Kn(x − x_t) + Kc(v_t − v) gives ë + Kc ė − Kn e = …, roots
{roots[0]:.1f} and {roots[1]:.1f} 1/s: the error grows as e^({max(roots.real):.1f} t) and the
run leaves the workspace ({printed.status}) at t = {printed.t[-1]:.3f} s. Fig. 4 of the
paper shows convergence, so the printed sign is a typo.

Figures: `dyn_fig4a_deviation_x.png` (Fig. 4a), `dyn_fig4b_phase_x.png` (Fig. 4b),
`dyn_deviation_x_no_ff.png`, `dyn_efforts.png`.

**Two-mass model vs the full models** (inverse-dynamics efforts on one period of the
reference, q4 = q5 = q6 = 0; RMS of τ_two-mass − τ_full and its share of the full
model's RMS, for τ1 [N·m], τ2 [N·m], F3 [N]):

| full model | gravity | Δτ1 | Δτ2 | ΔF3 |
| --- | --- | ---: | ---: | ---: |
{chr(10).join(_model_gap(None) + _model_gap(np.array([0.0, 0.0, -9.81])))}

**Robustness** (paper 004: model mismatch changes the error by ≤ ~3 %): the true plant is
the nominal two-mass model, the controller's model has m, m_d, L (or all three) scaled;
task space with feed-forward, RMS of |e| over 0–{DURATION:g} s:

{chr(10).join(_robustness())}
"""
    return Section(
        title="Dynamics and computed-torque control (papers 000, 004)",
        body=body,
        figures=tuple(p.name for p in figs),
    )
