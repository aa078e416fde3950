"""One computed-torque law for serial and closed mechanisms (papers 000 and 004).

Task space: with the task value x (a tool-frame position, or a loop output), its rate ẋ
and the reference (x_T, ẋ_T, ẍ_T), the commanded task acceleration is

.. math:: a^* = f\\,\\ddot x_T + K_n (x_T - x) + K_c (\\dot x_T - \\dot x)

(f = 1 with feed-forward). Paper 004 writes the error dynamics as
:math:`\\tau^2 \\ddot\\Delta + 2\\zeta\\tau\\dot\\Delta + \\Delta = 0`, i.e. K_n = 1/τ²,
K_c = 2ζ/τ. Paper 000 prints a = K_n (x − x_t) + K_c (v_t − v): ``printed_sign=True``
simulates that sign (ë + K_c ė − K_n e = …, unstable).

* Serial: J q̈ = a* − J̇ q̇ over the coordinates the task depends on (J from the family's
  closed form or Pinocchio, :mod:`.task`); the other coordinates are held at the posture
  (the family's ``home`` configuration, e.g. the RCM mechanisms' wrist at 0) with the same
  gains (a redundant J takes the minimum-norm solution plus that posture in its null space).
  Efforts τ = RNEA(q, q̇, q̈*) on the *controller's* model.
* Closed: [J_c; J_x] q̈ = [−γ − Baumgarte; a* − J̇_x q̇] and [Sᵀ J_cᵀ][τ; λ] = M q̈ + b
  (:mod:`rcm_pin.dynamics.constrained`). :class:`DriveSwitching` hands the torques to the
  extra drives while the main drives' type-2 measure is below a band (paper 004's
  five-bar).
* ``space="joint"`` (serial): the reference is mapped to (q_r, q̇_r, q̈_r) by the task's
  inverse and :math:`\\ddot q^* = f\\ddot q_r + K_n (q_r - q) + K_c (\\dot q_r - \\dot q)`.

Efforts are clipped to ``limits`` (per drive, or one number for every drive).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
import pinocchio as pin

from rcm_pin.control.capabilities import TaskKinematics
from rcm_pin.control.references import Reference
from rcm_pin.control.task import task_kinematics, task_output
from rcm_pin.dynamics import constrained as cd
from rcm_pin.errors import InvalidInputError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output
from rcm_pin.rotations import wrap_angle

if TYPE_CHECKING:
    from rcm_pin.control.closed_hot_path import ClosedLaw
    from rcm_pin.control.hot_path import SerialLaw

SPACES = ("task", "joint")


#: Fastest error dynamics accepted [rad/s]: K_n <= MAX_RATE², K_c <= 2 MAX_RATE (gains of
#: 1e300 made the explicit integrator step at ~1e-150 s: past two minutes for 0.05 s).
MAX_RATE = 1e4
#: Slowest time constant τ accepted by :meth:`Gains.from_tau_zeta` [s].
MAX_TAU = 1e4


@dataclass(frozen=True)
class Gains:
    """Feedback gains of the error dynamics ë + K_c ė + K_n e = 0.

    Attributes:
        kn: position gain K_n [1/s²].
        kc: velocity gain K_c [1/s].

    Raises:
        InvalidInputError: K_n ≤ 0, K_c < 0, not finite, or faster than :data:`MAX_RATE`.
    """

    kn: float
    kc: float

    def __post_init__(self) -> None:
        if not (np.isfinite(self.kn) and np.isfinite(self.kc) and self.kn > 0 and self.kc >= 0):
            raise InvalidInputError(
                f"gains Kn={self.kn}, Kc={self.kc} are invalid; valid: Kn > 0, Kc >= 0"
            )
        if self.kn > MAX_RATE**2 or self.kc > 2.0 * MAX_RATE:
            raise InvalidInputError(
                f"gains Kn={self.kn:g}, Kc={self.kc:g} are too fast; valid: Kn <= "
                f"{MAX_RATE**2:g} [1/s^2], Kc <= {2 * MAX_RATE:g} [1/s] (error dynamics faster "
                f"than {MAX_RATE:g} rad/s make the explicit integrator's steps shorter than "
                "0.1 ms; gains of 1e300 ran past two minutes for 0.05 s simulated)"
            )

    @classmethod
    def from_tau_zeta(cls, tau: float, zeta: float) -> Gains:
        """Gains of τ² Δ̈ + 2ζτ Δ̇ + Δ = 0 (paper 004): K_n = 1/τ², K_c = 2ζ/τ.

        Raises:
            InvalidInputError: τ ≤ 0, ζ < 0, τ outside 1/:data:`MAX_RATE` to
                :data:`MAX_TAU`, or gains over the bounds of :class:`Gains`.
        """
        if not (np.isfinite(tau) and np.isfinite(zeta) and tau > 0 and zeta >= 0):
            raise InvalidInputError(
                f"tau={tau}, zeta={zeta} are invalid; valid: tau > 0 [s], zeta >= 0"
            )
        if not 1.0 / MAX_RATE <= tau <= MAX_TAU:
            raise InvalidInputError(
                f"tau={tau:g} s is outside the valid range; valid: {1.0 / MAX_RATE:g} to "
                f"{MAX_TAU:g} s (a faster error dynamics makes the integrator's steps shorter "
                "than 0.1 ms)"
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


@dataclass(frozen=True)
class DriveSwitching:
    """Closed mechanisms: use the extra drives while σ_min/σ_max(A) of the main drives
    is below ``band`` (paper 004's crossing of a type-2 singularity)."""

    band: float = 0.2


class Effort(NamedTuple):
    """Efforts of one control step.

    Attributes:
        tau_full: generalised efforts (nv,) applied to the plant [N·m, N].
        tau: efforts of the active drives [N·m, N].
        saturated: a limit clipped some effort.
        alternate: the extra drives are active (drive switching).
        measure: type-2 measure of the main drives (NaN without switching).
    """

    tau_full: np.ndarray
    tau: np.ndarray
    saturated: bool
    alternate: bool
    measure: float


@dataclass(frozen=True, eq=False)
class ComputedTorque:
    """The computed-torque controller (module docstring).

    Attributes:
        model: the controller's model of the mechanism (may differ from the plant).
        reference: desired task trajectory.
        gains: K_n, K_c.
        space: ``"task"`` or ``"joint"`` (serial only).
        feedforward: add the reference acceleration.
        printed_sign: use paper 000's printed position term K_n (x − x_t).
        limits: drive effort limits (per drive, or a scalar) [N·m, N]; None: none.
        task: output coordinates tracked (default: tool position / loop output).
        baumgarte: (ω [rad/s], ζ) of the closure stabilisation (closed mechanisms).
        switching: drive switching (closed mechanisms with extra drives).
    """

    model: Mechanism
    reference: Reference
    gains: Gains
    space: str = "task"
    feedforward: bool = True
    printed_sign: bool = False
    limits: np.ndarray | float | None = None
    task: tuple[str, ...] | None = None
    baumgarte: tuple[float, float] = (50.0, 1.0)
    switching: DriveSwitching | None = None
    _task: Output = field(init=False, repr=False)
    _kin: TaskKinematics | None = field(init=False, repr=False)
    posture: np.ndarray = field(init=False, repr=False)  #: where the other coordinates are held

    def __post_init__(self) -> None:
        if self.space not in SPACES:
            raise InvalidInputError(f"space {self.space!r} is invalid; valid: task, joint")
        mech = self.model
        task = task_output(mech, self.task)
        kin = None if mech.loops is not None else task_kinematics(mech, task)
        if mech.loops is not None and self.space == "joint":
            raise InvalidInputError("space='joint' needs a serial mechanism; valid: 'task'")
        if self.switching is not None and (mech.loops is None or not mech.loops.extra_drives):
            raise InvalidInputError(f"drive switching needs extra drives; {mech.name} has none")
        if kin is not None and self.space == "joint" and kin.inverse is None:
            raise InvalidInputError(
                f"space='joint' needs the task's inverse kinematics; {mech.name} has none"
            )
        object.__setattr__(self, "_task", task)
        object.__setattr__(self, "_kin", kin)
        object.__setattr__(self, "posture", mech.home)  # serial: the others held there

    @property
    def task_output(self) -> Output:
        """The tracked output coordinates."""
        return self._task

    @property
    def kinematics(self) -> TaskKinematics | None:
        """Task kinematics of a serial mechanism (None for closed ones)."""
        return self._kin

    @property
    def kpos(self) -> float:
        """Signed position gain: K_n, or −K_n with the printed sign."""
        return -self.gains.kn if self.printed_sign else self.gains.kn

    def task_error(self, x_t: np.ndarray, x: np.ndarray) -> np.ndarray:
        """x_t − x in the task coordinates [m, rad], angles wrapped where they cross ±π."""
        e = x_t - x
        ang = self._task.angular
        if ang.any():  # wrap an angle error only where it crosses ±π
            e[ang] = np.where(np.abs(e[ang]) > np.pi, wrap_angle(e[ang]), e[ang])
        return e

    def acceleration(self, t: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Commanded accelerations q̈* (nv,) [rad/s², m/s²]."""
        g, ff = self.gains, float(self.feedforward)
        x_t, v_t, a_t = self.reference.evaluate(t)
        if self._kin is None:  # closed mechanism
            x, xd, _, _ = cd.output_motion(self.model, q, v, self._task)
            a_star = ff * a_t + self.kpos * self.task_error(x_t, x) + g.kc * (v_t - xd)
            return cd.acceleration_for_output(self.model, q, v, a_star, self.baumgarte, self._task)
        kin, cols = self._kin, self._kin.joints
        qdd = -g.kn * (q - self.posture) - g.kc * v  # hold the others at the posture
        if self.space == "task":
            J = kin.jacobian(q)
            a_star = (
                ff * a_t
                + self.kpos * self.task_error(x_t, kin.position(q))
                + g.kc * (v_t - J @ v[cols])
            )
            rhs = a_star - kin.bias(q, v)
            if J.shape[0] == J.shape[1]:
                qdd[cols] = np.linalg.solve(J, rhs)
            else:  # redundant: minimum norm plus the posture in the null space
                pinv = np.linalg.pinv(J)
                qdd[cols] = pinv @ rhs + (np.eye(len(cols)) - pinv @ J) @ qdd[cols]
        else:
            qr, qrd, qrdd = self.joint_reference(t)
            qdd[cols] = ff * qrdd + self.kpos * (qr - q[cols]) + g.kc * (qrd - v[cols])
        return qdd

    def joint_reference(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(q_r, q̇_r, q̈_r) of the task's coordinates: q̇_r = J⁻¹ẋ_T, q̈_r = J⁻¹(ẍ_T − J̇q̇_r)."""
        kin = self._kin
        if kin is None or kin.inverse is None:
            raise InvalidInputError("the joint reference needs the task's inverse kinematics")
        x, xd, xdd = self.reference.evaluate(t)
        q = np.zeros(self.model.nq)
        q[kin.joints] = kin.inverse(x)
        J = kin.jacobian(q)
        qd = np.zeros(self.model.nv)
        qd[kin.joints] = np.linalg.solve(J, xd)
        qdd = np.linalg.solve(J, xdd - kin.bias(q, qd))
        return q[kin.joints], qd[kin.joints], qdd

    def hot_path_law(self, plant: Mechanism) -> SerialLaw | ClosedLaw:
        """The law prepared once for :func:`~rcm_pin.control.simulate.simulate`'s
        right-hand side (no validation, no per-call objects; :mod:`.hot_path`)."""
        from rcm_pin.control.closed_hot_path import ClosedLaw
        from rcm_pin.control.hot_path import SerialLaw

        return SerialLaw(self) if self._kin is not None else ClosedLaw(self, plant)

    def effort(self, t: float, q: np.ndarray, v: np.ndarray) -> Effort:
        """Efforts of the law at (t, q, q̇), clipped to the limits."""
        mech, acc = self.model, self.acceleration(t, q, v)
        if mech.loops is None:
            tau = np.asarray(
                pin.rnea(mech.model, mech.data, mech.to_pin(q), mech.v_pin(v), mech.v_pin(acc))
            )[mech.v_index]
            clipped = tau if self.limits is None else np.clip(tau, -self.limits, self.limits)
            return Effort(clipped, clipped, bool(np.any(clipped != tau)), False, float("nan"))
        loops = mech.loops
        measure, alternate = float("nan"), False
        if self.switching is not None:
            from rcm_pin.analysis.loop_velocity import velocity_matrices

            measure = velocity_matrices(mech, q).measure_type2
            alternate = measure < self.switching.band
        drives = loops.extra_drives if alternate else loops.drives
        tau, _ = cd.inverse_dynamics(mech, q, v, acc, drives)
        clipped = tau if self.limits is None else np.clip(tau, -self.limits, self.limits)
        tau_full = np.zeros(mech.model.nv)
        tau_full[mech.joint_v(drives)] = clipped
        return Effort(tau_full, clipped, bool(np.any(clipped != tau)), alternate, measure)


def drive_limits(mech: Mechanism) -> np.ndarray:
    """The URDF effort limits of the drives (serial: every coordinate) [N·m, N]."""
    idx = mech.v_index if mech.loops is None else mech.loops.drive_v
    return np.asarray(mech.model.effortLimit)[idx].copy()


__all__ = ["SPACES", "ComputedTorque", "DriveSwitching", "Effort", "Gains", "drive_limits"]
