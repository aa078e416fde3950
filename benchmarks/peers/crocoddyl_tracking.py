"""Crocoddyl on the tracking OCP of ``benchmarks/bench_ocp.py --peer``: paper 000's reference on
``rcm_two_mass``, one period, N intervals, the same weights (run in the Crocoddyl venv,
which pins its own Pinocchio; it needs neither rcm_pin nor CasADi):

    /work/venvs/crocoddyl/bin/python benchmarks/peers/crocoddyl_tracking.py --rounds 5

Prints one JSON document: per case the median solve time [ms] of ``rounds`` solves, the
iterations, the stop value, feasibility and the tracking error at the nodes.

The problem, faithful to :mod:`ocp.tracking`'s cost (``ocp.paper000.build``):

* model ``urdf/rcm_two_mass.urdf`` (the catalogue's default rendering), frame ``tool``;
* state x = (q, v), control u = tau (fully actuated), forward dynamics integrated by
  symplectic Euler (``IntegratedActionModelEuler``), dt = T / N, T = 2 pi / 10 s;
* running cost at node k, t_k = k dt: ``w_p |p(q_k) - p_ref(t_k)|^2`` (w_p = 1e6 / m^2,
  time-averaged like rcm-pin's: the weight is 2 w_p / T, Crocoddyl halves a quadratic
  residual and multiplies by dt), the posture weights (zero on this model: no wrist) and
  the effort weight (zero, as in rcm-pin; FDDP converges without a regularisation);
  terminal: the position at T;
* x_0 = the analytic solution at t = 0 (here by Newton IK and v = J^-1 p'), the guess
  x_k = x_0, u_k = the quasi-static efforts (Crocoddyl's "hold" guess);
* cases: ``unlimited`` (FDDP), ``urdf_limits`` (BoxFDDP, |u| <= the URDF efforts, inactive)
  and ``binding_limits`` (BoxFDDP and mim-solvers' CSQP, |u| <= 0.8 x the exact solution's
  peak efforts, computed here by the same analytic route as ``ocp.paper000.peak_efforts``).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

import numpy as np

URDF = Path(__file__).resolve().parents[2] / "urdf" / "rcm_two_mass.urdf"
FRAME = "tool"
OMEGA = 10.0
HORIZON = 2.0 * np.pi / OMEGA
POSITION_WEIGHT = 1e6  # [1/m^2], ocp.tracking's default
EFFORT_WEIGHT = 0.0  # [1/(N m)^2], ocp.tracking's default (FDDP needs no regularisation here)
CENTRE, AMPLITUDE, PHASE = np.full(3, 0.1), np.full(3, 0.01), np.array([0.0, np.pi / 2, 0.0])
MAX_ITER = {"unlimited": 200, "urdf_limits": 200, "binding_limits": 1000}


def reference(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """p, p', p'' of paper 000's reference at times t (..., 3)."""
    arg = OMEGA * np.asarray(t, float)[..., None] + PHASE
    return (
        CENTRE + AMPLITUDE * np.sin(arg),
        AMPLITUDE * OMEGA * np.cos(arg),
        -AMPLITUDE * OMEGA**2 * np.sin(arg),
    )


def exact(model: Any, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The analytic solution q, v, a, tau at times t: Newton IK of p_ref (q1, q2 in the
    paper's branch), v = J^-1 p', a = J^-1 (p'' - J' v), tau = RNEA."""
    import pinocchio as pin

    data, fid = model.createData(), model.getFrameId(FRAME)
    frame = pin.LOCAL_WORLD_ALIGNED
    p, dp, ddp = reference(t)
    q = np.array([-0.8, 0.6, 0.18])
    out = np.zeros((4, len(p), model.nv))
    for k in range(len(p)):
        for _ in range(50):
            pin.framesForwardKinematics(model, data, q)
            err = data.oMf[fid].translation - p[k]
            if np.abs(err).max() < 1e-15:
                break
            jac = pin.computeFrameJacobian(model, data, q, fid, frame)[:3]
            q = q - np.linalg.solve(jac, err)
        jac = pin.computeFrameJacobian(model, data, q, fid, frame)[:3]
        v = np.linalg.solve(jac, dp[k])
        pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
        drift = pin.getFrameClassicalAcceleration(model, data, fid, frame).linear
        a = np.linalg.solve(jac, ddp[k] - drift)
        out[:, k] = q, v, a, pin.rnea(model, data, q, v, a)
    return out[0], out[1], out[2], out[3]


def problem(
    n_intervals: int, limits: np.ndarray | None, constraints: bool = False
) -> tuple[Any, Any, np.ndarray]:
    """The shooting problem, its model and x_0; ``limits`` bound |u| (None: no bounds), as
    the action models' box (BoxFDDP) or, ``constraints``, as control constraints (CSQP)."""
    import crocoddyl
    import pinocchio as pin

    model = pin.buildModelFromUrdf(str(URDF))
    state = crocoddyl.StateMultibody(model)
    actuation = crocoddyl.ActuationModelFull(state)
    fid, nu, dt = model.getFrameId(FRAME), model.nv, HORIZON / n_intervals
    pref = reference(np.arange(n_intervals + 1) * dt)[0]

    def node(k: int, step: float) -> Any:
        costs = crocoddyl.CostModelSum(state, nu)
        track = crocoddyl.ResidualModelFrameTranslation(state, fid, pref[k], nu)
        weight = 2 * POSITION_WEIGHT / HORIZON
        costs.addCost("position", crocoddyl.CostModelResidual(state, track), weight)
        if step > 0 and EFFORT_WEIGHT > 0:
            reg = crocoddyl.ResidualModelControl(state, nu)
            weight = 2 * EFFORT_WEIGHT / HORIZON
            costs.addCost("effort", crocoddyl.CostModelResidual(state, reg), weight)
        manager = crocoddyl.ConstraintModelManager(state, nu)
        if constraints and limits is not None and step > 0:
            bound = crocoddyl.ResidualModelControl(state, nu)
            box = crocoddyl.ConstraintModelResidual(state, bound, -limits, limits)
            manager.addConstraint("effort", box)
        dyn = crocoddyl.DifferentialActionModelFreeFwdDynamics(state, actuation, costs, manager)
        act = crocoddyl.IntegratedActionModelEuler(dyn, step)
        if limits is not None and step > 0 and not constraints:
            act.u_lb, act.u_ub = -limits, limits
        return act

    q0, v0 = (x[0] for x in exact(model, np.zeros(1))[:2])
    x0 = np.concatenate([q0, v0])
    running = [node(k, dt) for k in range(n_intervals)]
    shooting = crocoddyl.ShootingProblem(x0, running, node(n_intervals, 0.0))
    shooting.nthreads = 1
    return shooting, model, x0


def _solve(kind: str, shooting: Any, x0: np.ndarray, max_iter: int) -> dict[str, Any]:
    import crocoddyl
    import mim_solvers

    if kind == "csqp":
        solver = mim_solvers.SolverCSQP(shooting)
        solver.termination_tolerance = 1e-8
        solver.eps_abs = solver.eps_rel = 1e-10
    else:
        kinds = {"fddp": crocoddyl.SolverFDDP, "boxfddp": crocoddyl.SolverBoxFDDP}
        solver = kinds[kind](shooting)
        solver.th_stop = 1e-12
    xs = [x0.copy() for _ in range(shooting.T + 1)]
    us = list(shooting.quasiStatic(xs[:-1]))
    start = time.perf_counter()
    converged = solver.solve(xs, us, max_iter, False)
    wall = time.perf_counter() - start
    return {
        "solver": solver,
        "ms": 1e3 * wall,
        "iterations": int(solver.iter),
        "converged": bool(converged),
        "cost": float(solver.cost),
        "stop": float(solver.stop),
    }


def _errors(model: Any, solver: Any, limits: np.ndarray | None, n: int) -> dict[str, float]:
    import pinocchio as pin

    data, fid = model.createData(), model.getFrameId(FRAME)
    pref = reference(np.arange(n + 1) * HORIZON / n)[0]
    err = []
    for x, p in zip(solver.xs, pref):
        pin.framesForwardKinematics(model, data, np.asarray(x)[: model.nq])
        err.append(np.linalg.norm(data.oMf[fid].translation - p))
    us = np.array(solver.us)
    out = {"tracking_error": float(max(err)), "dynamics_gap": float(solver.ffeas)}
    if limits is not None:
        out["limit_excess"] = float(np.max(np.abs(us) - limits))
    return out


def run(rounds: int = 5, n_intervals: int = 100) -> dict[str, Any]:
    """Median solve times of ``rounds`` solves per case and solver, after one untimed
    warm-up solve each (prints nothing)."""
    import pinocchio as pin

    model = pin.buildModelFromUrdf(str(URDF))
    tgrid = np.linspace(0.0, HORIZON, 2001)
    peak = np.abs(exact(model, tgrid)[3]).max(0)
    cases = {
        "unlimited": (None, ("fddp",)),
        "urdf_limits": (model.effortLimit.copy(), ("boxfddp",)),
        "binding_limits": (0.8 * peak, ("boxfddp", "csqp")),
    }
    out: dict[str, Any] = {"peer": "crocoddyl", "n_intervals": n_intervals, "rounds": rounds}
    croc = __import__("crocoddyl").__version__
    out["versions"] = {"pinocchio": pin.__version__, "crocoddyl": croc}
    out["peak_efforts"] = peak.tolist()
    for case, (limits, kinds) in cases.items():
        for kind in kinds:
            shooting, model, x0 = problem(n_intervals, limits, kind == "csqp")
            _solve(kind, shooting, x0, MAX_ITER[case])  # warm-up (first-call allocations)
            runs = [_solve(kind, shooting, x0, MAX_ITER[case]) for _ in range(rounds)]
            last = runs[-1]
            row = {k: v for k, v in last.items() if k not in ("solver", "ms")}
            row["solve_ms"] = float(np.median([r["ms"] for r in runs]))
            row.update(_errors(model, last["solver"], limits, n_intervals))
            out[f"{case}/{kind}"] = row
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--n", type=int, default=100)
    args = parser.parse_args()
    print(json.dumps(run(args.rounds, args.n), indent=2))


if __name__ == "__main__":
    main()
