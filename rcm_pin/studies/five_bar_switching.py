"""Crossing a type-2 singularity of the five-bar with extra drives (paper 004, Figs. 13–14).

The output point P follows a path that crosses the type-2 curve of the main drives (distal
links aligned) under the paper's computed-torque law

    ẍ_d = ẍ_T + γ1 (ẋ_T − ẋ) + γ0 (x_T − x),   γ1 = 2ζ/τ_c, γ0 = 1/τ_c²

(τ_c [s] transient time constant, ζ damping): the one computed-torque law of
:mod:`rcm_pin.control.computed_torque` with its drive-switching option, drive torques from
the closed-loop inverse dynamics with the active drive set, and the one
:func:`rcm_pin.control.simulate.simulate` on the constrained forward dynamics.

Three runs:

* ``main``: main drives only, unlimited torque — |τ| grows like 1/distance to the curve
  (integration stops when |τ| exceeds ``blowup`` or the measure falls below 1e-9);
* ``main_saturated``: main drives only, torques clipped to ±``tau_max`` — loses the path;
* ``switching``: main drives outside the band, the two extra (elbow) drives inside it
  (σ_min/σ_max of A of the main drives below ``band``), same ±``tau_max`` limit.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rcm_pin.analysis.loop_velocity import velocity_matrices
from rcm_pin.control.computed_torque import ComputedTorque, DriveSwitching, Gains
from rcm_pin.control.references import QuinticPath
from rcm_pin.control.simulate import SimulationOptions
from rcm_pin.control.simulate import simulate as simulate_run
from rcm_pin.dynamics.constrained import (
    acceleration_for_output,
    inverse_dynamics,
    velocity_for_output,
)
from rcm_pin.mechanisms import five_bar as fb
from rcm_pin.model.mechanism import Mechanism


@dataclass(frozen=True)
class StudySettings:
    """Path, gains and limits of the study (SI units)."""

    p0: tuple[float, float] = (0.01, 0.17)  # path start [m]
    p1: tuple[float, float] = (-0.01, 0.02)  # path end [m]
    duration: float = 1.0  # [s]
    hold: float = 0.3  # rest at p1 after the motion [s]
    offset: tuple[float, float] = (0.002, 0.0)  # initial position error [m]
    mode: int = 1  # working mode (σ_1, σ_2) = (+, −): elbows out
    tau_c: float = 0.03  # transient time constant [s]
    zeta: float = 1.0
    band: float = 0.2  # switching band on the main-drive A measure [-]
    tau_max: float = 0.5  # drive torque limit [N·m]
    blowup: float = 1e3  # stop the unlimited run above this |τ| [N·m]


@dataclass(frozen=True)
class Run:
    """One simulated run: time [s], P and reference [m], efforts [N·m], extras-on flags."""

    label: str
    t: np.ndarray
    x: np.ndarray
    x_ref: np.ndarray
    tau_main: np.ndarray
    tau_extra: np.ndarray
    extras_on: np.ndarray
    measure: np.ndarray
    completed: bool
    info: dict[str, Any] = field(default_factory=dict)

    @property
    def error(self) -> np.ndarray:
        """Tracking error |P − P_T| [m]."""
        return np.linalg.norm(self.x - self.x_ref, axis=1)

    def summary(self) -> dict[str, Any]:
        """Peak efforts, errors (after the 0.2 s transient) and completion."""
        late = self.t > 0.2
        return {
            "label": self.label,
            "completed": self.completed,
            "t_end": float(self.t[-1]),
            "peak_main_torque": float(np.max(np.abs(self.tau_main))),
            "peak_extra_torque": float(np.max(np.abs(self.tau_extra))),
            "max_error_after_transient": float(np.max(self.error[late])) if late.any() else None,
            "final_error": float(self.error[-1]),
            "min_main_measure": float(np.min(self.measure)),
            "time_on_extras": float(np.sum(np.diff(self.t) * self.extras_on[1:])),
        }


def reference(t: float, s: StudySettings) -> tuple[np.ndarray, ...]:
    """Quintic point-to-point reference x_T, ẋ_T, ẍ_T at time t."""
    return QuinticPath(s.p0, s.p1, s.duration).evaluate(t)


def controller(
    mech: Mechanism, s: StudySettings, switching: bool, limit: float | None
) -> ComputedTorque:
    """The computed-torque law of the study (band 0: main drives, measure still recorded)."""
    return ComputedTorque(
        mech,
        QuinticPath(s.p0, s.p1, s.duration),
        Gains.from_tau_zeta(s.tau_c, s.zeta),
        limits=limit,
        switching=DriveSwitching(s.band if switching else 0.0),
    )


def simulate(
    mech: Mechanism,
    label: str,
    switching: bool,
    limit: float | None,
    s: StudySettings | None = None,
    max_step: float = 2e-3,
) -> Run:
    """Integrate the closed-loop system under computed torque (see module docstring)."""
    s = s or StudySettings()
    g = fb.geometry(mech)
    start = np.array(s.p0) + np.array(s.offset)
    qd, _ = fb.inverse_position(g, start)
    q0 = fb.full_q(g, start, qd[s.mode])
    ctrl = controller(mech, s, switching, limit)

    def blowup(t: float, q: np.ndarray, v: np.ndarray) -> float:
        eff = ctrl.effort(t, q, v)
        return min(s.blowup - float(np.max(np.abs(eff.tau))), eff.measure - 1e-9)

    t_end = s.duration + s.hold
    run = simulate_run(
        mech,
        ctrl,
        t_end,
        q0,
        options=SimulationOptions(
            samples=None,
            rtol=1e-8,
            atol=1e-10,
            method="RK45",
            max_step=max_step,
            stop_error=None,
            events=[(f"|tau| > {s.blowup:g} N*m or type-2 measure < 1e-9", blowup)],
        ),
    )
    loops = mech.require_loops()
    return Run(
        label=label,
        t=run.t,
        x=run.x,
        x_ref=run.x_ref,
        tau_main=run.tau[:, loops.drive_v],
        tau_extra=run.tau[:, mech.joint_v(loops.extra_drives)],
        extras_on=run.alternate,
        measure=run.measure,
        completed=bool(run.t[-1] >= t_end - 1e-9),
        info={"status": run.status, "nfev": run.nfev, "drives": list(loops.drives)},
    )


def torque_along_reference(
    mech: Mechanism, s: StudySettings | None = None, n: int = 4001
) -> dict[str, np.ndarray]:
    """Main and extra drive torques on the exact reference (no tracking error) [N·m].

    Shows the 1/distance growth of the main drives' torque at the crossing, and that the
    extra drives stay bounded there.
    """
    s = s or StudySettings()
    g = fb.geometry(mech)
    extra = mech.require_loops().extra_drives
    ts = np.linspace(0.0, s.duration, n)
    out = {"t": ts, "main": np.zeros((n, 2)), "extra": np.zeros((n, 2)), "measure": np.zeros(n)}
    for i, t in enumerate(ts):
        x, xd, xdd = reference(float(t), s)
        qs, _ = fb.inverse_position(g, x)
        q = fb.full_q(g, x, qs[s.mode])
        out["measure"][i] = velocity_matrices(mech, q).measure_type2
        v = velocity_for_output(mech, q, xd)
        a = acceleration_for_output(mech, q, v, xdd)
        try:
            out["main"][i] = inverse_dynamics(mech, q, v, a)[0]
        except np.linalg.LinAlgError:  # a sample exactly on the curve
            out["main"][i] = np.nan
        out["extra"][i] = inverse_dynamics(mech, q, v, a, extra)[0]
    return out


def switching_figure(runs: list[Run], ref: dict[str, np.ndarray], path: Path) -> Path:
    """Efforts and tracking error with and without drive switching."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.4))
    ax = axes[0]
    ax.semilogy(ref["t"], np.max(np.abs(ref["main"]), axis=1), label="main drives")
    ax.semilogy(ref["t"], np.max(np.abs(ref["extra"]), axis=1), label="extra drives")
    ax.set_ylim(1e-4, None)
    ax.set_title("max |τ| on the exact reference path")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("|τ| [N·m]")
    ax.legend()
    # The switching run follows the unlimited one wherever no limit acts: the unlimited run
    # (the first) is dashed and drawn on top so that neither hides the other.
    styles = [{"ls": (0, (4, 2)), "lw": 2.2, "zorder": 3}] + [{"lw": 1.5, "zorder": 2}] * len(runs)
    ax = axes[1]
    for run, style in zip(runs, styles):
        eff = np.max(np.abs(run.tau_main), axis=1) + np.max(np.abs(run.tau_extra), axis=1)
        ax.semilogy(run.t, np.maximum(eff, 1e-6), label=run.label, **style)
    on = runs[-1].extras_on
    if on.any():
        t_on = runs[-1].t[on]
        ax.axvspan(t_on.min(), t_on.max(), color="0.85", label="extra drives on")
    ax.set_ylim(1e-3, None)
    ax.set_title("max |drive torque| in simulation")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("|τ| [N·m]")
    ax.legend(fontsize=8)
    ax = axes[2]
    for run, style in zip(runs, styles):
        ax.semilogy(run.t, np.maximum(run.error, 1e-12), label=run.label, **style)
    ax.set_title("tracking error |P − P_T|")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("[m]")
    ax.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


__all__ = [
    "Run",
    "StudySettings",
    "controller",
    "reference",
    "simulate",
    "switching_figure",
    "torque_along_reference",
]
