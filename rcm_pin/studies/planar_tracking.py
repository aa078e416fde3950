"""Computed-torque tracking of a platform trajectory on the planar 3-RRR (paper 004, control).

The platform pose p = (x, y [m], φ [rad]) follows a reference p_T(t) (default: a circle of
the centre with a φ oscillation, inside the constant-orientation workspace and away from the
singular curves; :func:`check_path` classifies every sample) under the one computed-torque
law of :mod:`rcm_pin.control.computed_torque` (Kn = 1/τ², Kc = 2ζ/τ; joint acceleration
from [J_c; J_x] q̈ = [−γ − Baumgarte; a* − J̇_x q̇], drive torques from the closed-loop
inverse dynamics), integrated by the one :func:`rcm_pin.control.simulate.simulate` on the
constrained forward dynamics with Baumgarte stabilisation. With a perfect model every
output coordinate of e = p − p_T obeys τ² ë + 2ζτ ė + e = 0
(:func:`rcm_pin.control.linear.error_response`).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rcm_pin.analysis.loop_velocity import classify
from rcm_pin.analysis.position import inverse
from rcm_pin.control.computed_torque import ComputedTorque, Gains
from rcm_pin.control.linear import error_response as linear_response
from rcm_pin.control.references import CircleWithAngle
from rcm_pin.control.simulate import SimulationOptions, simulate
from rcm_pin.dynamics.constrained import (
    acceleration_for_output,
    inverse_dynamics,
    velocity_for_output,
)
from rcm_pin.errors import InvalidInputError, SingularConfigurationError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.rotations import wrap_angle


@dataclass(frozen=True)
class TrackingSettings:
    """Reference, gains and initial error (SI units)."""

    centre: tuple[float, float] = (0.02, 0.01)  # circle centre [m]
    radius: float = 0.03  # [m]
    phi0: float = 0.0  # mean orientation [rad]
    phi_amp: float = 0.1  # orientation oscillation amplitude [rad]
    period: float = 1.0  # one lap and one φ oscillation [s]
    duration: float = 1.0  # [s]
    tau: float = 0.05  # error time constant [s]
    zeta: float = 1.0  # error damping [-]
    mode: str = "+++"  # working mode label of the inverse problem
    offset: tuple[float, float, float] = (0.002, -0.001, 0.01)  # initial pose error [m, m, rad]
    rate_offset: tuple[float, float, float] = (0.0, 0.0, 0.0)  # initial rate error
    baumgarte: tuple[float, float] = (50.0, 1.0)  # ω [rad/s], ζ of the closure stabilisation
    samples: int = 201

    def validate(self) -> None:
        """Raises InvalidInputError on a non-positive or non-finite setting."""
        for name in ("radius", "period", "duration", "tau", "zeta"):
            val = getattr(self, name)
            if not (np.isfinite(val) and val > 0):
                raise InvalidInputError(f"{name} {val} is invalid; valid: finite and > 0")
        if self.samples < 2:
            raise InvalidInputError(f"samples {self.samples} is invalid; valid: >= 2")

    @property
    def circle(self) -> CircleWithAngle:
        """The reference as a :class:`~rcm_pin.control.references.CircleWithAngle`."""
        return CircleWithAngle(self.centre, self.radius, self.phi0, self.phi_amp, self.period)

    def reference(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """p_T, ṗ_T, p̈_T at time t."""
        return self.circle.evaluate(t)


@dataclass(frozen=True)
class TrackingResult:
    """Simulated tracking: t [s], q (N, n), pose / reference / error (N, 3), torques (N, 3)."""

    t: np.ndarray
    q: np.ndarray
    pose: np.ndarray
    reference: np.ndarray
    torques: np.ndarray
    error: np.ndarray
    closure_residual: np.ndarray
    settings: TrackingSettings
    info: dict[str, Any] = field(default_factory=dict)

    @property
    def max_closure_residual(self) -> float:
        """max |c(q)| over the samples [m]."""
        return float(np.max(self.closure_residual))

    def summary(self) -> dict[str, Any]:
        """Plain dict for the CLI."""
        expected = error_response(self.t, self.settings)
        return {
            "settings": asdict(self.settings),
            "kn": 1.0 / self.settings.tau**2,
            "kc": 2.0 * self.settings.zeta / self.settings.tau,
            "samples": len(self.t),
            "initial_error": self.error[0].tolist(),
            "final_error": self.error[-1].tolist(),
            "max_abs_error": np.max(np.abs(self.error), axis=0).tolist(),
            "max_deviation_from_error_dynamics": float(np.max(np.abs(self.error - expected))),
            "peak_torque": np.max(np.abs(self.torques), axis=0).tolist(),
            "max_closure_residual": self.max_closure_residual,
            **self.info,
        }


def error_response(t: np.ndarray, s: TrackingSettings) -> np.ndarray:
    """Closed-form e(t) (N, 3) of τ² ë + 2ζτ ė + e = 0 from e(0) = offset, ė(0) = rate_offset."""
    return linear_response(t, s.tau, s.zeta, np.array(s.offset), np.array(s.rate_offset))


def _check(mech: Mechanism, s: TrackingSettings) -> None:
    if mech.loops is None or mech.output.coords != ("x", "y", "rz"):
        raise InvalidInputError(
            f"platform tracking needs a closed mechanism with output (x, y, rz); {mech.name} "
            f"has {list(mech.output.coords)}"
        )
    s.validate()


def configuration(mech: Mechanism, pose: np.ndarray, mode: str) -> np.ndarray:
    """The closed configuration of working mode ``mode`` at an output pose."""
    sols = {sol.mode: sol.q for sol in inverse(mech, pose).solutions}
    if mode not in sols:
        raise InvalidInputError(
            f"mode {mode!r} is not a working mode of {mech.name}; valid: {', '.join(sols)}"
        )
    return sols[mode]


def check_path(mech: Mechanism, s: TrackingSettings, n: int = 73) -> dict[str, float]:
    """Classify n reference poses (working mode ``s.mode``); min singularity measures.

    Raises:
        UnreachablePoseError: a reference pose is outside the workspace.
        SingularConfigurationError: a reference pose is type-1 or type-2 singular.
    """
    _check(mech, s)
    m1 = m2 = np.inf
    for t in np.linspace(0.0, s.duration, n):
        c = classify(mech, configuration(mech, s.reference(float(t))[0], s.mode))
        if c.label != "regular":
            raise SingularConfigurationError(
                f"{mech.name}: the reference is {c.label} singular at t = {t:.4g} s "
                f"(measures {c.measure_type1:.2e}, {c.measure_type2:.2e})"
            )
        m1, m2 = min(m1, c.measure_type1), min(m2, c.measure_type2)
    return {"min_measure_type1": float(m1), "min_measure_type2": float(m2)}


def controller(mech: Mechanism, s: TrackingSettings) -> ComputedTorque:
    """The computed-torque law of the study."""
    return ComputedTorque(mech, s.circle, Gains.from_tau_zeta(s.tau, s.zeta), baumgarte=s.baumgarte)


def reference_torques(mech: Mechanism, s: TrackingSettings, t: np.ndarray) -> np.ndarray:
    """Drive torques (N, 3) [N·m] on the exact reference (inverse position, velocity, ID)."""
    out = np.zeros((len(t), mech.require_loops().dof))
    for i, ti in enumerate(t):
        p, pd, pdd = s.reference(float(ti))
        q = configuration(mech, p, s.mode)
        v = velocity_for_output(mech, q, pd)
        out[i] = inverse_dynamics(mech, q, v, acceleration_for_output(mech, q, v, pdd))[0]
    return out


def simulate_tracking(mech: Mechanism, s: TrackingSettings | None = None) -> TrackingResult:
    """Integrate the constrained dynamics under computed torque (module docstring)."""
    s = s or TrackingSettings()
    path = check_path(mech, s)
    p0, pd0, _ = s.reference(0.0)
    q0 = configuration(mech, p0 + np.array(s.offset), s.mode)
    v0 = velocity_for_output(mech, q0, pd0 + np.array(s.rate_offset))
    ctrl = controller(mech, s)
    run = simulate(
        mech,
        ctrl,
        s.duration,
        q0,
        v0,
        SimulationOptions(
            samples=s.samples,
            rtol=1e-11,
            atol=1e-13,
            method="DOP853",
            stop_error=None,
            baumgarte=s.baumgarte,
        ),
    )
    if not run.completed:
        raise SingularConfigurationError(f"{mech.name}: integration failed: {run.status}")
    err = run.x - run.x_ref
    err[:, 2] = wrap_angle(err[:, 2])
    drives = mech.require_loops().drive_v
    return TrackingResult(
        t=run.t,
        q=run.q,
        pose=run.x,
        reference=run.x_ref,
        torques=run.tau[:, drives],
        error=err,
        closure_residual=run.closure_residual,
        settings=s,
        info={"nfev": run.nfev, "drives": list(mech.require_loops().drives), **path},
    )


def tracking_figure(result: TrackingResult, path: Path) -> Path:
    """PNG: pose error (simulated and closed form) and drive torques over time."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    expected = error_response(result.t, result.settings)
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.4))
    for i, (lab, unit, sc) in enumerate((("x", "mm", 1e3), ("y", "mm", 1e3), ("φ", "mrad", 1e3))):
        ax = axes[0] if i < 2 else axes[1]
        ax.plot(result.t, sc * result.error[:, i], lw=2, label=f"e_{lab} simulated [{unit}]")
        ax.plot(result.t, sc * expected[:, i], "k--", lw=1, label=f"e_{lab} closed form")
    s = result.settings
    axes[0].set_title(f"position error (τ = {s.tau:g} s, ζ = {s.zeta:g})")
    axes[1].set_title(
        f"orientation error; max closure residual {result.max_closure_residual:.1e} m"
    )
    for ax in axes[:2]:
        ax.set_xlabel("t [s]")
        ax.legend(fontsize=8)
    for j in range(result.torques.shape[1]):
        axes[2].plot(result.t, result.torques[:, j], label=f"τ_A{j + 1}")
    axes[2].set_title("drive torques")
    axes[2].set_xlabel("t [s]")
    axes[2].set_ylabel("[N·m]")
    axes[2].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


__all__ = [
    "TrackingResult",
    "TrackingSettings",
    "check_path",
    "configuration",
    "controller",
    "error_response",
    "reference_torques",
    "simulate_tracking",
    "tracking_figure",
]
