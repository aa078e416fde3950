"""Closed-loop and free simulation on the Pinocchio forward dynamics (scipy ``solve_ivp``).

The plant integrates :math:`\\ddot q = M(q)^{-1} (\\tau - b(q, \\dot q))` (Cholesky; see
:mod:`rcm_pin.dynamics`) with the state y = (q, q̇) in Mechanism coordinates.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin
from scipy.integrate import solve_ivp

from rcm_pin.control import ComputedTorque, Gains
from rcm_pin.dynamics import solve_mass, v_index
from rcm_pin.errors import InvalidInputError
from rcm_pin.mechanism import Mechanism
from rcm_pin.trajectories import point_ik, point_jacobian, point_position


@dataclass(frozen=True, eq=False)
class SimulationResult:
    """A simulated run, sampled on a uniform grid.

    Attributes:
        mechanism: plant name.
        t: times (N,) [s].
        q: coordinates (N, n) [rad, m].
        v: velocities (N, n) [rad/s, m/s].
        tau: drive efforts (N, n) [N·m, N].
        saturated: whether a drive limit clipped τ at each sample (N,).
        p: tool centre (N, 3) [m].
        p_ref: desired tool centre (N, 3) [m] (NaN without a controller).
        v_tool: tool-centre velocity (N, 3) [m/s].
        v_ref: desired tool-centre velocity (N, 3) [m/s].
        status: ``"completed"`` or the terminal event that stopped the run.
        gains: controller gains (None for a free run).
        wall_time: integration wall time [s].
        nfev: right-hand-side evaluations.
    """

    mechanism: str
    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    tau: np.ndarray
    saturated: np.ndarray
    p: np.ndarray
    p_ref: np.ndarray
    v_tool: np.ndarray
    v_ref: np.ndarray
    status: str
    gains: Gains | None
    wall_time: float
    nfev: int

    @property
    def error(self) -> np.ndarray:
        """Tracking error e = p_ref − p (N, 3) [m]."""
        return self.p_ref - self.p

    @property
    def error_rate(self) -> np.ndarray:
        """ė = v_ref − ṗ (N, 3) [m/s]."""
        return self.v_ref - self.v_tool

    def steady_error(self, t_from: float) -> np.ndarray:
        """max |e| per axis over t ≥ t_from (3,) [m]."""
        mask = self.t >= t_from
        return np.max(np.abs(self.error[mask]), axis=0) if mask.any() else np.full(3, np.nan)

    def rms_error(self) -> float:
        """RMS of |e| over the run [m]."""
        return float(np.sqrt(np.mean(np.sum(self.error**2, axis=1))))

    def summary(self, t_steady: float | None = None) -> dict[str, Any]:
        """JSON-ready summary (status, errors [m], peak efforts, run statistics)."""
        t_steady = self.t[-1] / 2 if t_steady is None else t_steady
        return {
            "mechanism": self.mechanism,
            "status": self.status,
            "duration": float(self.t[-1]),
            "gains": None if self.gains is None else {"Kn": self.gains.kn, "Kc": self.gains.kc},
            "rms_error": self.rms_error(),
            "steady_error": self.steady_error(t_steady).tolist(),
            "steady_from": float(t_steady),
            "peak_effort": np.max(np.abs(self.tau), axis=0).tolist(),
            "saturated_fraction": float(np.mean(self.saturated)),
            "wall_time": self.wall_time,
            "nfev": self.nfev,
        }


class _Plant:
    """Fast forward dynamics of a Mechanism (no per-call validation)."""

    def __init__(self, mech: Mechanism) -> None:
        self.mech, self.idx, self.n = mech, v_index(mech), mech.nq
        self.data = mech.model.createData()

    def accel(self, q: np.ndarray, v: np.ndarray, tau: np.ndarray) -> np.ndarray:
        model, idx = self.mech.model, self.idx
        qp = self.mech.to_pin(q)
        vp = np.zeros(model.nv)
        vp[idx] = v
        M = np.asarray(pin.crba(model, self.data, qp, pin.Convention.WORLD))
        M = np.triu(M) + np.triu(M, 1).T
        b = np.asarray(pin.nonLinearEffects(model, self.data, qp, vp))
        return solve_mass(M[np.ix_(idx, idx)], tau - b[idx])


def initial_state(mech: Mechanism, p0: np.ndarray) -> np.ndarray:
    """q with q1..q3 from the principal inverse kinematics of p0 and q4.. = 0."""
    q = np.zeros(mech.nq)
    q[:3] = point_ik(p0)
    return q


def simulate(
    plant: Mechanism,
    controller: ComputedTorque | None,
    duration: float,
    q0: np.ndarray | None = None,
    v0: np.ndarray | None = None,
    samples: int = 1001,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    method: str = "DOP853",
    stop_error: float = 0.5,
    progress: bool = False,
) -> SimulationResult:
    """Integrate the plant under a controller (or with τ = 0 when ``controller`` is None).

    Args:
        plant: the "true" mechanism.
        controller: computed-torque controller (its model may differ from the plant).
        duration: simulated time [s].
        q0: initial coordinates (n,) [rad, m]; default: IK of the trajectory's start.
        v0: initial velocities (n,); default zero.
        samples: output samples on a uniform grid.
        rtol: relative tolerance of ``solve_ivp``.
        atol: absolute tolerance.
        method: ``solve_ivp`` method.
        stop_error: stop when |e| exceeds this [m] (diverging runs); also stops when
            q3 < 1 mm or cos q2 < 0.01 (leaving the regular region).
        progress: show a tqdm bar over simulated time.

    Returns:
        The :class:`SimulationResult`.

    Raises:
        InvalidInputError: duration ≤ 0, bad q0 / v0, or no q0 and no controller.
    """
    if not (np.isfinite(duration) and duration > 0):
        raise InvalidInputError(f"duration {duration} is invalid; valid: > 0 [s]")
    n = plant.nq
    if q0 is None:
        if controller is None:
            raise InvalidInputError("q0 is required without a controller")
        traj = controller.trajectory
        q0 = initial_state(plant, np.asarray(traj.start or traj.position(0.0)))
    q0 = plant.check_q(q0, "q0")
    v0 = np.zeros(n) if v0 is None else plant.check_q(v0, "v0")
    fd = _Plant(plant)
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(
            total=duration,
            desc=f"simulate {plant.name}",
            bar_format="{l_bar}{bar}| {n:.2f}/{total:.2f} s simulated [{elapsed}]",
        )
    shown = [0.0]

    def effort(t: float, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, bool]:
        return (np.zeros(n), False) if controller is None else controller.effort(t, q, v)

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        q, v = y[:n], y[n:]
        if bar is not None and t > shown[0] + duration / 200:
            bar.update(round(t - shown[0], 6))
            shown[0] = t
        return np.concatenate([v, fd.accel(q, v, effort(t, q, v)[0])])

    def ev_q3(t: float, y: np.ndarray) -> float:
        return float(y[2] - 1e-3)

    def ev_cos(t: float, y: np.ndarray) -> float:
        return float(np.cos(y[1]) - 1e-2)

    def ev_err(t: float, y: np.ndarray) -> float:
        if controller is None:
            return 1.0
        return float(
            stop_error - np.linalg.norm(controller.trajectory.position(t) - point_position(y))
        )

    events = [ev_q3, ev_cos, ev_err] if n >= 3 and plant.rcm_frame_id >= 0 else []
    for ev in events:
        ev.terminal = True  # type: ignore[attr-defined]
    t_eval = np.linspace(0.0, duration, samples)
    start = time.perf_counter()
    sol = solve_ivp(
        rhs,
        (0.0, duration),
        np.concatenate([q0, v0]),
        method=method,
        t_eval=t_eval,
        rtol=rtol,
        atol=atol,
        events=events or None,
    )
    wall = time.perf_counter() - start
    if bar is not None:
        bar.update(max(round(duration - shown[0], 6), 0.0))
        bar.close()
    names = ["q3 < 1 mm", "cos q2 < 0.01", f"|e| > {stop_error} m"]
    status = "completed"
    if sol.status == 1:
        status = "stopped: " + next(nm for nm, te in zip(names, sol.t_events) if len(te))
    elif sol.status < 0:
        status = f"failed: {sol.message}"
    return _result(
        plant, controller, sol.t, sol.y[:n].T, sol.y[n:].T, status, wall, sol.nfev, effort
    )


def _result(plant, controller, t, q, v, status, wall, nfev, effort) -> SimulationResult:
    N = len(t)
    tau = np.zeros_like(q)
    sat = np.zeros(N, dtype=bool)
    p = np.zeros((N, 3))
    vt = np.zeros((N, 3))
    for i in range(N):
        tau[i], sat[i] = effort(t[i], q[i], v[i])
        p[i] = point_position(q[i])
        vt[i] = point_jacobian(q[i]) @ v[i, :3]
    if controller is None:
        p_ref = v_ref = np.full((N, 3), np.nan)
    else:
        p_ref = controller.trajectory.position(t)
        v_ref = controller.trajectory.velocity(t)
    return SimulationResult(
        mechanism=plant.name,
        t=t,
        q=q,
        v=v,
        tau=tau,
        saturated=sat,
        p=p,
        p_ref=p_ref,
        v_tool=vt,
        v_ref=v_ref,
        status=status,
        gains=None if controller is None else controller.gains,
        wall_time=wall,
        nfev=nfev,
    )
