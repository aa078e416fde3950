"""The IK least-squares program handed to a CasADi ``nlpsol`` (IPOPT or SQP).

    minimise_q   1/2 |r(q, target)|^2
    subject to   lbg <= g(q) <= ubg          (ocp.ik_constraints)
                 c_j^2 + s_j^2 = 1           (each continuous joint's (cos, sin) pair)
                 lower <= q <= upper

``target`` is the NLP parameter, so one solver instance serves every target; ``q0`` is
the (warm) start. IPOPT uses the exact Hessian; ``sqpmethod`` uses ``qrqp`` with the
exact Hessian convexified by eigenvalue clipping (``regularize`` stalls on these
problems) and tolerances below 1e-10 raised to 1e-10. IPOPT runs with the monotone
barrier strategy: the adaptive one wanders near the singular Hessians of redundant or
zero-residual least squares and leaves residuals ~1e-8 near bounds.
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from ocp.symbolic import JIT_OPTIONS, SymbolicModel

_OK = {"Solve_Succeeded", "Solved_To_Acceptable_Level", "SOLVER_RET_SUCCESS"}


def _options(name: str, tol: float, max_iter: int, jit: bool) -> dict[str, Any]:
    opts: dict[str, Any] = dict(JIT_OPTIONS) if jit else {}
    opts["error_on_fail"] = False
    if name == "ipopt":
        opts.update(
            print_time=False,
            ipopt={
                "print_level": 0,
                "sb": "yes",
                "tol": tol,
                "max_iter": max_iter,
                "acceptable_tol": 1e-9,
                "acceptable_iter": 5,
                "mu_strategy": "monotone",
                "hessian_approximation": "exact",
                "warm_start_init_point": "no",
            },
        )
    else:
        opts.update(
            print_time=False,
            print_header=False,
            print_iteration=False,
            print_status=False,
            qpsol="qrqp",
            max_iter=max_iter,
            tol_pr=max(tol, 1e-10),
            tol_du=max(tol, 1e-10),
            convexify_strategy="eigen-clip",
            convexify_margin=1e-8,
            qpsol_options={
                "print_iter": False,
                "print_header": False,
                "print_info": False,
                "error_on_fail": False,
            },
        )
    return opts


class NlpSolver:
    """A built ``nlpsol`` with its bounds; :meth:`solve` returns raw results."""

    def __init__(
        self,
        name: str,
        sm: SymbolicModel,
        q: Any,
        target: Any,
        r: Any,
        g: Any,
        lbg: np.ndarray,
        ubg: np.ndarray,
        lower: np.ndarray,
        upper: np.ndarray,
        tol: float,
        max_iter: int,
        jit: bool,
    ) -> None:
        norms = [
            q[j.idx_q] ** 2 + q[j.idx_q + 1] ** 2 - 1.0
            for j in sm.joints
            if j.kind == "revolute_unbounded" and not j.mimic
        ]
        g_all = ca.vertcat(g, *norms)
        self.lbg = np.concatenate([lbg, np.zeros(len(norms))])
        self.ubg = np.concatenate([ubg, np.zeros(len(norms))])
        self.lower, self.upper, self.name = lower, upper, name
        nlp = {"x": q, "p": target, "f": 0.5 * ca.sumsqr(r), "g": g_all}
        self.solver = ca.nlpsol(f"ik_{name}", name, nlp, _options(name, tol, max_iter, jit))

    def solve(self, q0: np.ndarray, tvec: np.ndarray) -> tuple[np.ndarray, str, int, bool]:
        """``(q, status, iterations, solver_success)`` from the start ``q0``."""
        sol = self.solver(x0=q0, p=tvec, lbx=self.lower, ubx=self.upper, lbg=self.lbg, ubg=self.ubg)
        stats = self.solver.stats()
        status = str(stats.get("return_status", "unknown"))
        ok = bool(stats.get("success", False)) or status in _OK
        return (
            np.asarray(sol["x"], dtype=float).reshape(-1),
            status,
            int(stats.get("iter_count", -1)),
            ok,
        )


__all__ = ["NlpSolver"]
