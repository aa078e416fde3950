"""Row ``rcm_ik``, the peer: Drake's ``InverseKinematics`` on the same arm (the case's
URDF: the chain's joints, the fingers fixed) with SNOPT. Per target: the tip (the axis
frame's origin moved by ``tip_offset`` along its axis) at the target
(``AddPositionConstraint``, equality), the trocar on the shaft line
(``AddPositionConstraint`` on the trocar in the axis frame: 0 across the axis, free along
it; the point-to-line distance constraint at 0 is not differentiable there and SNOPT
fails on it), the joint limits (Drake's default),
a quadratic cost |q − q_prev|² (the warm start's branch; rcm-pin's RcmIK minimises the
tip error instead, with the RCM as an equality), the initial guess q_prev; SNOPT's major
optimality and feasibility tolerances at ``case["snopt_tol"]`` (1e-10: at IPOPT's 1e-12
SNOPT reports a third of the solves as failed, with the same errors). Timed: building and solving
the program of every target (Drake's users build one per target)."""

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
    return {"plant": plant, "ctx": plant.CreateDefaultContext(), "order": order,
            "frame": plant.GetFrameByName(case["axis_frame"]), "axis": axis,
            "tip": case["tip_offset"] * axis, "line_lo": -big, "line_hi": big,
            "trocar": np.asarray(case["trocar"]),
            "q0": np.asarray(case["q0"]), "targets": np.asarray(case["targets"]),
            "solver": SnoptSolver(), "opts": opts}  # fmt: skip


def solve(state: dict[str, Any], p: np.ndarray, q_prev: np.ndarray) -> tuple[np.ndarray, bool]:
    """One target from ``q_prev`` (Drake's order)."""
    plant, frame, world = state["plant"], state["frame"], state["plant"].world_frame()
    ik = InverseKinematics(plant, state["ctx"])
    ik.AddPositionConstraint(frame, state["tip"], world, p, p)
    ik.AddPositionConstraint(world, state["trocar"], frame, state["line_lo"],
                             state["line_hi"])  # trocar on the axis: 0 across it  # fmt: skip
    q = ik.q()
    prog = ik.get_mutable_prog()
    prog.AddQuadraticErrorCost(np.eye(len(q_prev)), q_prev, q)
    result = state["solver"].Solve(prog, q_prev, state["opts"])
    return result.GetSolution(q), result.is_success()


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
