"""Paper 004's control example on the translational 3-PPaPa: computed torque on the closed loop.

Reference (the paper's amplitudes, read as metres): x_T = 0.1 sin ωt, y_T = 0.12 sin ωt,
z_T = 0.15 sin ωt about the home pose (the origin), ω = 2π rad/s (one period per second; the
paper gives no ω). The error Δ = x − x_T obeys τ²Δ̈ + 2ζτΔ̇ + Δ = 0 (K_n = 1/τ², K_c = 2ζ/τ)
under the one computed-torque law (:class:`rcm_pin.control.computed_torque.ComputedTorque`:
[J_c; J_x] q̈ = [−γ; a* − J̇_x q̇], drive forces from [Sᵀ J_cᵀ][F; λ] = M q̈ + b), integrated
by the one :func:`rcm_pin.control.simulate.simulate` on the KKT dynamics.

Transient time (the project's definition): the time after which |Δ(t)| ≤ 5 % of |Δ(0)| for
good, for an initial position error with zero rate error. With ζ = 1 (critical damping, no
overshoot) Δ(t) = Δ(0)(1 + t/τ)e^{−t/τ}, so t_tr = s₅ τ with (1 + s₅)e^{−s₅} = 0.05
(s₅ ≈ 4.744): t_tr = 0.06 s gives τ ≈ 0.01265 s (:func:`tau_for_transient`).

Model mismatch (:func:`mismatch_table`): the plant is the nominal mechanism; the
controller's model has the input-link (slider) masses neglected (1e-9 kg: the xacro range
excludes 0), the output (platform) mass ±10 %, the input-link length l1 (xacro ``side_1``,
the crank of the parallelogram the slider carries; one argument for the three legs) ±1 mm,
and combinations. The controller reads the plant's full state and computes x with its own
model; its closure stabilisation is off (a mismatched length leaves a constant residual in
its model that it must not try to close). The figure of merit is the change of the
position error, max_t |Δ_mm(t) − Δ_0(t)| / max_t |Δ_0(t)| in % (our reading of the paper's
"at most 3 %": relative to the error of the perfect model).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.optimize import brentq

import rcm_pin
from rcm_pin.control.computed_torque import ComputedTorque, Gains
from rcm_pin.control.linear import error_response
from rcm_pin.control.references import CartesianTrajectory
from rcm_pin.control.simulate import SimulationOptions, simulate
from rcm_pin.dynamics.constrained import velocity_for_output
from rcm_pin.errors import SolverError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.studies.working_mode import configuration_at

NAME = "translational_3ppapa"
#: The paper's amplitudes of x_T, y_T, z_T [m].
AMPLITUDE = (0.1, 0.12, 0.15)
#: The paper's transient time [s].
TRANSIENT = 0.06
#: Settling band of the transient-time definition [-].
BAND = 0.05


def settling_factor(zeta: float = 1.0, band: float = BAND) -> float:
    """s = t_tr/τ: the last time |Δ(t)|/|Δ(0)| = band for Δ̇(0) = 0 (ζ ≥ 1: monotone decay)."""
    if zeta < 1.0:
        raise ValueError("the transient-time definition here needs ζ >= 1 (no overshoot)")
    tau = 1.0

    def f(s: float) -> float:
        return float(error_response(np.array([s]), tau, zeta, np.ones(1), np.zeros(1))[0, 0]) - band

    return float(brentq(f, 1e-6, 200.0, xtol=1e-15))


def tau_for_transient(t_tr: float = TRANSIENT, zeta: float = 1.0) -> float:
    """τ [s] whose transient (5 % band, Δ̇(0) = 0) lasts t_tr [s]."""
    return t_tr / settling_factor(zeta)


@dataclass(frozen=True)
class ControlSettings:
    """The example's choices (SI units)."""

    omega: float = 2.0 * np.pi  # [rad/s]
    zeta: float = 1.0  # [-]
    transient: float = TRANSIENT  # [s]
    offset: tuple[float, float, float] = (0.004, -0.003, 0.005)  # initial position error [m]
    duration: float = 1.0  # [s]
    samples: int = 401
    mode: str = "++/++/++"  # working mode of the legs
    rtol: float = 1e-11
    atol: float = 1e-13

    @property
    def tau(self) -> float:
        """τ of the error dynamics [s]."""
        return tau_for_transient(self.transient, self.zeta)

    @property
    def reference(self) -> CartesianTrajectory:
        """x_T(t) = a ⊙ sin ωt."""
        return CartesianTrajectory("paper004_control", (0.0, 0.0, 0.0), AMPLITUDE, self.omega)


@dataclass(frozen=True)
class ControlRun:
    """One run: t [s] (N,), error Δ = x − x_T (N, 3) [m], drive forces (N, 3) [N]."""

    t: np.ndarray
    error: np.ndarray
    forces: np.ndarray
    closure_residual: float
    nfev: int

    def transient_time(self, band: float = BAND) -> float:
        """Measured t_tr [s]: the last crossing of |Δ(t)| = band·|Δ(0)| (linear
        interpolation between samples)."""
        r = np.linalg.norm(self.error, axis=1) / np.linalg.norm(self.error[0])
        above = np.flatnonzero(r > band)
        i = int(above[-1])
        if i + 1 >= len(r):
            return float("inf")
        return float(self.t[i] + (r[i] - band) / (r[i] - r[i + 1]) * (self.t[i + 1] - self.t[i]))

    def linear_deviation(self, s: ControlSettings) -> float:
        """max |Δ − Δ_linear| [m] (the closed-form error dynamics from the same start)."""
        return float(np.max(np.abs(self.error - linear_error(self.t, s))))


def linear_error(t: np.ndarray, s: ControlSettings) -> np.ndarray:
    """Δ(t) (N, 3) of τ²Δ̈ + 2ζτΔ̇ + Δ = 0 from Δ(0) = offset, Δ̇(0) = 0."""
    return error_response(t, s.tau, s.zeta, np.array(s.offset), np.zeros(3))


def run(
    s: ControlSettings | None = None, plant: Mechanism | None = None, model: Mechanism | None = None
) -> ControlRun:
    """Simulate the example: the plant (default: the catalogue's mechanism) under computed
    torque on ``model`` (default: the plant itself, a perfect model).

    Raises:
        SolverError: the integration stopped early.
    """
    s = s or ControlSettings()
    plant = plant or rcm_pin.load(NAME)
    model = model or plant
    ref = s.reference
    x0, xd0, _ = ref.evaluate(0.0)
    q0, _ = configuration_at(plant, x0 + np.array(s.offset), s.mode)
    v0 = velocity_for_output(plant, q0, xd0)
    ctrl = ComputedTorque(model, ref, Gains.from_tau_zeta(s.tau, s.zeta), baumgarte=(0.0, 0.0))
    res = simulate(
        plant,
        ctrl,
        s.duration,
        q0,
        v0,
        SimulationOptions(
            samples=s.samples, rtol=s.rtol, atol=s.atol, method="DOP853", stop_error=None
        ),
    )
    if not res.completed:
        raise SolverError(f"{plant.name}: the control example stopped: {res.status}")
    drives = plant.require_loops().drive_v
    return ControlRun(
        t=res.t,
        error=res.x - res.x_ref,
        forces=res.tau[:, drives],
        closure_residual=float(np.max(res.closure_residual)),
        nfev=int(res.nfev),
    )


#: Mismatch cases: label → xacro arguments of the controller's model (nominal: 1 kg sliders,
#: 0.5 kg platform, l1 = 0.5 m).
MISMATCH: dict[str, dict[str, str]] = {
    "perfect model": {},
    "input-link masses neglected": {"m_slider": "1e-9"},
    "output mass +10 %": {"m_platform": "0.55"},
    "output mass −10 %": {"m_platform": "0.45"},
    "input-link length +1 mm": {"side_1": "0.501"},
    "input-link length −1 mm": {"side_1": "0.499"},
    "masses neglected, output +10 %": {"m_slider": "1e-9", "m_platform": "0.55"},
    "output +10 %, length +1 mm": {"m_platform": "0.55", "side_1": "0.501"},
    "all three (neglected, +10 %, +1 mm)": {
        "m_slider": "1e-9",
        "m_platform": "0.55",
        "side_1": "0.501",
    },
}


def mismatch_table(
    s: ControlSettings | None = None, cases: dict[str, dict[str, str]] | None = None
) -> list[dict[str, Any]]:
    """One row per mismatch case: peak error after the transient [mm], change of the error
    vs the perfect model [% of its peak], peak drive force [N] (module docstring)."""
    s = s or ControlSettings()
    plant = rcm_pin.load(NAME)
    base = run(s, plant)
    peak0 = float(np.max(np.linalg.norm(base.error, axis=1)))
    after = base.t >= s.transient
    rows = []
    for label, args in (cases or MISMATCH).items():
        r = base if not args else run(s, plant, rcm_pin.load(NAME, trusted=False, **args))
        change = float(np.max(np.linalg.norm(r.error - base.error, axis=1)))
        rows.append(
            {
                "case": label,
                "controller_args": args,
                "error_after_transient_mm": 1e3
                * float(np.max(np.linalg.norm(r.error[after], axis=1))),
                "change_percent": 100.0 * change / peak0,
                "peak_force_N": float(np.max(np.abs(r.forces))),
            }
        )
    return rows


__all__ = [
    "AMPLITUDE",
    "MISMATCH",
    "ControlRun",
    "ControlSettings",
    "linear_error",
    "mismatch_table",
    "run",
    "settling_factor",
    "tau_for_transient",
]
