"""The closed-mechanism right-hand side of ``simulate`` with one kinematics pass per model.

The validated route (:mod:`rcm_pin.dynamics.constrained`, used by
:meth:`~rcm_pin.control.computed_torque.ComputedTorque.effort`) runs Pinocchio's
forward kinematics, joint Jacobians and frame placements five times per right-hand side
(closure rows three times, the output twice) on the same (q, q̇). Here one pass of the
same three calls per model gives everything read from it:

* :class:`KinematicsPass`: world closure residual c, J_c, γ = J̇_c q̇ (the formulas of
  ``constrained.world_closure``) and the output's x, ẋ = J_x q̇, J_x, J̇_x q̇ (those of
  ``constrained.output_drift``);
* :class:`ClosedPlant`: the KKT forward dynamics of ``constrained.forward_dynamics``;
* :class:`ClosedLaw`: the closed computed-torque law (``ComputedTorque.acceleration`` and
  ``constrained.inverse_dynamics`` on the main drives); with drive switching it keeps
  the validated ``ComputedTorque.effort``.

Tests (``tests/test_simulate_closed_hot_path.py``) compare them with those public functions.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from rcm_pin.control.hot_path import RefFn, SampledEfforts, reference_function, solve
from rcm_pin.model.loops import LWA
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output

if TYPE_CHECKING:
    from rcm_pin.control.computed_torque import ComputedTorque


class KinematicsPass:
    """Closure rows and output rows of a closed Mechanism from one kinematics pass."""

    def __init__(self, mech: Mechanism, output: Output) -> None:
        loops = mech.loops
        assert loops is not None
        self.model, self.data, self.output = mech.model, mech.model.createData(), output
        self.zero = np.zeros(mech.model.nv)
        self.closures = [
            (c.frame_a_id, c.frame_b_id, np.array(c.world_rows, dtype=int), c.kind == "3d")
            for c in loops.closures
        ]
        self.fid, self.rows = output.frame_id, output.rows

    def closure(self, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(c (m,) [m, rad], J_c (m, nv), γ = J̇_c q̇ (m,)) at (q, q̇)."""
        self._run(q, v)
        return self._closure()

    def task(self, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, ...]:
        """(x, ẋ = J_x q̇, J_x (k, nv), J̇_x q̇) of the output at (q, q̇)."""
        self._run(q, v)
        return self._task(v)

    def closure_and_task(
        self, q: np.ndarray, v: np.ndarray
    ) -> tuple[tuple[np.ndarray, np.ndarray, np.ndarray], tuple[np.ndarray, ...]]:
        """:meth:`closure` and :meth:`task` at (q, q̇) from one pass."""
        self._run(q, v)
        return self._closure(), self._task(v)

    def _run(self, q: np.ndarray, v: np.ndarray) -> None:
        """Forward kinematics (q, q̇, q̈ = 0), joint Jacobians and frame placements into
        this pass's own Data; only the methods above read it, right after."""
        model, data = self.model, self.data
        pin.forwardKinematics(model, data, q, v, self.zero)
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)

    def _closure(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        model, data = self.model, self.data
        cs, js, gs = [], [], []
        for fa, fb, rows, linear in self.closures:
            oMa, oMb = data.oMf[fa], data.oMf[fb]
            ja = pin.getFrameJacobian(model, data, fa, LWA)
            jb = pin.getFrameJacobian(model, data, fb, LWA)
            aa = pin.getFrameClassicalAcceleration(model, data, fa, LWA)
            ab = pin.getFrameClassicalAcceleration(model, data, fb, LWA)
            if linear:
                cs.append((oMa.translation - oMb.translation)[rows])
                gs.append((aa.linear - ab.linear)[rows])
            else:
                rot = pin.log3(oMa.rotation @ oMb.rotation.T)
                cs.append(np.r_[oMa.translation - oMb.translation, rot][rows])
                gs.append((aa.vector - ab.vector)[rows])
            js.append((ja - jb)[rows])
        return np.concatenate(cs), np.vstack(js), np.concatenate(gs)

    def _task(self, v: np.ndarray) -> tuple[np.ndarray, ...]:
        model, data = self.model, self.data
        jx = pin.getFrameJacobian(model, data, self.fid, LWA)[self.rows]
        acc = pin.getFrameClassicalAcceleration(model, data, self.fid, LWA).vector
        return self.output.value(data.oMf[self.fid]), jx @ v, jx, acc[self.rows]


class ClosedPlant:
    """KKT forward dynamics of a closed Mechanism with Baumgarte stabilisation."""

    def __init__(self, mech: Mechanism, baumgarte: tuple[float, float]) -> None:
        self.kin = KinematicsPass(mech, mech.output)
        self.model, self.data = self.kin.model, self.kin.data
        # crba's convention as rcm_pin.dynamics.tree.mass_matrix_pin chooses it
        self.convention = (pin.Convention.WORLD,) if mech.coupling.has_mimic else ()
        self.w, self.z = baumgarte
        self.n = mech.model.nv

    def accel(self, q: np.ndarray, v: np.ndarray, tau_full: np.ndarray) -> np.ndarray:
        """q̈ (nv,) [rad/s²] under the generalised torques τ (nv,) [N·m]."""
        c, jc, gam = self.kin.closure(q, v)
        M = np.asarray(pin.crba(self.model, self.data, q, *self.convention))
        M = np.triu(M) + np.triu(M, 1).T
        b = pin.nonLinearEffects(self.model, self.data, q, v)
        w, z, n = self.w, self.z, self.n
        rhs_c = -gam - 2.0 * z * w * (jc @ v) - w * w * c
        m = len(c)
        kkt = np.zeros((n + m, n + m))
        kkt[:n, :n], kkt[:n, n:], kkt[n:, :n] = M, -jc.T, jc
        return solve(kkt, np.concatenate([tau_full - b, rhs_c]))[:n]


class ClosedLaw:
    """The closed computed-torque law with one kinematics pass (module docstring)."""

    def __init__(self, ctrl: ComputedTorque, plant: Mechanism) -> None:
        mech, loops = ctrl.model, ctrl.model.loops
        assert loops is not None
        self.ctrl, self.plant = ctrl, plant
        self.kin = KinematicsPass(mech, ctrl.task_output)
        self.plant_kin = KinematicsPass(plant, ctrl.task_output)
        self.model, self.data = mech.model, mech.model.createData()
        self.reference: RefFn = reference_function(ctrl.reference)
        self.kpos, self.kc, self.ff = ctrl.kpos, ctrl.gains.kc, float(ctrl.feedforward)
        self.w, self.z = ctrl.baumgarte
        self.drive_v = mech.joint_v(loops.drives)
        n, k = mech.model.nv, len(self.drive_v)
        self.n, self.k = n, k
        self.select = np.zeros((n, k))
        self.select[self.drive_v, np.arange(k)] = 1.0
        self.limits = None if ctrl.limits is None else np.asarray(ctrl.limits, dtype=float)

    def _raw(self, t: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Drive efforts (k,) of the main drives, unclipped [N·m, N]."""
        x_t, v_t, a_t = self.reference(t)
        (c, jc, gam), (x, xd, jx, drift) = self.kin.closure_and_task(q, v)
        e = self.ctrl.task_error(x_t, x)
        a_star = self.ff * a_t + self.kpos * e + self.kc * (v_t - xd)
        w, z = self.w, self.z
        rhs = np.concatenate([-gam - 2.0 * z * w * (jc @ v) - w * w * c, a_star - drift])
        acc = solve(np.vstack([jc, jx]), rhs)
        tau = pin.rnea(self.model, self.data, q, v, acc)
        mat = np.concatenate([self.select, jc.T], axis=1)
        return solve(mat, tau)[: self.k]

    def _full(self, tau: np.ndarray) -> np.ndarray:
        out = np.zeros(self.n)
        out[self.drive_v] = tau
        return out

    def tau(self, t: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Generalised efforts (nv,) [N·m, N] at (t, q, q̇), clipped to the limits."""
        if self.ctrl.switching is not None:
            return self.ctrl.effort(t, q, v).tau_full
        tau, lim = self._raw(t, q, v), self.limits
        return self._full(tau if lim is None else np.clip(tau, -lim, lim))

    def samples(self, t: np.ndarray, q: np.ndarray, v: np.ndarray) -> SampledEfforts:
        """Efforts and the plant's task state at the output samples."""
        N, dim = len(t), self.ctrl.task_output.dim
        out = SampledEfforts(
            np.zeros((N, v.shape[1])), np.zeros(N, dtype=bool), np.zeros(N, dtype=bool),
            np.full(N, np.nan), np.zeros((N, dim)), np.zeros((N, dim)),
        )  # fmt: skip
        lim = self.limits
        for i in range(N):
            if self.ctrl.switching is not None:
                eff = self.ctrl.effort(float(t[i]), q[i], v[i])
                out.tau[i], out.saturated[i] = eff.tau_full, eff.saturated
                out.alternate[i], out.measure[i] = eff.alternate, eff.measure
            else:
                raw = self._raw(float(t[i]), q[i], v[i])
                tau = raw if lim is None else np.clip(raw, -lim, lim)
                out.tau[i], out.saturated[i] = self._full(tau), bool(np.any(tau != raw))
            out.x[i], out.xd[i] = self.plant_kin.task(q[i], v[i])[:2]
        return out


__all__ = ["ClosedLaw", "ClosedPlant", "KinematicsPass"]
