"""Computed-torque tracking of a Cartesian tool-centre trajectory (papers 000 and 004).

Task space (``space="task"``): with the tool centre p = q3 e4, ṗ = J q̇, the commanded
point acceleration is

.. math:: a^* = a_t + K_n (p_t - p) + K_c (v_t - \\dot p), \\qquad
          \\ddot q^*_{1..3} = J^{-1} (a^* - h(q, \\dot q)),

joint space (``space="joint"``): the reference (q_r, q̇_r, q̈_r) of q1..q3 comes from the
inverse kinematics and :math:`\\ddot q^* = \\ddot q_r + K_n (q_r - q) + K_c (\\dot q_r -
\\dot q)`. Extra coordinates q4.. are held at 0 with the same gains. The drive efforts
are :math:`\\tau = \\hat M(q) \\ddot q^* + \\hat b(q, \\dot q)` on the *controller's*
model (RNEA), clipped to the drive limits. With a perfect model and no saturation the
error e = p_t − p obeys :math:`\\ddot e + K_c \\dot e + K_n e = (1 - f)\\, a_t`
(f = 1 with feed-forward). Paper 004 writes it as
:math:`\\tau^2 \\ddot\\Delta + 2\\zeta\\tau\\dot\\Delta + \\Delta = 0`, i.e.
K_n = 1/τ², K_c = 2ζ/τ. Paper 000 prints a = K_n (x − x_t) + K_c (v_t − v):
``printed_sign=True`` simulates that sign (error dynamics ë + K_c ė − K_n e = …,
unstable).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin
from scipy.integrate import solve_ivp

from rcm_pin.dynamics import v_index
from rcm_pin.errors import InvalidInputError
from rcm_pin.mechanism import Mechanism
from rcm_pin.trajectories import (
    CartesianTrajectory,
    joint_reference,
    point_bias,
    point_jacobian,
    point_position,
)

SPACES = ("task", "joint")


@dataclass(frozen=True)
class Gains:
    """Feedback gains of a ∂² error dynamics ë + K_c ė + K_n e = 0.

    Attributes:
        kn: position gain K_n [1/s²].
        kc: velocity gain K_c [1/s].
    """

    kn: float
    kc: float

    def __post_init__(self) -> None:
        if not (np.isfinite(self.kn) and np.isfinite(self.kc) and self.kn > 0 and self.kc >= 0):
            raise InvalidInputError(
                f"gains Kn={self.kn}, Kc={self.kc} are invalid; valid: Kn > 0, Kc >= 0"
            )

    @classmethod
    def from_tau_zeta(cls, tau: float, zeta: float) -> Gains:
        """Gains of τ² Δ̈ + 2ζτ Δ̇ + Δ = 0 (paper 004): K_n = 1/τ², K_c = 2ζ/τ.

        Raises:
            InvalidInputError: τ ≤ 0 or ζ < 0.
        """
        if not (np.isfinite(tau) and np.isfinite(zeta) and tau > 0 and zeta >= 0):
            raise InvalidInputError(
                f"tau={tau}, zeta={zeta} are invalid; valid: tau > 0 [s], zeta >= 0"
            )
        return cls(kn=1.0 / tau**2, kc=2.0 * zeta / tau)

    @property
    def tau(self) -> float:
        """Time constant τ = 1/√K_n [s]."""
        return float(1.0 / np.sqrt(self.kn))

    @property
    def zeta(self) -> float:
        """Damping ratio ζ = K_c τ / 2 [-]."""
        return 0.5 * self.kc * self.tau


@dataclass(frozen=True, eq=False)
class ComputedTorque:
    """Computed-torque controller (module docstring).

    Attributes:
        model: the controller's model of the mechanism (may differ from the plant).
        trajectory: desired tool-centre trajectory.
        gains: K_n, K_c.
        space: ``"task"`` (Cartesian error) or ``"joint"`` (error of q1..q3 from the IK).
        feedforward: add the reference acceleration.
        printed_sign: use paper 000's printed position term K_n (x − x_t).
        limits: drive effort limits (n,) [N·m, N]; None: no saturation.
    """

    model: Mechanism
    trajectory: CartesianTrajectory
    gains: Gains
    space: str = "task"
    feedforward: bool = True
    printed_sign: bool = False
    limits: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.space not in SPACES:
            raise InvalidInputError(f"space {self.space!r} is invalid; valid: task, joint")
        if self.model.nq < 3:
            raise InvalidInputError(f"{self.model.name} has {self.model.nq} < 3 coordinates")

    @property
    def kpos(self) -> float:
        """Signed position gain: K_n, or −K_n with the printed sign."""
        return -self.gains.kn if self.printed_sign else self.gains.kn

    def acceleration(self, t: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Commanded joint accelerations q̈* (n,) [rad/s², m/s²]."""
        g, ff, traj = self.gains, float(self.feedforward), self.trajectory
        qdd = -g.kn * q - g.kc * v  # hold q4.. at zero
        if self.space == "task":
            J = point_jacobian(q)
            a_star = (
                ff * traj.acceleration(t)
                + self.kpos * (traj.position(t) - point_position(q))
                + g.kc * (traj.velocity(t) - J @ v[:3])
            )
            qdd[:3] = np.linalg.solve(J, a_star - point_bias(q, v))
        else:
            qr, qrd, qrdd = joint_reference(traj, t)
            qdd[:3] = ff * qrdd + self.kpos * (qr - q[:3]) + g.kc * (qrd - v[:3])
        return qdd

    def effort(self, t: float, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, bool]:
        """Drive efforts τ (n,) [N·m, N] and whether a limit clipped them."""
        model = self.model
        idx = v_index(model)
        qp = model.to_pin(q)
        vp = np.zeros(model.model.nv)
        ap = np.zeros(model.model.nv)
        vp[idx] = v
        ap[idx] = self.acceleration(t, q, v)
        tau = np.asarray(pin.rnea(model.model, model.data, qp, vp, ap))[idx]
        if self.limits is None:
            return tau, False
        clipped = np.clip(tau, -self.limits, self.limits)
        return clipped, bool(np.any(clipped != tau))


def drive_limits(mech: Mechanism) -> np.ndarray:
    """The URDF effort limits in coordinate order (n,) [N·m, N]."""
    return np.asarray(mech.model.effortLimit)[v_index(mech)].copy()


def linear_error(
    gains: Gains,
    e0: np.ndarray,
    de0: np.ndarray,
    t: np.ndarray,
    forcing: CartesianTrajectory | None = None,
    printed_sign: bool = False,
) -> np.ndarray:
    """Prediction of the error e = p_t − p by the linear error dynamics.

    .. math:: \\ddot e + K_c \\dot e \\pm K_n e = a_t(t)\\ (\\text{without feed-forward})
              \\text{ or } 0

    Args:
        gains: K_n, K_c.
        e0: initial error (k,) [m].
        de0: initial error rate (k,) [m/s].
        t: increasing output times (N,) [s], t[0] the initial time.
        forcing: the trajectory whose acceleration drives the error (no feed-forward);
            None with feed-forward.
        printed_sign: −K_n instead of K_n (paper 000's printed law).

    Returns:
        e(t) (N, k) [m].
    """
    e0, de0 = np.atleast_1d(np.asarray(e0, float)), np.atleast_1d(np.asarray(de0, float))
    k = e0.size
    kpos = -gains.kn if printed_sign else gains.kn

    def rhs(time: float, y: np.ndarray) -> np.ndarray:
        f = forcing.acceleration(time)[:k] if forcing is not None else 0.0
        return np.concatenate([y[k:], f - gains.kc * y[k:] - kpos * y[:k]])

    sol = solve_ivp(
        rhs,
        (t[0], t[-1]),
        np.concatenate([e0, de0]),
        method="DOP853",
        t_eval=t,
        rtol=1e-12,
        atol=1e-14,
    )
    return np.asarray(sol.y[:k].T)
