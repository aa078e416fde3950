"""The tracking OCP on the collocation positions alone: Newton's method and a reduced NLP.

:class:`ocp.tracking.TrackingOCP` with ``reduced=True`` (Radau): the gap constraints solved
for the node states (:mod:`ocp.tracking_newton`), so that the variables are
``Y = (Q_0, ..., Q_{N-1})`` behind a constant prefix that holds ``x_init``.

* Without path constraints: Newton's method with a sparse LDL^T of the banded Hessian
  (:class:`ocp.tracking_newton.NewtonTracking`); joint limits are checked afterwards.
* With them: IPOPT on the reduced NLP, ``min f(Y)`` s.t. the drive (and velocity) limits per
  stage and the joint limits as bounds, its derivatives assembled stage by stage
  (:class:`ocp.stagewise.StagewiseNLP` over the windows ``y_k`` of stride ``d n``). The same
  KKT points as the full NLP (the eliminated constraints are linear and solved exactly), with
  half its variables and constraints and no gap rows in IPOPT's linear systems.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import casadi as ca
import numpy as np

from ocp.stagewise import Hessian, StagewiseNLP
from ocp.tracking_grid import TrackingGrid
from ocp.tracking_newton import NewtonTracking, newton_for, reduced_stage

#: (variables w in the full layout, objective, solver stats, wall time [s], solver name)
Solved = tuple[np.ndarray, float, dict[str, Any], float, str]


class ReducedTracking:
    """Newton's method and the reduced IPOPT NLP of one tracking OCP (built on first use).

    ``free_stage`` / ``stage``: the stage without / with path constraints; ``opts``: CasADi
    function options (JIT); ``compile``: C flags for :mod:`ocp.compiled`, or None;
    ``ipopt_options(nlp, n_path)``: the nlpsol options of the reduced NLP."""

    def __init__(
        self,
        grid: TrackingGrid,
        free_stage: ca.Function,
        stage: ca.Function,
        *,
        opts: dict[str, Any] | None,
        compile: str | None,
        hessian: Hessian,
        ipopt_options: Callable[[StagewiseNLP, int], dict[str, Any]],
    ) -> None:
        self.grid, self._stage = grid, stage
        n, self._nx = grid.sm.nv, grid.nx
        self.newton: NewtonTracking = newton_for(
            free_stage, grid.col, n, grid.N, opts=opts, compile=compile
        )
        self._build = (opts, compile, hessian, ipopt_options)
        self._ipopt: ca.Function | None = None

    def _w(self, y: np.ndarray, x_init: np.ndarray) -> np.ndarray:
        """The full variable vector (nodes and collocation positions) of the positions y."""
        g = self.grid
        return g._join(self.newton.node_states(y, x_init, g.h), y.reshape(g.N, g.nu))

    def solve_newton(
        self,
        w0: np.ndarray,
        pref: np.ndarray,
        posture: np.ndarray,
        x_init: np.ndarray,
        max_iter: int,
    ) -> Solved:
        """Newton's method without path constraints from the collocation positions of w0."""
        g = self.grid
        y0 = g._split(np.asarray(w0, dtype=float))[1].reshape(-1)
        params = g.stage_parameters(pref, posture)
        start = time.perf_counter()
        res = self.newton.solve(y0, x_init, params, g.h, max_iter=max_iter)
        wall = time.perf_counter() - start
        stats = {"success": res.success, "return_status": res.status, "iter_count": res.iterations}
        return self._w(res.y, x_init), res.objective, stats, wall, "newton"

    def _solver(self) -> ca.Function:
        if self._ipopt is None:
            opts, compile, hessian, ipopt_options = self._build
            g, n = self.grid, self.grid.sm.nv
            nlp = StagewiseNLP(
                reduced_stage(self._stage, g.col, n),
                g.N,
                g.nu,
                self.newton.pad,
                *g.parameter_symbols(),
                opts or {},
                hessian=hessian,
                compile=compile,
            )
            n_path = self._stage.size1_out(0) - self._nx
            self._ipopt = ca.nlpsol(
                "tracking_reduced", "ipopt", nlp.nlp, ipopt_options(nlp, n_path)
            )
        return self._ipopt

    def solve_ipopt(
        self, w0: np.ndarray, pars: np.ndarray, bounds: dict[str, np.ndarray], x_init: np.ndarray
    ) -> Solved:
        """IPOPT on the reduced NLP with the full problem's bounds (``TrackingGrid.bounds``)
        and parameters, from the collocation positions of w0."""
        g, solver = self.grid, self._solver()
        prefix = self.newton.prefix(x_init, g.h)

        def positions(w: np.ndarray) -> np.ndarray:
            return g._split(np.asarray(w, dtype=float))[1].reshape(-1)

        lbx = np.concatenate([prefix, positions(bounds["lbx"])])
        ubx = np.concatenate([prefix, positions(bounds["ubx"])])
        lbg, ubg = (bounds[k].reshape(g.N, -1)[:, self._nx :].reshape(-1) for k in ("lbg", "ubg"))
        x0 = np.concatenate([prefix, positions(w0)])
        start = time.perf_counter()
        sol = solver(x0=x0, p=pars, lbx=lbx, ubx=ubx, lbg=lbg, ubg=ubg)
        wall = time.perf_counter() - start
        y = np.asarray(sol["x"]).reshape(-1)[self.newton.pad :]
        return self._w(y, x_init), float(sol["f"]), solver.stats(), wall, "ipopt"


__all__ = ["ReducedTracking", "Solved"]
