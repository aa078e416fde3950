"""Rows ``tracking_*``, the peer: rcm-pin's tracking problem in Crocoddyl (its own venv:
pin 4.0.0, crocoddyl 3.2.1, mim-solvers). THE Crocoddyl side of the comparison (it
replaces the former standalone script ``crocoddyl_tracking.py``, removed, whose problem
differed; see below).

The problem, as rcm-pin's (``ocp.tracking``, ``ocp.paper000``):

* the same URDF (``case["urdf"]``), frame, horizon T, N, initial state x0 (the analytic
  solution at t = 0) and reference; state (q, v), control u = tau (full actuation),
  forward dynamics (``DifferentialActionModelFreeFwdDynamics``) integrated by
  ``IntegratedActionModelEuler`` (symplectic Euler: v+ = v + dt a, q+ = q + dt v+),
  dt = T / N: Crocoddyl's usual transcription;
* the same cost terms and weights: rcm-pin minimises (1/T) Σ_k h Σ_r B_r w_p |p(Q_r) −
  p_ref|² (no effort or posture term on this model); Crocoddyl's running node k costs
  dt · (weight/2) |p(q_k) − p_ref(t_k)|², so weight = 2 w_p / T gives the same objective
  value on a rectangle rule; the terminal node (Crocoddyl does not multiply it by dt)
  gets 2 w_p dt / T, so nodes 1..N weigh alike (node 0 is fixed by x0), as Radau's last
  point t_{k+1} of each interval does in rcm-pin's quadrature;
* no control regularisation (rcm-pin has none): FDDP and BoxFDDP converge without one;
* the guess Crocoddyl users write: x_k = x0, u_k = ``problem.quasiStatic`` (rcm-pin's
  "hold" guess); cold every run;
* one thread (``problem.nthreads = 1``, ``case["threads"]``): rcm-pin's solve is
  single-threaded, and on the shared 2-core machine Crocoddyl's default two OpenMP
  threads made the same solve 5–10× slower.

``case["solver"]``: ``fddp`` (no limits), ``boxfddp`` (the effort limits as control bounds),
``csqp`` (mim-solvers' SQP, the limits as control constraints). Stopping: ``th_stop`` 1e-12
(rcm-pin's IPOPT tol) within ``case["max_iter"]`` (default 500). With binding limits BoxFDDP
converges (483 iterations, stop 3e-14, cost 99.7819); CSQP meets no KKT threshold: its KKT
measure stalls at 2.5e-3 from iteration 200 on with its default ADMM tolerances
(eps_abs = eps_rel = 1e-4), and at 6e-5 (line search stuck at iteration 167) with 1e-6,
whose QPs hit their 1000-iteration cap (15–25× the time per iteration; the former script's
1e-10: 57 ms per iteration). So CSQP keeps its defaults and ``termination_tolerance`` 1e-12
and stops at 100 iterations (default ``max_iter`` for csqp: cost 99.7855, 4e-5 relative
above BoxFDDP's optimum, node error as BoxFDDP's to 1e-4 m), reported ``converged: false``;
a new CSQP solver per run, since it carries its ADMM state from one solve to the next
(the second solve of the same problem was 1.8× slower, to another point).

Choices against the former standalone script (the same transcription, solver and guess):
it weighted the terminal node 2 w_p / T, 100× a running node (1/dt), so its binding-limits
optimum was another problem (BoxFDDP stopped at 339 iterations, not converged, cost 415);
this worker's first version halved the weights (w_p / T: the same optimum, but every
stopping threshold twice as loose) and added a 1e-8 control regularisation, which cost
FDDP 1.3e-10 m of node tracking error (5e-17 m without) and kept BoxFDDP from converging
with binding limits (583 iterations, then failure). RK4 (``IntegratedActionModelRK``) is
closer to Radau between the nodes, but its optimum (a constant u per interval) ends 5e-4 m
off the reference at the nodes, in 8× Euler's time: not taken.

The problem that remains different: Euler with one control per interval against Radau IIA
d = 3 (three collocation points, efforts at each); both meet the reference exactly at the
nodes without limits, so the tracking error is compared at the N + 1 nodes; with binding
limits the two optima differ by the transcription (objectives 101.28 and 99.78, node
tracking errors 0.0156 and 0.0160 m), and the limits hold at Crocoddyl's u_k, at rcm-pin's
collocation points. Timed: ``solve``."""

from __future__ import annotations

from typing import Any

import crocoddyl
import numpy as np
import pinocchio as pin
from common import reference


def _node(state: Any, fid: int, p_ref: np.ndarray, w: float, lim: Any, csqp: bool) -> Any:
    nu = state.nv
    costs = crocoddyl.CostModelSum(state, nu)
    track = crocoddyl.ResidualModelFrameTranslation(state, fid, p_ref, nu)
    costs.addCost("track", crocoddyl.CostModelResidual(state, track), w)
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
    dt, w = T / N, 2.0 * case["position_weight"] / T
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
    xs = [x0.copy() for _ in range(N + 1)]
    us = list(problem.quasiStatic(xs[:-1]))
    out = {"problem": problem, "xs": xs, "us": us, "model": model, "t": t, "case": case,
           "lim": lim, "csqp": solver_name == "csqp"}  # fmt: skip
    if solver_name == "csqp":
        out["max_iter"] = int(case.get("max_iter", 100))
    else:
        cls = crocoddyl.SolverBoxFDDP if solver_name == "boxfddp" else crocoddyl.SolverFDDP
        out["solver"] = cls(problem)
        out["solver"].th_stop = 1e-12
        out["max_iter"] = int(case.get("max_iter", 500))
    return out


def _csqp(problem: Any) -> Any:
    import mim_solvers

    solver = mim_solvers.SolverCSQP(problem)
    solver.termination_tolerance = 1e-12
    return solver


def run_once(state: dict[str, Any]) -> Any:
    # CSQP keeps its ADMM state (rho adapted from 0.1 to ~230, the duals) from one solve to
    # the next: a new solver per run keeps every run cold (its construction is timed, well
    # under 1 % of the solve); FDDP and BoxFDDP reset their regularisation in ``solve``.
    solver = _csqp(state["problem"]) if state["csqp"] else state["solver"]
    ok = solver.solve(state["xs"], state["us"], state["max_iter"], False)
    return ok, int(solver.iter), np.array(solver.xs), np.array(solver.us), float(solver.cost)


def accuracy(state: dict[str, Any], result: Any) -> dict[str, Any]:
    ok, iters, xs, us, cost = result
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
    return {**out, "objective": cost, "iterations": iters, "converged": bool(ok)}
