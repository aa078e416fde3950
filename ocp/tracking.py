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
* solve: ``reduced=True`` (the default with Radau and IPOPT, :mod:`ocp.tracking_reduced`)
  solves the gaps for the node states: Newton's method on the collocation positions solves
  the problem without path constraints and its solution is returned when it keeps every
  limit (a KKT point, zero multipliers); else IPOPT solves the reduced NLP. ``reduced=False``
  (or fatrop, whose ``[x_k, u_k]`` / ``[gap_k, path_k]`` order is given manually): the full
  NLP. Derivatives are assembled stage by stage (:mod:`ocp.stagewise`); ``jit=True``:
  CasADi's JIT; ``compile=True`` (or C flags, ``"-O0"``): :mod:`ocp.compiled`'s disk cache,
  once per model, frame, scheme, weights and limits present (h is a stage parameter);
  ``hessian="cost"`` (IPOPT's default): the cost's Hessian only (exact while the limits are
  inactive, the same KKT point when they bind), ``"exact"`` (fatrop's) the Lagrangian's.

The model is a serial :class:`rcm_pin.Mechanism` (default frame: its tool frame) or a
``pin.Model`` with a frame (efforts by the tree's inverse dynamics: closed ones refused).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any, Literal

import casadi as ca
import numpy as np

from ocp.collocation import Scheme, collocation
from ocp.models import ModelSource, require_serial, resolve
from ocp.stagewise import Hessian, StagewiseNLP
from ocp.symbolic import JIT_OPTIONS, SymbolicModel
from ocp.tracking_grid import BYTES_PER_VARIABLE, MAX_BYTES, TrackingGrid, check_size
from ocp.tracking_options import nlp_options
from ocp.tracking_reduced import ReducedTracking
from ocp.tracking_result import TrackingResult, make_result
from ocp.tracking_stage import StageCost, tracking_stage
from rcm_pin.errors import InvalidInputError, SolverError

Reference = Callable[[np.ndarray], np.ndarray] | np.ndarray


class TrackingOCP(TrackingGrid):
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
        hessian: Hessian | None = None,
        compile: bool | str = False,
        reduced: bool = True,
    ) -> None:
        require_serial(model, "the tracking OCP")
        src = resolve(model, frame)
        self.sm: SymbolicModel = src.sm
        sm, n = self.sm, self.sm.nv
        if sm.nq != sm.nv:
            raise InvalidInputError("tracking needs nq == nv (no continuous joints)")
        if horizon <= 0 or n_intervals < 1 or solver not in ("ipopt", "fatrop"):
            raise InvalidInputError("need horizon > 0, n_intervals >= 1, solver ipopt|fatrop")
        check_size(n_intervals, n, degree)
        hessian = hessian or ("exact" if solver == "fatrop" else "cost")
        fatrop_custom = solver == "fatrop" and (hessian != "exact" or bool(compile))
        if hessian not in ("exact", "cost") or fatrop_custom or (jit and compile):
            raise InvalidInputError(
                f"hessian={hessian!r}, compile={compile!r} with solver={solver!r}, "
                f"jit={jit!r}; valid: hessian 'exact' | 'cost', compile and 'cost' with "
                "solver 'ipopt' only (fatrop differentiates the expanded NLP itself), "
                "compile without jit (it replaces it)"
            )
        self.fid, self.solver_name = src.frame_id, solver
        self.T, self.N, self.col = float(horizon), int(n_intervals), collocation(degree, scheme)
        self.h, d = self.T / self.N, degree
        self.lower = np.asarray(sm.model.lowerPositionLimit if lower is None else lower, float)
        self.upper = np.asarray(sm.model.upperPositionLimit if upper is None else upper, float)
        posture_w = np.zeros(n) if posture_weights is None else np.asarray(posture_weights, float)
        self.drive_limits, self.velocity_limits = drive_limits, velocity_limits
        self.nx, self.nu = 2 * n, n * d
        self._cost = StageCost(float(position_weight), posture_w, float(effort_weight))
        self.stage, self.outputs = tracking_stage(
            sm, self.fid, self.col, self._cost, drive_limits, velocity_limits
        )
        self._settings = (solver, tol, max_iter, jit, hessian, compile)
        self.nlp, self.solver = self._nlp_solver(self.stage)
        self._unlimited: tuple[StagewiseNLP, ca.Function] | None = None
        self.reduced = bool(reduced) and solver == "ipopt" and scheme == "radau"
        self._reduced: ReducedTracking | None = None

    def _nlp_solver(self, stage: ca.Function) -> tuple[StagewiseNLP, ca.Function]:
        """The NLP over all stages (variables in fatrop's ``[x_0, u_0, ..., x_N]`` order)."""
        solver, tol, max_iter, jit, hessian, compile = self._settings
        nlp = StagewiseNLP(
            stage,
            self.N,
            self.nx + self.nu,
            self.nx,
            *self.parameter_symbols(),
            dict(JIT_OPTIONS) if jit else {},
            hessian=hessian,
            compile=("-O1" if compile is True else compile) or None,
        )
        problem = nlp.nlp if solver == "ipopt" else nlp.expanded()
        opts = nlp_options(nlp, solver, tol, max_iter, stage.size1_out(0) - self.nx, self)
        return nlp, ca.nlpsol(f"tracking_{solver}", solver, problem, opts)

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
        screen: bool = True,
    ) -> TrackingResult:
        """Track ``reference`` (callable ``t -> (..., 3)`` or ``(N d, 3)`` array) from the
        state ``x_init = (q, v)``; ``effort_limits`` (nv,) bound ``|tau|``.

        ``screen=True`` (the default) with finite limits first solves without the path
        constraints (Newton's method; with ``reduced=False`` an NLP built on first use): a
        solution within the limits is a KKT point of the limited problem (zero multipliers)
        and is returned; otherwise the limited problem is solved from the same guess
        (iterations and solve time then count both). Paper 000, URDF limits: Newton's q is
        2e-16 from the analytic zero-cost solution (the unlimited IPOPT solve 2e-13, the
        limited one 1.4e-11: its barrier bias). Without finite limits Newton's method serves
        whatever ``screen`` (IPOPT when its solution leaves a joint limit or it fails).
        """
        tc = self.collocation_times()
        pref = np.asarray(reference(tc) if callable(reference) else reference, dtype=float)
        x_init = np.asarray(x_init, dtype=float).reshape(-1)
        if pref.shape != (len(tc), 3) or x_init.shape != (self.nx,):
            raise InvalidInputError(f"reference must be ({len(tc)}, 3), x_init ({self.nx},)")
        post = np.zeros(self.sm.nv) if posture is None else np.asarray(posture, float)
        w0 = self.hold_guess(x_init) if guess is None else guess
        bounds = self.bounds(x_init, effort_limits, velocity_limits)
        pars, screened = np.concatenate([pref.reshape(-1), post]), None
        limits = (effort_limits, velocity_limits)
        finite = any(lim is not None and np.isfinite(lim).any() for lim in limits)
        if self.reduced:
            route = self._route()
            if screen or not finite:
                newton = route.solve_newton(w0, pref, post, x_init, self._settings[2])
                screened = self._result(pref, *newton)
                if screened.success and self.keeps(screened, limits):
                    return screened
            result = self._result(pref, *route.solve_ipopt(w0, pars, bounds, x_init))
        elif screen and finite:
            screened, within = self._screen(w0, pars, pref, bounds, limits)
            result = screened if within else self._call(self.solver, w0, pars, pref, bounds)
        else:
            result = self._call(self.solver, w0, pars, pref, bounds)
        if result is screened:
            return result
        if screened is not None:
            result = replace(
                result,
                iterations=result.iterations + screened.iterations,
                solve_time=result.solve_time + screened.solve_time,
            )
        if raise_on_failure and not result.success:
            raise SolverError(
                f"tracking OCP ({self.solver_name}) failed: {result.status} "
                f"after {result.iterations} iterations"
            )
        return result

    def _call(
        self, solver: ca.Function, w0: np.ndarray, pars: np.ndarray, pref: np.ndarray, bounds: Any
    ) -> TrackingResult:
        start = time.perf_counter()
        sol = solver(x0=w0, p=pars, **bounds)
        wall = time.perf_counter() - start
        w, f = np.asarray(sol["x"]).reshape(-1), float(sol["f"])
        return self._result(pref, w, f, solver.stats(), wall, self.solver_name)

    def _free_stage(self) -> ca.Function:
        """The stage without path constraints (gaps only)."""
        return tracking_stage(self.sm, self.fid, self.col, self._cost, False, False)[0]

    def limited_stats(self) -> dict[str, Any]:
        """``stats()`` of the last solve of the problem with path constraints (IPOPT's on
        the reduced NLP with ``reduced=True``, else the full NLP's); {} before any."""
        try:
            return dict((self._route()._solver() if self.reduced else self.solver).stats())
        except RuntimeError:  # CasADi: no stats before the first evaluation
            return {}

    def _route(self) -> ReducedTracking:
        """The reduced problem's solvers (:mod:`ocp.tracking_reduced`), built on first use."""
        if self._reduced is None:
            _, tol, max_iter, jit, hessian, compile = self._settings

            def options(nlp: StagewiseNLP, n_path: int) -> dict[str, Any]:
                return nlp_options(nlp, "ipopt", tol, max_iter, n_path, self)

            self._reduced = ReducedTracking(
                self,
                self._free_stage(),
                self.stage,
                opts=dict(JIT_OPTIONS) if jit else None,
                compile=("-O1" if compile is True else compile) or None,
                hessian=hessian,
                ipopt_options=options,
            )
        return self._reduced

    def _screen(
        self,
        w0: np.ndarray,
        pars: np.ndarray,
        pref: np.ndarray,
        bounds: dict[str, np.ndarray],
        limits: tuple[np.ndarray | None, np.ndarray | None],
    ) -> tuple[TrackingResult, bool]:
        """The solve without path constraints, and whether it succeeded within the limits."""
        if self._unlimited is None:
            self._unlimited = self._nlp_solver(self._free_stage())
        gaps = np.zeros(self.N * self.nx)
        free = {"lbx": bounds["lbx"], "ubx": bounds["ubx"], "lbg": gaps, "ubg": gaps}
        res = self._call(self._unlimited[1], w0, pars, pref, free)
        within = res.success
        for lim, value in zip(limits, (res.tau, res.v_colloc)):
            within = within and (lim is None or bool(np.all(np.abs(value) <= lim)))
        return res, within

    def _result(
        self,
        pref: np.ndarray,
        w: np.ndarray,
        f: float,
        stats: dict[str, Any],
        wall: float,
        solver: str,
    ) -> TrackingResult:
        n = self.sm.nv
        x, u = self._split(w)
        zs = np.hstack([x[:-1], u, x[1:]]).T
        outs = [np.asarray(o).T for o in self.outputs.map(self.N)(zs, 1.0 / self.h)]
        grid = (np.arange(self.N + 1) * self.h, x[:, :n], x[:, n:], self.collocation_times())
        return make_result(grid, u.reshape(-1, n), outs, pref, f, stats, wall, solver)


__all__ = ["BYTES_PER_VARIABLE", "MAX_BYTES", "TrackingOCP", "TrackingResult", "check_size"]
