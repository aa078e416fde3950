"""Crossing a type-2 singularity of the five-bar with extra drives (paper 004, Figs. 13–14).

The output point P follows a path that crosses the type-2 curve of the main drives (distal
links aligned) under the paper's computed-torque law

    ẍ_d = ẍ_T + γ1 (ẋ_T − ẋ) + γ0 (x_T − x),   γ1 = 2ζ/τ_c, γ0 = 1/τ_c²

(τ_c [s] transient time constant, ζ damping). Drive torques come from the closed-loop
inverse dynamics of :mod:`.dynamics` with the active drive set; the plant is the constrained
forward dynamics, integrated with ``scipy.integrate.solve_ivp``.

Three runs:
* ``main``: main drives only, unlimited torque — |τ| grows like 1/distance to the curve
  (integration stops when |τ| exceeds ``blowup`` or the measure falls below 1e-9);
* ``main_saturated``: main drives only, torques clipped to ±``tau_max`` — loses the path;
* ``switching``: main drives outside the band, the two extra (elbow) drives inside it
  (σ_min/σ_max of A of the main drives below ``band``), same ±``tau_max`` limit.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from rcm_pin.closed_loop import five_bar as fb
from rcm_pin.closed_loop.core import ClosedMechanism
from rcm_pin.closed_loop.dynamics import (
    acceleration_for_output,
    forward_dynamics,
    inverse_dynamics,
    output_drift,
    velocity_for_output,
)
from rcm_pin.closed_loop.velocity import velocity_matrices


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
    p0, p1 = np.array(s.p0), np.array(s.p1)
    u = min(max(t / s.duration, 0.0), 1.0)
    h = 10 * u**3 - 15 * u**4 + 6 * u**5
    hd = (30 * u**2 - 60 * u**3 + 30 * u**4) / s.duration if 0 < t < s.duration else 0.0
    hdd = (60 * u - 180 * u**2 + 120 * u**3) / s.duration**2 if 0 < t < s.duration else 0.0
    return p0 + h * (p1 - p0), hd * (p1 - p0), hdd * (p1 - p0)


def _controller(
    mech: ClosedMechanism,
    t: float,
    q: np.ndarray,
    v: np.ndarray,
    s: StudySettings,
    switching: bool,
    limit: float | None,
) -> dict[str, Any]:
    xt, xdt, xddt = reference(t, s)
    xd, _, _ = output_drift(mech, q, v)
    x = mech.output(q)
    g1, g0 = 2.0 * s.zeta / s.tau_c, 1.0 / s.tau_c**2
    a = acceleration_for_output(mech, q, v, xddt + g1 * (xdt - xd) + g0 * (xt - x))
    measure = velocity_matrices(mech, q).measure_type2
    extras = switching and measure < s.band
    drives = mech.extra_drives if extras else mech.driven
    tau, _ = inverse_dynamics(mech, q, v, a, drives)
    if limit is not None:
        tau = np.clip(tau, -limit, limit)
    tau_full = np.zeros(mech.model.nv)
    tau_full[mech.joint_indices(drives)] = tau
    return {
        "x": x,
        "xt": xt,
        "tau": tau,
        "tau_full": tau_full,
        "extras": extras,
        "measure": measure,
    }


def simulate(
    mech: ClosedMechanism,
    label: str,
    switching: bool,
    limit: float | None,
    s: StudySettings | None = None,
    max_step: float = 2e-3,
) -> Run:
    """Integrate the closed-loop system under computed torque (see module docstring)."""
    s = s or StudySettings()
    g = fb.GeometryFiveBar.from_params(mech.params)
    start = np.array(s.p0) + np.array(s.offset)
    qd, _ = fb.inverse_position(g, start)
    q0 = fb.full_q(g, start, qd[s.mode])
    n = mech.model.nv

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        q, v = y[:n], y[n:]
        ctl = _controller(mech, t, q, v, s, switching, limit)
        a, _ = forward_dynamics(mech, q, v, ctl["tau_full"])
        return np.concatenate([v, a])

    def blowup(t: float, y: np.ndarray) -> float:
        ctl = _controller(mech, t, y[:n], y[n:], s, switching, limit)
        return min(s.blowup - float(np.max(np.abs(ctl["tau"]))), ctl["measure"] - 1e-9)

    blowup.terminal = True  # type: ignore[attr-defined]
    t_end = s.duration + s.hold
    sol = solve_ivp(
        rhs,
        (0.0, t_end),
        np.concatenate([q0, np.zeros(n)]),
        method="RK45",
        max_step=max_step,
        rtol=1e-8,
        atol=1e-10,
        events=blowup,
        dense_output=False,
    )
    keep = np.ones(len(sol.t), dtype=bool)
    rows = [
        _controller(mech, t, y[:n], y[n:], s, switching, limit)
        for t, y in zip(sol.t[keep], sol.y.T[keep], strict=True)
    ]
    tau_main = np.array([r["tau"] if not r["extras"] else np.zeros(2) for r in rows])
    tau_extra = np.array([r["tau"] if r["extras"] else np.zeros(2) for r in rows])
    return Run(
        label=label,
        t=sol.t,
        x=np.array([r["x"] for r in rows]),
        x_ref=np.array([r["xt"] for r in rows]),
        tau_main=tau_main,
        tau_extra=tau_extra,
        extras_on=np.array([r["extras"] for r in rows]),
        measure=np.array([r["measure"] for r in rows]),
        completed=bool(sol.t[-1] >= t_end - 1e-9),
        info={"status": int(sol.status), "nfev": int(sol.nfev), "drives": list(mech.driven)},
    )


def torque_along_reference(
    mech: ClosedMechanism, s: StudySettings | None = None, n: int = 4001
) -> dict[str, np.ndarray]:
    """Main and extra drive torques on the exact reference (no tracking error) [N·m].

    Shows the 1/distance growth of the main drives' torque at the crossing, and that the
    extra drives stay bounded there.
    """
    s = s or StudySettings()
    g = fb.GeometryFiveBar.from_params(mech.params)
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
        out["extra"][i] = inverse_dynamics(mech, q, v, a, mech.extra_drives)[0]
    return out
