"""Computed-torque tracking of a platform trajectory on the planar 3-RRR (paper 004, control).

The platform pose p = (x, y [m], φ [rad]) follows a reference p_T(t) (default: a circle of
the centre with a φ oscillation, inside the constant-orientation workspace and away from the
singular curves; :func:`check_path` classifies every sample). The control law of paper 004

    a* = p̈_T + Kc (ṗ_T − ṗ) + Kn (p_T − p),   Kn = 1/τ², Kc = 2ζ/τ

gives the joint acceleration ([J_c; J_x] q̈ = [−γ − Baumgarte; a* − J̇_x q̇]) and the drive
torques through the closed-loop inverse dynamics of :mod:`.dynamics`. The plant is the
KKT forward dynamics with Baumgarte stabilisation, integrated by ``solve_ivp``. With a
perfect model, every output coordinate of e = p − p_T obeys τ² ë + 2ζτ ė + e = 0
(closed form: :func:`error_response`).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from rcm_pin.closed_loop.core import ClosedMechanism
from rcm_pin.closed_loop.dynamics import (
    acceleration_for_output,
    forward_dynamics,
    inverse_dynamics,
    output_drift,
    velocity_for_output,
)
from rcm_pin.closed_loop.position import inverse_position
from rcm_pin.closed_loop.velocity import classify
from rcm_pin.errors import InvalidInputError, SingularConfigurationError


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
    mode: str = "+++"  # working mode label of inverse_position
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

    def reference(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """p_T, ṗ_T, p̈_T at time t."""
        w = 2.0 * np.pi / self.period
        c, s = np.cos(w * t), np.sin(w * t)
        r, a = self.radius, self.phi_amp
        p = np.array([self.centre[0] + r * c, self.centre[1] + r * s, self.phi0 + a * s])
        return (
            p,
            np.array([-r * w * s, r * w * c, a * w * c]),
            -(w**2) * (p - [*self.centre, self.phi0]),
        )


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
    t = np.asarray(t, dtype=float)[:, None]
    e0, de0 = np.array(s.offset), np.array(s.rate_offset)
    wn, z = 1.0 / s.tau, s.zeta
    if abs(z - 1.0) < 1e-9:
        return np.exp(-wn * t) * (e0 + (de0 + wn * e0) * t)
    if z < 1.0:
        wd = wn * np.sqrt(1.0 - z * z)
        return np.exp(-z * wn * t) * (
            e0 * np.cos(wd * t) + (de0 + z * wn * e0) / wd * np.sin(wd * t)
        )
    r = wn * np.sqrt(z * z - 1.0)
    s1, s2 = -z * wn + r, -z * wn - r
    c1 = (de0 - s2 * e0) / (s1 - s2)
    return c1 * np.exp(s1 * t) + (e0 - c1) * np.exp(s2 * t)


def _check(mech: ClosedMechanism, s: TrackingSettings) -> None:
    if tuple(mech.output_coords) != ("x", "y", "rz"):
        raise InvalidInputError(
            f"platform tracking needs output (x, y, rz); {mech.name} has {list(mech.output_coords)}"
        )
    s.validate()


def _configuration(mech: ClosedMechanism, pose: np.ndarray, mode: str) -> np.ndarray:
    sols = {sol.mode: sol.q for sol in inverse_position(mech, pose).solutions}
    if mode not in sols:
        raise InvalidInputError(
            f"mode {mode!r} is not a working mode of {mech.name}; valid: {', '.join(sols)}"
        )
    return sols[mode]


def check_path(mech: ClosedMechanism, s: TrackingSettings, n: int = 73) -> dict[str, float]:
    """Classify n reference poses (working mode ``s.mode``); min singularity measures.

    Raises:
        UnreachablePoseError: a reference pose is outside the workspace.
        SingularConfigurationError: a reference pose is type-1 or type-2 singular.
    """
    _check(mech, s)
    m1 = m2 = np.inf
    for t in np.linspace(0.0, s.duration, n):
        c = classify(mech, _configuration(mech, s.reference(float(t))[0], s.mode))
        if c.label != "regular":
            raise SingularConfigurationError(
                f"{mech.name}: the reference is {c.label} singular at t = {t:.4g} s "
                f"(measures {c.measure_type1:.2e}, {c.measure_type2:.2e})"
            )
        m1, m2 = min(m1, c.measure_type1), min(m2, c.measure_type2)
    return {"min_measure_type1": float(m1), "min_measure_type2": float(m2)}


def control(
    mech: ClosedMechanism, s: TrackingSettings, t: float, q: np.ndarray, v: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(drive torques (3,) [N·m], reference pose) of the computed-torque law at (t, q, v)."""
    p_t, v_t, a_t = s.reference(t)
    pd, _, _ = output_drift(mech, q, v)
    kn, kc = 1.0 / s.tau**2, 2.0 * s.zeta / s.tau
    a_star = a_t + kc * (v_t - pd) + kn * (p_t - mech.output(q))
    a = acceleration_for_output(mech, q, v, a_star, s.baumgarte)
    return inverse_dynamics(mech, q, v, a)[0], p_t


def reference_torques(mech: ClosedMechanism, s: TrackingSettings, t: np.ndarray) -> np.ndarray:
    """Drive torques (N, 3) [N·m] on the exact reference (inverse position, velocity, ID)."""
    out = np.zeros((len(t), mech.dof))
    for i, ti in enumerate(t):
        p, pd, pdd = s.reference(float(ti))
        q = _configuration(mech, p, s.mode)
        v = velocity_for_output(mech, q, pd)
        out[i] = inverse_dynamics(mech, q, v, acceleration_for_output(mech, q, v, pdd))[0]
    return out


def simulate_tracking(mech: ClosedMechanism, s: TrackingSettings | None = None) -> TrackingResult:
    """Integrate the constrained dynamics under computed torque (module docstring)."""
    s = s or TrackingSettings()
    path = check_path(mech, s)
    p0, pd0, _ = s.reference(0.0)
    q0 = _configuration(mech, p0 + np.array(s.offset), s.mode)
    v0 = velocity_for_output(mech, q0, pd0 + np.array(s.rate_offset))
    n = mech.model.nv
    tau_full = np.zeros(n)

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        q, v = y[:n], y[n:]
        tau_full[mech.idx_driven] = control(mech, s, t, q, v)[0]
        return np.concatenate([v, forward_dynamics(mech, q, v, tau_full, s.baumgarte)[0]])

    t_eval = np.linspace(0.0, s.duration, s.samples)
    sol = solve_ivp(
        rhs, (0.0, s.duration), np.concatenate([q0, v0]), "DOP853", t_eval, rtol=1e-11, atol=1e-13
    )
    if not sol.success:
        raise SingularConfigurationError(f"{mech.name}: integration failed: {sol.message}")
    qs = sol.y[:n].T
    rows = [control(mech, s, t, y[:n], y[n:]) for t, y in zip(sol.t, sol.y.T, strict=True)]
    pose = np.array([mech.output(q) for q in qs])
    ref = np.array([r[1] for r in rows])
    err = pose - ref
    err[:, 2] = (err[:, 2] + np.pi) % (2.0 * np.pi) - np.pi
    res = np.array([np.max(np.abs(mech.closure_residual(q))) for q in qs])
    return TrackingResult(
        t=sol.t,
        q=qs,
        pose=pose,
        reference=ref,
        torques=np.array([r[0] for r in rows]),
        error=err,
        closure_residual=res,
        settings=s,
        info={"nfev": int(sol.nfev), "drives": list(mech.driven), **path},
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
