"""Rows ``tracking_*``, the peer: the same tracking problem in Crocoddyl (its own venv:
pin 4.0.0, crocoddyl 3.2.1, mim-solvers). The same URDF (``case["urdf"]``), horizon, N
nodes, initial state and reference; forward dynamics (``DifferentialActionModelFree
FwdDynamics``, full actuation) integrated by ``IntegratedActionModelEuler`` (dt = T/N,
Crocoddyl's usual transcription), cost per node (1/T)·w_p·|p(q_k) − p_ref(t_k)|² (dt
applied by the integrator, as rcm-pin's quadrature weights), plus a 1e-8 control
regularisation (rcm-pin has none; FDDP needs a positive-definite Q_uu).
``case["solver"]``: ``fddp`` (no limits), ``boxfddp`` (the effort limits as control bounds),
``csqp`` (mim-solvers' SQP with the limits as control constraints). Cold start every run:
x_k = x0, u_k quasi-static; stopping threshold 1e-12 (rcm-pin's IPOPT tol), at most
``case["max_iter"]`` iterations (default 500; with binding limits neither BoxFDDP nor CSQP
meets any threshold from 1e-5 to 1e-12 within 500, so that row stops them at 100 and
reports "converged": false beside their tracking error). One thread
(``problem.nthreads = 1``, ``case["threads"]``): rcm-pin's solve is single-threaded, and
on the shared 2-core machine Crocoddyl's default 2 OpenMP threads made the same solve
5-10× slower. Timed: ``solve``."""

from __future__ import annotations

from typing import Any

import crocoddyl
import numpy as np
import pinocchio as pin
from common import reference

REG = 1e-8  # control regularisation weight [1/(N m)^2]


def _node(state: Any, fid: int, p_ref: np.ndarray, w: float, lim: Any, csqp: bool) -> Any:
    nu = state.nv
    costs = crocoddyl.CostModelSum(state, nu)
    track = crocoddyl.ResidualModelFrameTranslation(state, fid, p_ref, nu)
    costs.addCost("track", crocoddyl.CostModelResidual(state, track), w)
    reg = crocoddyl.ResidualModelControl(state, nu)
    costs.addCost("ureg", crocoddyl.CostModelResidual(state, reg), REG)
    act = crocoddyl.ActuationModelFull(state)
    if csqp and lim is not None:
        cons = crocoddyl.ConstraintModelManager(state, nu)
        res = crocoddyl.ResidualModelControl(state, nu)
        cons.addConstraint("effort", crocoddyl.ConstraintModelResidual(state, res, -lim, lim))
        return crocoddyl.DifferentialActionModelFreeFwdDynamics(state, act, costs, cons)
    return crocoddyl.DifferentialActionModelFreeFwdDynamics(state, act, costs)


def setup(case: dict[str, Any]) -> dict[str, Any]:
    model = pin.buildModelFromUrdf(case["urdf"])
    state = crocoddyl.StateMultibody(model)
    fid = model.getFrameId(case["frame"])
    T, N = float(case["horizon"]), int(case["n_intervals"])
    dt, w = T / N, case["position_weight"] / T
    t = np.linspace(0.0, T, N + 1)
    p_ref = reference(case["traj"], t)[0]
    solver_name = case["solver"]
    lim = None if case["effort_limits"] is None else np.asarray(case["effort_limits"])
    models = []
    for k in range(N + 1):
        csqp = solver_name == "csqp" and k < N  # no control at the terminal node
        dam = _node(state, fid, p_ref[k], w if k < N else w * dt, lim, csqp)
        iam = crocoddyl.IntegratedActionModelEuler(dam, dt if k < N else 0.0)
        if lim is not None and solver_name == "boxfddp":
            iam.u_lb, iam.u_ub = -lim, lim
        models.append(iam)
    x0 = np.asarray(case["x0"])
    problem = crocoddyl.ShootingProblem(x0, models[:-1], models[-1])
    problem.nthreads = int(case.get("threads", 1))
    if solver_name == "csqp":
        import mim_solvers

        solver = mim_solvers.SolverCSQP(problem)
        solver.termination_tolerance = 1e-12
    else:
        cls = crocoddyl.SolverBoxFDDP if solver_name == "boxfddp" else crocoddyl.SolverFDDP
        solver = cls(problem)
        solver.th_stop = 1e-12
    xs = [x0.copy() for _ in range(N + 1)]
    us = list(problem.quasiStatic(xs[:-1]))
    return {"solver": solver, "xs": xs, "us": us, "model": model, "t": t, "case": case,
            "lim": lim, "max_iter": int(case.get("max_iter", 500))}  # fmt: skip


def run_once(state: dict[str, Any]) -> Any:
    solver = state["solver"]
    ok = solver.solve(state["xs"], state["us"], state["max_iter"], False)
    return ok, int(solver.iter), np.array(solver.xs), np.array(solver.us)


def accuracy(state: dict[str, Any], result: Any) -> dict[str, Any]:
    ok, iters, xs, us = result
    model, case, lim = state["model"], state["case"], state["lim"]
    data, fid = model.createData(), model.getFrameId(case["frame"])
    p_ref = reference(case["traj"], state["t"])[0]
    err = 0.0
    for x, p in zip(xs, p_ref):
        pin.framesForwardKinematics(model, data, x[: model.nq])
        err = max(err, float(np.linalg.norm(data.oMf[fid].translation - p)))
    out: dict[str, Any] = {"node_tracking_error_m": err}
    if lim is None:
        out["peak_effort_Nm"] = float(np.abs(us).max())
    else:
        out["peak_effort_over_limit"] = float((np.abs(us) / lim).max())
        out["limit_excess"] = float(np.maximum(np.abs(us) - lim, 0.0).max())
    return {**out, "iterations": iters, "converged": bool(ok)}
