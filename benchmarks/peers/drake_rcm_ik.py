"""Peer: RCM inverse kinematics of panda in Drake (InverseKinematics + SNOPT).

The problem (shared with ``benchmarks/bench_rcm_ik.py``, which imports :func:`problem_spec`,
:func:`kinematic_urdf` and :func:`circle` from this file; they need numpy only):

* panda of example-robot-data, kinematics only (visuals, collisions and the two finger
  joints dropped: 7 revolute joints);
* the tool shaft is the z axis of ``panda_hand``; the tip is :data:`SHAFT` along it;
* the start pose :data:`Q_START` ("ready"); the trocar is on the shaft :data:`DEPTH` from
  the hand at the start pose;
* :data:`N_TARGETS` tip targets on a circle of radius :data:`RADIUS` around the start tip,
  in the plane orthogonal to the start shaft; each solve is warm-started from the previous
  solution (the first from the start pose).

Drake's formulation: one ``InverseKinematics`` program built once, joint limits on; the tip
a ``PositionConstraint`` with equal bounds (updated per target); the RCM a
``PositionConstraint`` of the trocar (a point fixed in the world) measured in the hand
frame with x = y = 0 (the two components of p_T − p_s orthogonal to the shaft, the same
residual as rcm-pin's); no cost (a feasibility problem). SNOPT with its default
tolerances and "tight" ones (major feasibility and optimality 1e-12); IPOPT in Drake if
SNOPT is not available (said in the output). The errors are recomputed by Drake forward
kinematics (distance of the trocar from the shaft line, |tip − target|).

Run with Drake's interpreter: ``python benchmarks/peers/drake_rcm_ik.py --rounds 5``
(JSON on stdout; ``--urdf`` overrides the search for panda.urdf). For the harness of
``benchmarks/peers/worker.py``: ``setup(case)`` (case keys ``tolerance``: None = SNOPT's
defaults, or a number; ``urdf``) and ``run_once(state)`` (the circle once; its worst
errors and failures).
"""

from __future__ import annotations

import argparse
import glob
import json
import os
import sys
import time
import xml.etree.ElementTree as ET
from typing import Any

import numpy as np

#: Start pose ("ready") [rad].
Q_START = (0.0, -0.785398, 0.0, -2.356194, 0.0, 1.570796, 0.785398)
#: The shaft's frame (its z axis is the shaft) and the tip beyond its origin [m].
HAND, SHAFT = "panda_hand", 0.3
#: Trocar on the start shaft, from the hand origin [m].
DEPTH = 0.15
#: Circle of tip targets around the start tip [m] and their number.
RADIUS, N_TARGETS = 0.03, 100
#: SNOPT's "tight" tolerances (major feasibility / optimality).
TIGHT = 1e-12
PANDA = "example-robot-data/robots/panda_description/urdf/panda.urdf"


def find_urdf(path: str | None = None) -> str:
    """``path``, ``$PANDA_URDF``, or panda.urdf of an installed example-robot-data."""
    if path or os.environ.get("PANDA_URDF"):
        return str(path or os.environ["PANDA_URDF"])
    here = os.path.dirname(os.path.abspath(__file__))
    roots = [sys.prefix, os.path.join(here, "..", "..", ".venv"), "/work/main/.venv"]
    for root in roots:
        hits = glob.glob(os.path.join(root, "lib", "python*", "site-packages", "cmeel.prefix",
                                      "share", PANDA))  # fmt: skip
        if hits:
            return hits[0]
    raise FileNotFoundError(f"no {PANDA}; pass --urdf or set PANDA_URDF")


def kinematic_urdf(path: str) -> str:
    """The URDF text with only links (no visuals, collisions) and joints, fingers removed."""
    root = ET.parse(path).getroot()
    fingers = {"panda_leftfinger", "panda_rightfinger"}
    for child in list(root):
        if child.tag == "link" and child.get("name") not in fingers:
            for sub in list(child):
                if sub.tag in ("visual", "collision"):
                    child.remove(sub)
        elif child.tag == "joint" and child.find("child").get("link") not in fingers:  # type: ignore[union-attr]
            for sub in list(child):
                if sub.tag in ("safety_controller", "dynamics"):
                    child.remove(sub)
        else:
            root.remove(child)
    return ET.tostring(root, encoding="unicode")


def circle(center: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """(N_TARGETS, 3) points of radius RADIUS around ``center`` orthogonal to ``axis``."""
    a = axis / np.linalg.norm(axis)
    b1 = np.cross(a, np.eye(3)[int(np.argmin(np.abs(a)))])
    b1 /= np.linalg.norm(b1)
    b2 = np.cross(a, b1)
    th = 2.0 * np.pi * np.arange(N_TARGETS) / N_TARGETS
    return center + RADIUS * (np.outer(np.cos(th), b1) + np.outer(np.sin(th), b2))


def problem_spec() -> dict[str, Any]:
    """The constants of the problem (JSON-ready)."""
    return {"q_start": list(Q_START), "frame": HAND, "axis": "z", "shaft": SHAFT,
            "depth": DEPTH, "radius": RADIUS, "n_targets": N_TARGETS}  # fmt: skip


class DrakeRcmIK:
    """The IK program, built once; :meth:`solve` per target."""

    def __init__(self, urdf_text: str, tolerance: float | None) -> None:
        from pydrake.multibody.inverse_kinematics import InverseKinematics
        from pydrake.multibody.parsing import Parser
        from pydrake.multibody.plant import MultibodyPlant
        from pydrake.solvers import IpoptSolver, SnoptSolver, SolverOptions

        plant = MultibodyPlant(0.0)
        Parser(plant).AddModelsFromString(urdf_text, "urdf")
        plant.WeldFrames(plant.world_frame(), plant.GetFrameByName("panda_link0"))
        plant.Finalize()
        self.plant, self.ctx = plant, plant.CreateDefaultContext()
        self.hand, world = plant.GetFrameByName(HAND), plant.world_frame()
        q0 = np.array(Q_START)
        X = self.pose(q0)
        a = X.rotation().matrix()[:, 2]
        self.trocar = X.translation() + DEPTH * a
        self.targets = circle(X.translation() + SHAFT * a, a)
        self.ik = InverseKinematics(plant, with_joint_limits=True)
        tip = np.array([0.0, 0.0, SHAFT])
        self.tip = self.ik.AddPositionConstraint(
            self.hand, tip, world, self.targets[0], self.targets[0]
        ).evaluator()
        big = 1e3  # the trocar's coordinate along the shaft is free
        self.ik.AddPositionConstraint(world, self.trocar, self.hand, np.array([0.0, 0.0, -big]),
                                      np.array([0.0, 0.0, big]))  # fmt: skip
        self.q = self.ik.q()
        snopt = SnoptSolver()
        self.solver: Any = snopt if snopt.available() else IpoptSolver()
        self.solver_name = "SNOPT" if snopt.available() else "IPOPT"
        self.options = SolverOptions()
        if tolerance is not None and self.solver_name == "SNOPT":
            for key in ("Major feasibility tolerance", "Major optimality tolerance"):
                self.options.SetOption(snopt.solver_id(), key, tolerance)
        elif tolerance is not None:
            self.options.SetOption(IpoptSolver().solver_id(), "tol", tolerance)

    def pose(self, q: np.ndarray) -> Any:
        self.plant.SetPositions(self.ctx, q)
        return self.plant.CalcRelativeTransform(self.ctx, self.plant.world_frame(), self.hand)

    def solve(self, target: np.ndarray, q0: np.ndarray) -> tuple[np.ndarray, bool]:
        self.tip.set_bounds(target, target)
        res = self.solver.Solve(self.ik.prog(), q0, self.options)
        return res.GetSolution(self.q), bool(res.is_success())

    def errors(self, q: np.ndarray, target: np.ndarray) -> tuple[float, float]:
        """(distance of the trocar from the shaft line, |tip − target|) [m]."""
        X = self.pose(q)
        p, a = X.translation(), X.rotation().matrix()[:, 2]
        d = self.trocar - p
        rcm = float(np.linalg.norm(d - (d @ a) * a))
        return rcm, float(np.linalg.norm(p + SHAFT * a - target))


def one_round(ik: DrakeRcmIK) -> dict[str, Any]:
    """The circle once: time per target [µs], worst errors, failures."""
    q, qs = np.array(Q_START), []
    fails = 0
    start = time.perf_counter()
    for p in ik.targets:
        q, ok = ik.solve(p, q)
        qs.append(q)
        fails += not ok
    us = (time.perf_counter() - start) / len(ik.targets) * 1e6
    errs = np.array([ik.errors(x, p) for x, p in zip(qs, ik.targets)])
    return {"us": us, "rcm": float(errs[:, 0].max()), "tip": float(errs[:, 1].max()),
            "failures": fails}  # fmt: skip


def setup(case: dict[str, Any]) -> DrakeRcmIK:
    """The program of ``case`` (worker protocol)."""
    return DrakeRcmIK(kinematic_urdf(find_urdf(case.get("urdf"))), case.get("tolerance"))


def run_once(state: DrakeRcmIK) -> dict[str, Any]:
    """The circle once (worker protocol): worst RCM distance and tip error [m], failures."""
    r = one_round(state)
    return {"rcm_max": r["rcm"], "tip_max": r["tip"], "failures": r["failures"],
            "solver": state.solver_name}  # fmt: skip


def run(rounds: int = 5, urdf: str | None = None) -> dict[str, Any]:
    """``rounds`` of the circle for SNOPT's default and tight tolerances, alternating."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        drake_version = version("drake")
    except PackageNotFoundError:
        drake_version = "unknown"
    text = kinematic_urdf(find_urdf(urdf))
    solvers = {"default": DrakeRcmIK(text, None), "tight": DrakeRcmIK(text, TIGHT)}
    per: dict[str, list[dict[str, Any]]] = {k: [] for k in solvers}
    for _ in range(rounds):
        for key, ik in solvers.items():
            per[key].append(one_round(ik))
    ik = solvers["default"]
    out: dict[str, Any] = {
        "peer": "drake", "version": drake_version, "solver": ik.solver_name,
        "problem": problem_spec(),
        "trocar": ik.trocar.tolist(), "targets_first": ik.targets[0].tolist(),
    }  # fmt: skip
    for key, rows in per.items():
        out[key] = {
            "us_per_target": float(np.median([r["us"] for r in rows])),
            "us_rounds": [r["us"] for r in rows],
            "rcm_max": max(r["rcm"] for r in rows),
            "tip_max": max(r["tip"] for r in rows),
            "failures": max(r["failures"] for r in rows),
        }
    return out


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--urdf", default=None)
    args = ap.parse_args()
    print(json.dumps(run(args.rounds, args.urdf)))
