"""Row ``rcm_ik``, the peer: Drake's ``InverseKinematics`` on the same arm (the case's
URDF: the chain's joints, the fingers fixed) with SNOPT.

One program per setup, built once (as Drake's users write a tracking IK): the tip (the
axis frame's origin moved by ``tip_offset`` along its axis) at the target
(``AddPositionConstraint`` with equal bounds, the bounds updated per target by
``set_bounds``), the trocar on the shaft line (``AddPositionConstraint`` on the trocar in
the axis frame: 0 across the axis, free along it; the point-to-line distance constraint
at 0 is not differentiable there and SNOPT fails on it), the joint limits (Drake's
default), the initial guess q_prev (the previous solution; the first from the case's
start configuration). SNOPT's major optimality and feasibility tolerances at
``case["snopt_tol"]`` (1e-10: at IPOPT's 1e-12 SNOPT reports a third of the solves as
failed, with the same errors). Timed: the solves of every target (bounds update, and the
cost's, included).

The cost |q − q_prev|² (the warm start's branch; rcm-pin's RcmIK has none, its LM takes
the minimum-norm step), added once and its coefficients updated per target
(``QuadraticCost.UpdateCoefficients``, convexity given), by default; ``case["cost"] =
"none"`` drops it (a feasibility problem). Why the cost stays, measured on this row
(Drake 1.51, SNOPT at 1e-10, loaded 2-core machine, 2 Dec 2026):

* no cost: 24 of the 100 solves end at SNOPT's info 41 ("current point cannot be
  improved"), the tip 1.1e-8 m off, and it is no faster (min over 15 circles 490 µs per
  target against 454 µs with the cost; medians 1109 / 1117 µs);
* the cost updated per target: 2 failures (info 41 at targets 0 and 99, RCM 8e-9 m and
  1.8e-7 m), RCM median 5.4e-15 m, tip ≤ 2.2e-13 m: bit for bit the solutions of the
  former formulation (a new program and cost per target), which spent 28 µs per target
  building it (the update: 7 µs) and took 572 µs per target (min over 15 circles).

Hence one program and the cost: the fastest at the same failures and accuracy.
"""

from __future__ import annotations

import itertools
from typing import Any

import numpy as np
from pydrake.math import RigidTransform
from pydrake.multibody.inverse_kinematics import InverseKinematics
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant
from pydrake.solvers import SnoptSolver, SolverOptions


def setup(case: dict[str, Any]) -> dict[str, Any]:
    plant = MultibodyPlant(0.0)
    (model,) = Parser(plant).AddModels(case["urdf"])
    root = plant.get_body(plant.GetBodyIndices(model)[0])
    plant.WeldFrames(plant.world_frame(), root.body_frame(), RigidTransform())
    plant.Finalize()
    order = [plant.GetJointByName(j).position_start() for j in case["joints"]]
    assert plant.num_positions() == len(order)
    opts = SolverOptions()
    for name in ("Major optimality tolerance", "Major feasibility tolerance"):
        opts.SetOption(SnoptSolver.id(), name, float(case["snopt_tol"]))
    axis = np.eye(3)[case["axis"]]
    big = np.where(axis > 0, np.inf, 0.0)
    ctx = plant.CreateDefaultContext()
    frame, world = plant.GetFrameByName(case["axis_frame"]), plant.world_frame()
    trocar, targets = np.asarray(case["trocar"]), np.asarray(case["targets"])
    tip = case["tip_offset"] * axis
    ik = InverseKinematics(plant, ctx)
    tip_bounds = ik.AddPositionConstraint(frame, tip, world, targets[0], targets[0])
    ik.AddPositionConstraint(world, trocar, frame, -big, big)  # 0 across the axis
    prog, q = ik.get_mutable_prog(), ik.q()
    cost = None
    if case.get("cost", "quadratic") == "quadratic":
        n = len(order)
        cost = prog.AddQuadraticErrorCost(np.eye(n), np.zeros(n), q).evaluator()
    return {"plant": plant, "ctx": ctx, "order": order, "frame": frame, "axis": axis,
            "tip": tip, "trocar": trocar, "q0": np.asarray(case["q0"]), "targets": targets,
            "ik": ik, "prog": prog, "q": q, "tip_bounds": tip_bounds.evaluator(),
            "cost": cost, "solver": SnoptSolver(), "opts": opts}  # fmt: skip


def solve(state: dict[str, Any], p: np.ndarray, q_prev: np.ndarray) -> tuple[np.ndarray, bool]:
    """One target from ``q_prev`` (Drake's order): the tip bounds and the cost updated."""
    state["tip_bounds"].set_bounds(p, p)
    cost = state["cost"]
    if cost is not None:  # |q − q_prev|² = ½ qᵀ(2I)q − 2 q_prevᵀq + |q_prev|²
        n = len(q_prev)
        cost.UpdateCoefficients(2.0 * np.eye(n), -2.0 * q_prev, float(q_prev @ q_prev), True)
    result = state["solver"].Solve(state["prog"], q_prev, state["opts"])
    return result.GetSolution(state["q"]), result.is_success()


def run_once(state: dict[str, Any]) -> list[tuple[np.ndarray, bool]]:
    order = state["order"]
    q = np.zeros(len(order))
    q[order] = state["q0"]
    out = []
    for p in state["targets"]:
        q, ok = solve(state, p, q)
        out.append((q, ok))
    return out


def accuracy(state: dict[str, Any], out: list[tuple[np.ndarray, bool]]) -> dict[str, Any]:
    plant, ctx, frame = state["plant"], state["ctx"], state["frame"]
    rcm, tips = [], []
    for (q, _), p in zip(out, state["targets"]):
        plant.SetPositions(ctx, q)
        X = plant.CalcRelativeTransform(ctx, plant.world_frame(), frame)
        a, o = X.rotation().matrix() @ state["axis"], X.translation()
        d = state["trocar"] - o
        rcm.append(float(np.linalg.norm(d - (d @ a) * a)))
        tips.append(float(np.linalg.norm(X.multiply(state["tip"]) - p)))
    qs = [q for q, _ in out]
    return {"rcm_error_max_m": max(rcm), "rcm_error_median_m": float(np.median(rcm)),
            "tip_error_max_m": max(tips),
            "failures": sum(not ok for _, ok in out),
            "step_dq_max": float(max(np.abs(b - a).max()
                                     for a, b in itertools.pairwise(qs)))}  # fmt: skip
