"""Trajectory-tracking optimal control of one frame's position, by direct collocation.

Over ``[0, T]`` cut into ``N`` intervals of length ``h`` with ``d`` collocation points
each (:mod:`ocp.collocation`, Radau IIA by default), in the order of the math:

* variables, stage-wise ``[x_0, u_0, x_1, u_1, ..., x_N]``: node states
  ``x_k = (q_k, v_k)``, stage controls ``u_k = (Q_1..Q_d)`` (positions at the collocation
  points); velocities, accelerations and drive efforts follow from them:

      V_r = (1/h) sum_j D_jr Q_j,   A_r = (1/h) sum_j D_jr V_j   (Q_0 = q_k, V_0 = v_k)
      T_r = rnea(Q_r, V_r, A_r)                                   (inverse dynamics)

  i.e. collocation of ``q' = v``, ``v' = M^{-1}(tau - b)`` with the efforts eliminated
  (no mass-matrix inverse; a fully actuated model makes every trajectory admissible);
* objective: ``(1/T) sum_k h sum_r B_r [w_p |p(Q_r) - p_ref(t_kr)|^2
  + sum_i w_i (Q_r,i - posture_i)^2 + w_tau |T_r|^2]``;
* dynamics: gap closing ``x_{k+1} = sum_j E_j (Q_j, V_j)`` (Radau: ``(Q_d, V_d)``);
* path constraints: joint limits on ``q_k, Q_r`` (bounds); drive limits
  ``-tau_max <= T_r <= tau_max`` and velocity limits on ``V_r`` (general constraints,
  present when enabled at construction, values set per solve);
* boundary condition: ``x_0 = x_init`` (bounds);
* initial guess: given, or "hold" (``q_init`` everywhere, node velocities ``v_init``);
* solve: IPOPT (exact Hessian) or fatrop (structure given manually: the layout above is
  fatrop's ``[x_k, u_k]`` / ``[gap_k, path_k]`` order). Derivatives are assembled stage by
  stage (:mod:`ocp.stagewise`); ``jit=True`` compiles the stage functions.

The model is a serial :class:`rcm_pin.Mechanism` (default frame: its tool frame) or a
``pin.Model`` with a frame; the efforts are eliminated through the tree's inverse
dynamics, so a closed Mechanism (its loops need constraint forces) is refused.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any, Literal

import casadi as ca
import numpy as np

from ocp.collocation import Scheme, collocation
from ocp.models import ModelSource, require_serial, resolve
from ocp.stagewise import StagewiseNLP
from ocp.symbolic import JIT_OPTIONS, SymbolicModel
from ocp.tracking_result import TrackingResult, make_result
from rcm_pin.errors import InvalidInputError, SolverError

Reference = Callable[[np.ndarray], np.ndarray] | np.ndarray


class TrackingOCP:
    """Build once for a model, frame, horizon and grid; :meth:`solve` per reference."""

    def __init__(
        self,
        model: ModelSource,
        frame: str | int | None = None,
        *,
        horizon: float,
        n_intervals: int = 100,
        degree: int = 3,
        scheme: Scheme = "radau",
        lower: np.ndarray | None = None,
        upper: np.ndarray | None = None,
        drive_limits: bool = True,
        velocity_limits: bool = False,
        position_weight: float = 1e6,
        posture_weights: np.ndarray | None = None,
        effort_weight: float = 0.0,
        solver: Literal["ipopt", "fatrop"] = "ipopt",
        tol: float = 1e-12,
        max_iter: int = 200,
        jit: bool = False,
    ) -> None:
        require_serial(model, "the tracking OCP")
        src = resolve(model, frame)
        self.sm: SymbolicModel = src.sm
        sm, n = self.sm, self.sm.nv
        if sm.nq != sm.nv:
            raise InvalidInputError("tracking needs nq == nv (no continuous joints)")
        if horizon <= 0 or n_intervals < 1 or solver not in ("ipopt", "fatrop"):
            raise InvalidInputError("need horizon > 0, n_intervals >= 1, solver ipopt|fatrop")
        self.fid, self.solver_name = src.frame_id, solver
        self.T, self.N, self.col = float(horizon), int(n_intervals), collocation(degree, scheme)
        self.h, d = self.T / self.N, degree
        self.lower = np.asarray(sm.model.lowerPositionLimit if lower is None else lower, float)
        self.upper = np.asarray(sm.model.upperPositionLimit if upper is None else upper, float)
        posture_w = np.zeros(n) if posture_weights is None else np.asarray(posture_weights, float)
        self.drive_limits, self.velocity_limits = drive_limits, velocity_limits
        # -- variables (one stage: node state, collocation positions, next node state) -----
        self.nx, self.nu = 2 * n, n * d
        z = ca.SX.sym("z", 2 * self.nx + self.nu)
        p_ref, post = ca.SX.sym("p_ref", 3, d), ca.SX.sym("posture", n)
        x, x_next = z[: self.nx], z[self.nx + self.nu :]
        qs = [x[:n]] + [z[self.nx + r * n : self.nx + (r + 1) * n] for r in range(d)]
        vs = [x[n:]] + [
            sum(self.col.D[j, r] * qs[j] for j in range(d + 1)) / self.h for r in range(d)
        ]
        acc = [sum(self.col.D[j, r] * vs[j] for j in range(d + 1)) / self.h for r in range(d)]
        place, rnea = sm.frame_placement(self.fid), sm.rnea()
        taus = [rnea(qs[r + 1], vs[r + 1], acc[r]) for r in range(d)]
        pos = [place(qs[r + 1])[0] for r in range(d)]
        # -- objective (quadrature of the stage cost over the interval, time-averaged) -----
        cost = 0
        for r in range(d):
            stage = position_weight * ca.sumsqr(pos[r] - p_ref[:, r])
            stage += ca.dot(posture_w, (qs[r + 1] - post) ** 2)
            if effort_weight:
                stage += effort_weight * ca.sumsqr(taus[r])
            cost += self.h * self.col.B[r] / self.T * stage
        # -- dynamics (gap closing) and path constraints ----------------------------------
        end = ca.vertcat(
            sum(self.col.E[j] * qs[j] for j in range(d + 1)),
            sum(self.col.E[j] * vs[j] for j in range(d + 1)),
        )
        g = [x_next - end] + (taus if drive_limits else []) + (vs[1:] if velocity_limits else [])
        self.n_path = n * d * (int(drive_limits) + int(velocity_limits))
        pars = ca.vertcat(ca.vec(p_ref), post)
        self.stage = ca.Function(
            "tracking_stage", [z, pars], [ca.vertcat(*g), cost], ["z", "p"], ["g", "l"]
        )
        self.outputs = ca.Function(
            "tracking_outputs",
            [z],
            [ca.horzcat(*vs[1:]), ca.horzcat(*acc), ca.horzcat(*taus), ca.horzcat(*pos)],
            ["z"],
            ["V", "A", "tau", "p"],
        )
        # -- the NLP over all stages (variables in fatrop's [x_0, u_0, ..., x_N] order) ------
        pref_all, post_mx = ca.MX.sym("p_ref", 3, self.N * d), ca.MX.sym("posture", n)
        params = ca.vertcat(ca.reshape(pref_all, 3 * d, self.N), ca.repmat(post_mx, 1, self.N))
        self.nlp = StagewiseNLP(
            self.stage,
            self.N,
            self.nx + self.nu,
            self.nx,
            params,
            ca.vertcat(ca.vec(pref_all), post_mx),
            dict(JIT_OPTIONS) if jit else {},
        )
        nlp = self.nlp.nlp if solver == "ipopt" else self.nlp.expanded()
        self.solver = ca.nlpsol(
            f"tracking_{solver}", solver, nlp, self._options(solver, tol, max_iter)
        )

    def _options(self, solver: str, tol: float, max_iter: int) -> dict[str, Any]:
        opts: dict[str, Any] = self.nlp.solver_options() if solver == "ipopt" else {}
        opts.update(error_on_fail=False, print_time=False)
        if solver == "ipopt":
            opts["ipopt"] = {
                "print_level": 0,
                "sb": "yes",
                "tol": tol,
                "max_iter": max_iter,
                "mu_strategy": "adaptive",
            }
            return opts
        # fatrop stops with a failure below ~1e-10 on this problem: floor its tolerance
        opts.update(
            structure_detection="manual",
            N=self.N,
            nx=[self.nx] * (self.N + 1),
            nu=[self.nu] * self.N + [0],
            ng=[self.n_path] * self.N + [0],
            fatrop={"print_level": 0, "tol": max(tol, 1e-10), "max_iter": max_iter},
        )
        return opts

    # -- times, bounds, guesses -------------------------------------------------------------
    def _split(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Node states (N + 1, nx) and stage controls (N, nu) of a variable vector."""
        body = w[: -self.nx].reshape(self.N, self.nx + self.nu)
        return np.vstack([body[:, : self.nx], w[-self.nx :]]), body[:, self.nx :]

    def _join(self, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return np.concatenate([np.hstack([x[:-1], u]).reshape(-1), x[-1]])

    def bounds(
        self,
        x_init: np.ndarray,
        effort_limits: np.ndarray | None,
        velocity_limits: np.ndarray | None,
    ) -> dict[str, np.ndarray]:
        """``lbx, ubx, lbg, ubg``: boundary condition, joint, drive and velocity limits."""
        n, d = self.sm.nv, self.col.degree
        inf = np.full(n, np.inf)
        tmax = inf if effort_limits is None else np.asarray(effort_limits, float)
        vmax = inf if velocity_limits is None else np.asarray(velocity_limits, float)
        for name, lim, on in (
            ("effort", tmax, self.drive_limits),
            ("velocity", vmax, self.velocity_limits),
        ):
            if lim.shape != (n,) or np.any(lim < 0) or (np.isfinite(lim).any() and not on):
                raise InvalidInputError(
                    f"{name}_limits must be ({n},) >= 0 and enabled at "
                    f"construction ({name.replace('effort', 'drive')}"
                    f"_limits=True)"
                )
        xl = np.concatenate([self.lower, np.full(n, -np.inf)])
        xu = np.concatenate([self.upper, inf])
        lbx = self._join(np.tile(xl, (self.N + 1, 1)), np.tile(np.tile(self.lower, d), (self.N, 1)))
        ubx = self._join(np.tile(xu, (self.N + 1, 1)), np.tile(np.tile(self.upper, d), (self.N, 1)))
        lbx[: self.nx] = ubx[: self.nx] = x_init  # boundary condition x_0 = x_init
        path = np.concatenate(
            [np.tile(tmax, d)] * self.drive_limits
            + [np.tile(vmax, d)] * self.velocity_limits
            + [np.zeros(0)]
        )
        ubg = np.tile(np.concatenate([np.zeros(self.nx), path]), self.N)
        lbg = np.tile(np.concatenate([np.zeros(self.nx), -path]), self.N)
        return {"lbx": lbx, "ubx": ubx, "lbg": lbg, "ubg": ubg}

    def collocation_times(self) -> np.ndarray:
        """Times of the ``N d`` collocation points."""
        k = np.arange(self.N)[:, None]
        return ((k + self.col.tau[None, 1:]) * self.h).reshape(-1)

    def guess_from(self, q_colloc: np.ndarray, x_init: np.ndarray) -> np.ndarray:
        """Variable vector from positions at the collocation points (N d, nq); node
        velocities from the collocation polynomials."""
        n, d = self.sm.nv, self.col.degree
        qc = np.asarray(q_colloc, dtype=float).reshape(self.N, d, n)
        qall = np.concatenate([np.vstack([x_init[None, :n], qc[:-1, -1]])[:, None], qc], 1)
        vend = np.einsum("jr,kjn->krn", self.col.D, qall)[:, -1] / self.h
        x = np.vstack([x_init, np.hstack([qc[:, -1], vend])])
        return self._join(x, qc.reshape(self.N, d * n))

    def hold_guess(self, x_init: np.ndarray) -> np.ndarray:
        """``q_init`` at every point and node, node velocities ``v_init``."""
        n = self.sm.nv
        x = np.tile(x_init, (self.N + 1, 1))
        return self._join(x, np.tile(x_init[:n], (self.N, self.col.degree)))

    # -- solve ---------------------------------------------------------------------------
    def solve(
        self,
        reference: Reference,
        x_init: np.ndarray,
        *,
        effort_limits: np.ndarray | None = None,
        velocity_limits: np.ndarray | None = None,
        posture: np.ndarray | None = None,
        guess: np.ndarray | None = None,
        raise_on_failure: bool = True,
    ) -> TrackingResult:
        """Track ``reference`` (callable ``t -> (..., 3)`` or ``(N d, 3)`` array) from the
        state ``x_init = (q, v)``; ``effort_limits`` (nv,) bound ``|tau|``."""
        tc = self.collocation_times()
        pref = np.asarray(reference(tc) if callable(reference) else reference, dtype=float)
        x_init = np.asarray(x_init, dtype=float).reshape(-1)
        if pref.shape != (len(tc), 3) or x_init.shape != (self.nx,):
            raise InvalidInputError(f"reference must be ({len(tc)}, 3), x_init ({self.nx},)")
        post = np.zeros(self.sm.nv) if posture is None else np.asarray(posture, float)
        w0 = self.hold_guess(x_init) if guess is None else guess
        bounds = self.bounds(x_init, effort_limits, velocity_limits)
        start = time.perf_counter()
        sol = self.solver(x0=w0, p=np.concatenate([pref.reshape(-1), post]), **bounds)
        wall = time.perf_counter() - start
        stats = self.solver.stats()
        result = self._result(np.asarray(sol["x"]).reshape(-1), pref, float(sol["f"]), stats, wall)
        if raise_on_failure and not result.success:
            raise SolverError(
                f"tracking OCP ({self.solver_name}) failed: {result.status} "
                f"after {result.iterations} iterations"
            )
        return result

    def _result(
        self, w: np.ndarray, pref: np.ndarray, f: float, stats: dict[str, Any], wall: float
    ) -> TrackingResult:
        n = self.sm.nv
        x, u = self._split(w)
        zs = np.hstack([x[:-1], u, x[1:]]).T
        outs = [np.asarray(o).T for o in self.outputs.map(self.N)(zs)]  # V, A, tau, p
        grid = (np.arange(self.N + 1) * self.h, x[:, :n], x[:, n:], self.collocation_times())
        return make_result(grid, u.reshape(-1, n), outs, pref, f, stats, wall, self.solver_name)


__all__ = ["TrackingOCP", "TrackingResult"]
