"""Tracking a tool-tip path with the RCM as a path constraint: a kinematic OCP.

On the grid t_k = k h (k = 0..N) with the configurations q_1..q_N as variables (q_0
given), in the order of the math:

* objective: ``(1/N) Σ_k [ w_p |p_tip(q_k) − p_ref,k|² + w_a |(q_{k+1} − 2 q_k + q_{k−1}) / h²|² ]``
  (tip tracking, and a small joint-acceleration penalty that picks a smooth motion in the
  arm's redundancy; the second difference at the last node uses q_{N+1} = q_N);
* path constraint: the RCM at every node, ``(R_s b_i)ᵀ (p_T − p_s(q_k)) = 0`` (two rows,
  :class:`ocp.ik_constraints.AxisThroughPoint`), or ``dist² ≤ tol²``;
* velocity limits ``|q_{k+1} − q_k| ≤ v_max h`` and joint limits (bounds);
* optional drive limits ``|τ_k| ≤ τ_max`` (the URDF's effort limits) with
  ``τ_k = rnea(q_k, (q_{k+1} − q_{k−1}) / 2h, (q_{k+1} − 2 q_k + q_{k−1}) / h²)``.

Solved by IPOPT (exact Hessian). The motion is a finite-difference transcription of q(t)
(the efforts follow from RNEA and may be bounded), not the collocation of
:class:`ocp.tracking.TrackingOCP`, which has no hook for extra path constraints.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np
import pinocchio as pin

from ocp.ik_constraints import AxisThroughPoint, constraint_expr
from ocp.rcm import TIP_FRAME, tip_model
from ocp.symbolic import SymbolicModel
from rcm_pin.control.rcm_task import RcmTool, line_distance
from rcm_pin.errors import InvalidInputError, SolverError


@dataclass(frozen=True)
class RcmTrackingResult:
    """Nodes (N + 1) of the solution and its errors by Pinocchio FK.

    Attributes:
        t: (N + 1,) [s]; q: (N + 1, n); p_tip: (N + 1, 3) [m];
        rcm_error: (N + 1,) distance of p_T from the shaft [m]; tip_error: (N + 1,) [m];
        tau: (N, n) joint torques at q_1..q_N (RNEA with gravity, central differences) [N·m];
        success, status, iterations, solve_time [s].
    """

    t: np.ndarray
    q: np.ndarray
    p_tip: np.ndarray
    rcm_error: np.ndarray
    tip_error: np.ndarray
    tau: np.ndarray
    success: bool
    status: str
    iterations: int
    solve_time: float


class RcmTrackingOCP:
    """Build once for a model, tool and grid; :meth:`solve` per reference."""

    def __init__(
        self, model: pin.Model, tool: RcmTool, *, n_intervals: int, dt: float,
        tolerance: float = 0.0, position_weight: float = 1e6, acceleration_weight: float = 1e-8,
        drive_limits: bool = False, tol: float = 1e-10, max_iter: int = 300,
    ) -> None:  # fmt: skip
        if n_intervals < 1 or not dt > 0:
            raise InvalidInputError(f"need n_intervals >= 1 and dt > 0; got {n_intervals}, {dt}")
        self.model, self.tool = tip_model(model, tool), tool
        self.N, self.h, n = int(n_intervals), float(dt), self.model.nv
        sm = SymbolicModel(self.model)
        q = ca.SX.sym("q", n)
        p_tip = sm.frame_placement(TIP_FRAME)(q)[0]
        p_s, R_s = sm.frame_placement(int(tool.axis_frame))(q)
        c = AxisThroughPoint(tool.trocar, tuple(np.eye(3)[tool.axis]), tolerance)  # type: ignore[arg-type]
        rcm = constraint_expr(c, p_s, R_s)
        self.tip = ca.Function("rcm_tip_position", [q], [p_tip], ["q"], ["p"])
        self.rcm = ca.Function("rcm_rows", [q], [rcm.g], ["q"], ["g"])
        Q, q0 = ca.MX.sym("Q", n, self.N), ca.MX.sym("q0", n)
        ref = ca.MX.sym("p_ref", 3, self.N)
        full = ca.horzcat(q0, Q, Q[:, -1])  # q_0 .. q_N, q_{N+1} = q_N
        acc = (full[:, 2:] - 2 * full[:, 1:-1] + full[:, :-2]) / self.h**2
        tips = self.tip.map(self.N)(Q)
        cost = position_weight * ca.sumsqr(tips - ref) + acceleration_weight * ca.sumsqr(acc)
        steps = ca.horzcat(q0, Q)[:, 1:] - ca.horzcat(q0, Q)[:, :-1]
        vel = (full[:, 2:] - full[:, :-2]) / (2 * self.h)
        taus = sm.rnea().map(self.N)(Q, vel, acc)  # RNEA with gravity at q_1..q_N
        self.torques = ca.Function("rcm_node_torques", [q0, Q], [taus], ["q0", "Q"], ["tau"])
        g = ca.vertcat(ca.vec(self.rcm.map(self.N)(Q)), ca.vec(steps))
        if drive_limits:
            g = ca.vertcat(g, ca.vec(taus))
        self.drive_limits = drive_limits
        self.n_rcm = int(rcm.g.shape[0])
        self._lbg_rcm = np.tile(rcm.lbg, self.N)
        self._ubg_rcm = np.tile(rcm.ubg, self.N)
        nlp = {"x": ca.vec(Q), "p": ca.vertcat(q0, ca.vec(ref)), "f": cost / self.N, "g": g}
        opts: dict[str, Any] = {
            "print_time": False,
            "error_on_fail": False,
            "expand": True,
            "ipopt": {"print_level": 0, "sb": "yes", "tol": tol, "max_iter": max_iter},
        }
        self.solver = ca.nlpsol("rcm_tracking", "ipopt", nlp, opts)
        self.lower = np.asarray(self.model.lowerPositionLimit, float)
        self.upper = np.asarray(self.model.upperPositionLimit, float)
        self.v_max = np.asarray(self.model.velocityLimit, float)
        self.tau_max = np.asarray(self.model.effortLimit, float)

    def solve(
        self, p_ref: np.ndarray, q0: np.ndarray, *, guess: np.ndarray | None = None,
        raise_on_failure: bool = True,
    ) -> RcmTrackingResult:  # fmt: skip
        """Track ``p_ref`` ((N + 1, 3) [m], row 0 at q0) from ``q0``.

        Raises:
            InvalidInputError: shapes. SolverError: IPOPT did not converge.
        """
        p_ref = np.asarray(p_ref, dtype=float)
        q0 = np.asarray(q0, dtype=float).reshape(-1)
        n = self.model.nv
        if p_ref.shape != (self.N + 1, 3) or q0.shape != (n,):
            raise InvalidInputError(f"p_ref must be ({self.N + 1}, 3) and q0 ({n},)")
        w0 = np.tile(q0, self.N) if guess is None else np.asarray(guess, float)[1:].reshape(-1)
        vh = np.tile(self.v_max * self.h, self.N)
        th = np.tile(self.tau_max, self.N) if self.drive_limits else np.zeros(0)
        start = time.perf_counter()
        sol = self.solver(
            x0=w0, p=np.concatenate([q0, p_ref[1:].reshape(-1)]),
            lbx=np.tile(self.lower, self.N), ubx=np.tile(self.upper, self.N),
            lbg=np.concatenate([self._lbg_rcm, -vh, -th]),
            ubg=np.concatenate([self._ubg_rcm, vh, th]),
        )  # fmt: skip
        wall = time.perf_counter() - start
        stats = self.solver.stats()
        q = np.vstack([q0, np.asarray(sol["x"]).reshape(self.N, n)])
        tau = np.asarray(self.torques(q0, q[1:].T)).T
        result = self._result(q, tau, p_ref, stats, wall)
        if raise_on_failure and not result.success:
            raise SolverError(
                f"RCM tracking OCP (ipopt) failed: {result.status} after "
                f"{result.iterations} iterations"
            )
        return result

    def _result(
        self, q: np.ndarray, tau: np.ndarray, p_ref: np.ndarray, stats: dict[str, Any],
        wall: float,
    ) -> RcmTrackingResult:  # fmt: skip
        data = self.model.createData()
        tips, ps, axes = np.empty((len(q), 3)), np.empty((len(q), 3)), np.empty((len(q), 3))
        tid = self.model.getFrameId(TIP_FRAME)
        for k, qk in enumerate(q):
            pin.framesForwardKinematics(self.model, data, qk)
            tips[k] = data.oMf[tid].translation
            ps[k] = data.oMf[self.tool.axis_frame].translation
            axes[k] = data.oMf[self.tool.axis_frame].rotation[:, self.tool.axis]
        rcm = line_distance(ps, axes, np.asarray(self.tool.trocar))
        t = np.arange(len(q)) * self.h
        return RcmTrackingResult(
            t, q, tips, rcm, np.linalg.norm(tips - p_ref, axis=1), tau,
            bool(stats.get("success", False)), str(stats.get("return_status", "unknown")),
            int(stats.get("iter_count", -1)), wall,
        )  # fmt: skip


__all__ = ["RcmTrackingOCP", "RcmTrackingResult"]
