"""Nonlinear free vibrations with beats (paper 004): the translational 3-PPaPa on drive springs.

The free mechanism (drives as springs of stiffness c about a pose, gravity cancelled as in
:mod:`rcm_pin.dynamics.vibrations`) starts from rest with one output coordinate displaced
by ε; the constrained forward dynamics (KKT, Baumgarte) is integrated by scipy's DOP853 at
rtol 1e-12. The energy E = ½ q̇ᵀ M q̇ + ½ Σ c_i (q_a,i − q⁰_a,i)² is conserved (its relative
drift is reported); the modal energies E_j = ½ (η̇_j² + ω_j² η_j²) with
η = Φᵀ M_q (q_a − q⁰_a) are constant in the linear limit.

Pose (0.05, 0, 0) m in mode ++/++/++: the middle mode moves y and z only (its x entry is 0
by the legs' symmetry), so x(t) holds the other two modes and beats with period
T = 2π/|ω₃ − ω₁|, while the energy passes from x to y and z and back. The beat period is
measured as the mean spacing of the minima of x's envelope (Hilbert transform, interior
minima refined by a parabola).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.signal import hilbert

import rcm_pin
from rcm_pin.dynamics.tree import mass_matrix_pin
from rcm_pin.dynamics.vibrations import (
    Vibrations,
    natural_frequencies,
    spring_dynamics,
)
from rcm_pin.errors import SolverError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.studies.working_mode import configuration_at

NAME = "translational_3ppapa"


@dataclass(frozen=True)
class BeatSettings:
    """Pose, excitation and integration (SI units)."""

    pose: tuple[float, float, float] = (0.05, 0.0, 0.0)  # [m]
    mode: str = "++/++/++"
    stiffness: float = 1e5  # [N/m]
    amplitude: float = 1e-4  # ε: initial displacement of the output coordinate [m]
    coordinate: int = 0  # which output coordinate is displaced (0: x)
    beats: float = 2.6  # duration in beat periods 2π/|ω₃ − ω₁|
    dt: float = 5e-4  # sample step [s]
    rtol: float = 1e-12
    atol: float = 1e-15


@dataclass(frozen=True)
class BeatRun:
    """t (N,) [s], output (N, 3) [m], modal energies (N, 3) [J], energy (N,) [J]."""

    t: np.ndarray
    output: np.ndarray
    modal_energy: np.ndarray
    energy: np.ndarray
    vibrations: Vibrations
    equilibrium: np.ndarray

    @property
    def energy_drift(self) -> float:
        """max |E(t) − E(0)| / E(0)."""
        return float(np.max(np.abs(self.energy - self.energy[0])) / self.energy[0])

    @property
    def linear_beat_period(self) -> float:
        """2π/|ω₃ − ω₁| [s] of the frequency equation."""
        w = self.vibrations.frequencies
        return float(2.0 * np.pi / abs(w[2] - w[0]))

    def beat_period(self, coordinate: int = 0) -> float:
        """Mean spacing of the interior minima of the envelope of one output coordinate [s].

        Raises:
            SolverError: fewer than two interior minima (run too short).
        """
        u = self.output[:, coordinate] - self.equilibrium[coordinate]
        env = np.abs(hilbert(u - u.mean()))
        n, dt = len(env), float(self.t[1] - self.t[0])
        guard = int(0.15 * self.linear_beat_period / dt)
        win = max(3, int(0.3 * self.linear_beat_period / dt))
        mins = []
        for i in range(guard, n - guard):
            lo, hi = max(0, i - win), min(n, i + win + 1)
            if env[i] == env[lo:hi].min():
                a, b, c = env[i - 1], env[i], env[i + 1]
                den = a - 2.0 * b + c
                mins.append(self.t[i] + (0.5 * dt * (a - c) / den if den != 0 else 0.0))
        if len(mins) < 2:
            raise SolverError(f"{len(mins)} envelope minima; valid: a run of >= 2 beat periods")
        return float(np.mean(np.diff(mins)))


def _energies(
    mech: Mechanism, vib: Vibrations, q0: np.ndarray, y: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(total energy (N,), modal energies (N, k)) of states y (N, 2 nv)."""
    loops = mech.require_loops()
    n = mech.model.nv
    data = mech.model.createData()
    c, phi, m_q, w = vib.stiffness, vib.modes, vib.mass, vib.frequencies
    total = np.zeros(len(y))
    modal = np.zeros((len(y), len(c)))
    for i, yi in enumerate(y):
        q, v = yi[:n], yi[n:]
        dqa = q[loops.drive_q] - q0[loops.drive_q]
        total[i] = 0.5 * v @ mass_matrix_pin(mech.model, data, q) @ v + 0.5 * c @ dqa**2
        eta, deta = phi.T @ m_q @ dqa, phi.T @ m_q @ v[loops.drive_v]
        modal[i] = 0.5 * (deta**2 + w**2 * eta**2)
    return total, modal


def run(s: BeatSettings | None = None) -> BeatRun:
    """Integrate the free vibrations (module docstring).

    Raises:
        SolverError: the integrator failed.
    """
    s = s or BeatSettings()
    mech = rcm_pin.load(NAME)
    pose = np.array(s.pose)
    q0, _ = configuration_at(mech, pose, s.mode)
    vib = natural_frequencies(mech, q0, s.stiffness)
    start = pose.copy()
    start[s.coordinate] += s.amplitude
    q_start, _ = configuration_at(mech, start, s.mode)
    n = mech.model.nv
    f = spring_dynamics(mech, q0, vib.stiffness, (50.0, 1.0))
    w = vib.frequencies
    duration = s.beats * 2.0 * np.pi / abs(w[2] - w[0])
    t_eval = np.arange(0.0, duration, s.dt)
    sol = solve_ivp(
        lambda _t, y: f(y),
        (0.0, t_eval[-1]),
        np.r_[q_start, np.zeros(n)],
        method="DOP853",
        t_eval=t_eval,
        rtol=s.rtol,
        atol=s.atol,
    )
    if not sol.success:
        raise SolverError(f"{NAME}: free-vibration integration failed: {sol.message}")
    y = sol.y.T
    out = np.array([mech.output_value(yi[:n]) for yi in y])
    energy, modal = _energies(mech, vib, q0, y)
    return BeatRun(sol.t, out, modal, energy, vib, pose)


def figure(r: BeatRun, path: Path) -> None:
    """PNG: output coordinates (displacements) and modal energies over time."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 1, figsize=(10.8, 6), sharex=True, layout="constrained")
    # y and z move (almost) alike: z is dashed so that it does not hide y
    for i, (lab, ls) in enumerate(zip("xyz", ("-", "-", (0, (3, 2))), strict=True)):
        axes[0].plot(r.t, 1e6 * (r.output[:, i] - r.equilibrium[i]), lw=0.9, ls=ls, label=lab)
    axes[0].set_ylabel("output displacement [µm]")
    axes[0].set_title(
        f"free vibrations: beat period {r.beat_period():.4f} s, 2π/|ω₃ − ω₁| = "
        f"{r.linear_beat_period:.4f} s; energy drift {r.energy_drift:.1e}"
    )
    for j in range(r.modal_energy.shape[1]):
        axes[1].plot(r.t, r.modal_energy[:, j], label=f"mode {j + 1}")
    axes[1].plot(r.t, r.energy, "k--", lw=0.8, label="total")
    axes[1].set_ylabel("energy [J]")
    axes[1].set_xlabel("t [s]")
    for ax in axes:  # beside the axes: inside, it covered the curves
        ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.savefig(path, dpi=110)
    plt.close(fig)


__all__ = ["NAME", "BeatRun", "BeatSettings", "figure", "run"]
