"""The right-hand side of :func:`rcm_pin.control.simulate.simulate` without per-call overhead.

Everything constant over a run is prepared once (Pinocchio ``Data`` objects, index arrays,
gains, limits, the reference's coefficients); a call validates nothing, builds no
dataclass or NamedTuple and solves its small systems with one LAPACK call each:

* :class:`SerialPlant`: q̈ = M(q)⁻¹ (τ − b(q, q̇)) with ``pin.crba`` (WORLD convention,
  upper triangle read by LAPACK ``dposv``, see :func:`rcm_pin.dynamics.tree.solve_mass_upper`)
  and ``pin.nonLinearEffects``;
* :class:`SerialLaw`: the serial computed-torque law of
  :class:`~rcm_pin.control.computed_torque.ComputedTorque` (same formulas, same order of
  operations), τ = RNEA(q, q̇, q̈*) on the controller's model, clipped to the limits;
  :meth:`SerialLaw.samples` recomputes the efforts, task values and rates at the output
  samples (the reference sampled vectorised, clipping and saturation flags vectorised);
* closed mechanisms: :mod:`rcm_pin.control.closed_hot_path`.

Tests (``tests/test_simulate_hot_path.py``) check these against Pinocchio's crba /
nonLinearEffects / rnea called directly and against the public law.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
import pinocchio as pin

from rcm_pin.control.references import CartesianTrajectory, Reference
from rcm_pin.dynamics.tree import solve_mass_upper
from rcm_pin.lazy import lapack
from rcm_pin.model.mechanism import Mechanism

if TYPE_CHECKING:
    from rcm_pin.control.computed_torque import ComputedTorque

_WORLD = pin.Convention.WORLD
RefFn = Callable[[float], tuple[np.ndarray, np.ndarray, np.ndarray]]


class SampledEfforts(NamedTuple):
    """Efforts and task state at the output samples (one per run, not per call).

    Attributes:
        tau: generalised efforts applied (N, nv) [N·m, N].
        saturated: a limit clipped some effort (N,).
        alternate: the extra drives were active (N,).
        measure: type-2 measure of the main drives (N,) (NaN without switching).
        x: task value (N, dim) [m, rad].
        xd: task rate (N, dim).
    """

    tau: np.ndarray
    saturated: np.ndarray
    alternate: np.ndarray
    measure: np.ndarray
    x: np.ndarray
    xd: np.ndarray


def _to_pin(mech: Mechanism) -> tuple[Callable[[np.ndarray], np.ndarray], ...]:
    """(q -> Pinocchio q, v -> Pinocchio v) without validation (no copy when the orders agree)."""
    if mech.identity_order and np.array_equal(mech.v_index, np.arange(mech.model.nv)):
        return (lambda q: q), (lambda v: v)
    if mech.continuous.size:  # θ -> (cos θ, sin θ)
        return mech.to_pin, mech.v_pin
    qi, vi, nq, nv = mech.q_index, mech.v_index, mech.model.nq, mech.model.nv

    def q_pin(q: np.ndarray) -> np.ndarray:
        out = np.zeros(nq)
        out[qi] = q
        return out

    def v_pin(v: np.ndarray) -> np.ndarray:
        out = np.zeros(nv)
        out[vi] = v
        return out

    return q_pin, v_pin


class SerialPlant:
    """Forward dynamics of a serial Mechanism: q̈ = M⁻¹ (τ − b) (module docstring)."""

    def __init__(self, mech: Mechanism) -> None:
        self.model, self.data = mech.model, mech.model.createData()
        self.q_pin, self.v_pin = _to_pin(mech)
        idx = mech.v_index
        self.idx = None if np.array_equal(idx, np.arange(mech.model.nv)) else idx
        self.block = None if self.idx is None else np.ix_(idx, idx)

    def accel(self, q: np.ndarray, v: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """q̈ (nv,) [rad/s², m/s²] at (q, q̇) under the efforts τ (nv,) [N·m, N]."""
        qp = self.q_pin(q)
        M = pin.crba(self.model, self.data, qp, _WORLD)
        b = pin.nonLinearEffects(self.model, self.data, qp, self.v_pin(v))
        if self.idx is not None:  # a sub-block of the symmetric matrix
            M = (np.triu(M) + np.triu(M, 1).T)[self.block]
            b = b[self.idx]
        return solve_mass_upper(M, tau - b)


def reference_function(ref: Reference) -> RefFn:
    """(x_T, ẋ_T, ẍ_T)(t) with the coefficients of a :class:`CartesianTrajectory` prepared
    once (the same operations as its ``evaluate``); other references: their ``evaluate``."""
    if type(ref) is not CartesianTrajectory:
        return ref.evaluate
    centre, amp, phase = np.asarray(ref.centre), np.asarray(ref.amplitude), np.asarray(ref.phase)
    omega = ref.omega
    amp_w, amp_w2 = amp * omega, -amp * omega**2
    sin, cos = np.sin, np.cos

    def evaluate(t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        arg = omega * t + phase
        s = sin(arg)
        return centre + amp * s, amp_w * cos(arg), amp_w2 * s

    return evaluate


def reference_samples(ref: Reference, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(x_T, ẋ_T, ẍ_T) at the times t (N,): vectorised where the reference is."""
    fns = [getattr(ref, nm, None) for nm in ("position", "velocity", "acceleration")]
    if all(callable(f) for f in fns):
        x, xd, xdd = (np.asarray(f(t), dtype=np.float64) for f in fns)  # type: ignore[misc]
        return x, xd, xdd
    rows = [ref.evaluate(float(ti)) for ti in t]
    x, xd, xdd = (np.array([r[k] for r in rows]) for k in range(3))
    return x, xd, xdd


def solve(A: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """A x = rhs by one LAPACK ``dgesv`` call (the routine of ``np.linalg.solve``, without
    its per-call overhead); a singular A goes to ``np.linalg.solve``, which raises."""
    x, info = lapack("dgesv")(A, rhs)[2:]
    return x if info == 0 else np.linalg.solve(A, rhs)


class SerialLaw:
    """The serial computed-torque law of a ComputedTorque, prepared once (module docstring)."""

    def __init__(self, ctrl: ComputedTorque) -> None:
        mech, kin, g = ctrl.model, ctrl.kinematics, ctrl.gains
        assert kin is not None  # a serial mechanism
        cols = np.asarray(kin.joints)
        contiguous = len(cols) > 0 and np.array_equal(cols, np.arange(cols[0], cols[0] + len(cols)))
        self.ctrl, self.kin = ctrl, kin
        #: the task's coordinates: a slice when contiguous (a view, no fancy-index copy)
        self.cols: slice | np.ndarray = slice(cols[0], cols[0] + len(cols)) if contiguous else cols
        self.ncols = len(cols)
        self.model, self.data = mech.model, mech.model.createData()
        self.q_pin, self.v_pin = _to_pin(mech)
        idx = mech.v_index
        self.idx = None if np.array_equal(idx, np.arange(mech.model.nv)) else idx
        self.kn, self.kc, self.kpos, self.ff = g.kn, g.kc, ctrl.kpos, float(ctrl.feedforward)
        self.posture = ctrl.posture
        self.task_space = ctrl.space == "task"
        self.angular = bool(ctrl.task_output.angular.any())
        self.square = ctrl.task_output.dim == self.ncols
        self.limits = None if ctrl.limits is None else np.asarray(ctrl.limits, dtype=float)
        self.lower = None if self.limits is None else -self.limits
        self.reference: RefFn = reference_function(ctrl.reference)

    def accel(
        self, t: float, q: np.ndarray, v: np.ndarray, x_t: np.ndarray, v_t: np.ndarray,
        a_t: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:  # fmt: skip
        """q̈* (nv,) and, in task space, the task value x and its Jacobian J."""
        kin, cols = self.kin, self.cols
        qdd = -self.kn * (q - self.posture) - self.kc * v  # hold the others at the posture
        if not self.task_space:
            qr, qrd, qrdd = self.ctrl.joint_reference(t)
            qdd[cols] = self.ff * qrdd + self.kpos * (qr - q[cols]) + self.kc * (qrd - v[cols])
            return qdd, None, None
        J, x = kin.jacobian(q), kin.position(q)
        e = self.ctrl.task_error(x_t, x) if self.angular else x_t - x
        ff = a_t if self.ff == 1.0 else self.ff * a_t  # 1.0 * a == a exactly
        a_star = ff + self.kpos * e + self.kc * (v_t - J @ v[cols])
        rhs = a_star - kin.bias(q, v)
        if self.square:
            qdd[cols] = solve(J, rhs)
        else:  # redundant: minimum norm plus the posture in the null space
            pinv = np.linalg.pinv(J)
            qdd[cols] = pinv @ rhs + (np.eye(self.ncols) - pinv @ J) @ qdd[cols]
        return qdd, x, J

    def rnea(self, q: np.ndarray, v: np.ndarray, a: np.ndarray) -> np.ndarray:
        """τ = RNEA(q, q̇, q̈) on the controller's model (nv,) [N·m, N], unclipped."""
        tau = pin.rnea(self.model, self.data, self.q_pin(q), self.v_pin(v), self.v_pin(a))
        return tau if self.idx is None else tau[self.idx]

    def tau(self, t: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Efforts applied to the plant (nv,) [N·m, N] at (t, q, q̇), clipped to the limits."""
        x_t, v_t, a_t = self.reference(t)
        tau = self.rnea(q, v, self.accel(t, q, v, x_t, v_t, a_t)[0])
        lo, hi = self.lower, self.limits
        if lo is None or hi is None:
            return tau
        return np.minimum(np.maximum(tau, lo), hi)  # np.clip without its overhead

    def samples(self, t: np.ndarray, q: np.ndarray, v: np.ndarray) -> SampledEfforts:
        """Efforts, saturation flags, task values and rates at the output samples: the
        law's formulas on all samples at once; the family's closed forms (vectorised when
        the family gives ``batch``), the joint reference and RNEA (one state per call)
        per sample."""
        N, cols, kin, ctrl = len(t), self.cols, self.kin, self.ctrl
        dim, k = ctrl.task_output.dim, self.ncols
        if kin.batch is not None:
            x, J, h = kin.batch(q, v)
        else:
            x = np.array([kin.position(qi) for qi in q]).reshape(N, dim)
            J = np.array([kin.jacobian(qi) for qi in q]).reshape(N, dim, k)
        xd = np.einsum("nij,nj->ni", J, v[:, cols])
        qdd = -self.kn * (q - self.posture) - self.kc * v  # hold the others at the posture
        if self.task_space:
            x_t, v_t, a_t = reference_samples(ctrl.reference, t)
            if kin.batch is None:
                h = np.array([kin.bias(qi, vi) for qi, vi in zip(q, v)]).reshape(N, dim)
            e = (
                np.array([ctrl.task_error(a, b) for a, b in zip(x_t, x)]).reshape(N, dim)
                if self.angular
                else x_t - x
            )
            rhs = (self.ff * a_t + self.kpos * e + self.kc * (v_t - xd) - h)[..., None]
            if self.square:
                qdd[:, cols] = np.linalg.solve(J, rhs)[..., 0]
            else:  # redundant: minimum norm plus the posture in the null space
                pinv = np.linalg.pinv(J)
                null = (np.eye(k) - pinv @ J) @ qdd[:, cols, None]
                qdd[:, cols] = (pinv @ rhs + null)[..., 0]
        else:
            refs = [ctrl.joint_reference(float(ti)) for ti in t]
            qr, qrd, qrdd = (np.array([r[j] for r in refs]).reshape(N, k) for j in range(3))
            qdd[:, cols] = (
                self.ff * qrdd + self.kpos * (qr - q[:, cols]) + self.kc * (qrd - v[:, cols])
            )
        raw = np.array([self.rnea(qi, vi, ai) for qi, vi, ai in zip(q, v, qdd)])
        raw = raw.reshape(N, v.shape[1])
        lim = self.limits
        tau = raw if lim is None else np.minimum(np.maximum(raw, -lim), lim)
        sat = np.any(tau != raw, axis=1)
        return SampledEfforts(tau, sat, np.zeros(N, dtype=bool), np.full(N, np.nan), x, xd)


def free_samples(N: int, nv: int) -> SampledEfforts:
    """A run without a controller: τ = 0, no task."""
    return SampledEfforts(
        np.zeros((N, nv)), np.zeros(N, dtype=bool), np.zeros(N, dtype=bool),
        np.full(N, np.nan), np.full((N, 0), np.nan), np.full((N, 0), np.nan),
    )  # fmt: skip


__all__ = [
    "SampledEfforts",
    "SerialLaw",
    "SerialPlant",
    "free_samples",
    "reference_function",
    "reference_samples",
    "solve",
]
