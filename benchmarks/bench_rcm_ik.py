"""RCM inverse kinematics of panda: rcm-pin's routes beside Drake, rounds interleaved.

The problem is the one of ``benchmarks/peers/drake_rcm_ik.py`` (its constants and its
URDF preparation are imported from there): panda's hand z axis as the shaft, the tip
0.3 m along it, the trocar on the shaft at the "ready" pose, 100 tip targets on a 3 cm
circle around the start tip, each solve warm-started from the previous one. Per round:

* ``lm``: :class:`ocp.rcm.RcmIK` with ``solver="lm"`` (compiled projected LM, the default);
* ``ipopt``: the same with ``solver="ipopt"`` (the NLP, tol 1e-12; the route before);
* ``numpy``: a plain Pinocchio + numpy Gauss–Newton on the same residual (frame Jacobian,
  ``lstsq``, clipped to the limits; :class:`NumpyGaussNewton`), the pure-Python alternative;
* ``drake_default`` / ``drake_tight``: Drake's InverseKinematics + SNOPT with its default
  tolerances and with 1e-12 (one round of the peer script in Drake's interpreter, a
  separate process, between rcm-pin's rounds).

Prints one JSON document: µs per target (median over the rounds), the worst RCM distance
and tip error over the circle (by forward kinematics on each side: Pinocchio here, Drake
there), failures, and the ratios of rcm-pin's routes to Drake's, round by round (each
pair measured within the same few seconds of load): their median and range.

    python benchmarks/bench_rcm_ik.py [--rounds 5] [--drake-python PATH]
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import subprocess
import time
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pinocchio as pin

from ocp.rcm import RcmIK
from rcm_pin.control.rcm_task import RcmTool

PEER = Path(__file__).parent / "peers" / "drake_rcm_ik.py"
DRAKE_PYTHON = os.environ.get("DRAKE_PYTHON", "/work/venvs/drake/bin/python")


def _peer() -> Any:
    spec = importlib.util.spec_from_file_location("drake_rcm_ik", PEER)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def problem() -> tuple[pin.Model, RcmTool, np.ndarray, np.ndarray]:
    """(model, tool, start q, targets) of the peer's problem, by Pinocchio FK."""
    d = _peer()
    model = pin.buildModelFromXML(d.kinematic_urdf(d.find_urdf()))
    data, fid = model.createData(), model.getFrameId(d.HAND)
    q0 = np.array(d.Q_START)
    pin.framesForwardKinematics(model, data, q0)
    M = data.oMf[fid]
    a = M.rotation[:, 2]
    trocar = M.translation + d.DEPTH * a
    tool = RcmTool(fid, 2, fid, d.SHAFT, tuple(float(x) for x in trocar), d.HAND)
    return model, tool, q0, d.circle(M.translation + d.SHAFT * a, a)


def _skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


class NumpyGaussNewton:
    """Gauss–Newton on [tip − target; (R e_x, R e_y)ᵀ (p_T − p_s)] with Pinocchio's
    LOCAL_WORLD_ALIGNED hand Jacobian (d(R e)/dq = −[R e]× J_ω); ``solve`` mimics
    :meth:`ocp.rcm.RcmIK.solve` (errors by the same FK)."""

    def __init__(self, model: pin.Model, tool: RcmTool) -> None:
        self.ik = RcmIK(model, tool)  # its errors() only
        self.model, self.data, self.tool = model, model.createData(), tool
        self.trocar = np.asarray(tool.trocar)

    def _rj(self, q: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        m, d, f = self.model, self.data, self.tool.axis_frame
        pin.computeJointJacobians(m, d, q)
        M = pin.updateFramePlacement(m, d, f)
        J = pin.getFrameJacobian(m, d, f, pin.LOCAL_WORLD_ALIGNED)
        R, ps, jv, jw = M.rotation, M.translation, J[:3], J[3:]
        a, dt = R[:, 2], self.trocar - ps
        jtip = jv - self.tool.tip_offset * _skew(a) @ jw
        rows = [(_skew(R[:, i]) @ dt) @ jw - R[:, i] @ jv for i in (0, 1)]
        r = np.concatenate([ps + self.tool.tip_offset * a - p, [R[:, 0] @ dt, R[:, 1] @ dt]])
        return r, np.vstack([jtip, *rows])

    def solve(self, p: np.ndarray, q: np.ndarray, **_: Any) -> Any:
        lo, hi = self.model.lowerPositionLimit, self.model.upperPositionLimit
        r, J = self._rj(q, p)
        for _ in range(50):
            if r @ r <= 1e-24:
                break
            q = np.clip(q - np.linalg.lstsq(J, r, rcond=None)[0], lo, hi)
            r, J = self._rj(q, p)
        rcm, tip = self.ik.errors(q, p)
        ok = float(np.linalg.norm(r)) <= 1e-9
        return SimpleNamespace(ik=SimpleNamespace(q=q, success=ok), rcm_error=rcm, tip_error=tip)


def one_round(ik: Any, q0: np.ndarray, targets: np.ndarray) -> dict[str, Any]:
    """The circle once, warm-started: µs per target, worst errors, failures."""
    q, out = q0, []
    start = time.perf_counter()
    for p in targets:
        r = ik.solve(p, q, raise_on_failure=False)
        q = r.ik.q
        out.append(r)
    us = (time.perf_counter() - start) / len(targets) * 1e6
    return {"us": us, "rcm": max(r.rcm_error for r in out), "tip": max(r.tip_error for r in out),
            "failures": sum(not r.ik.success for r in out)}  # fmt: skip


def drake_round(python: str) -> dict[str, Any] | None:
    """One round of the peer script in Drake's interpreter; None if it does not run."""
    if not Path(python).exists():
        return None
    run = subprocess.run([python, str(PEER), "--rounds", "1"], capture_output=True, text=True)
    return json.loads(run.stdout) if run.returncode == 0 else None


def summary(rows: list[dict[str, Any]]) -> dict[str, Any]:
    return {
        "us_per_target": float(np.median([r["us"] for r in rows])),
        "us_rounds": [round(r["us"], 1) for r in rows],
        "rcm_max": max(r["rcm"] for r in rows),
        "tip_max": max(r["tip"] for r in rows),
        "failures": max(r["failures"] for r in rows),
    }


def _ratio(values: list[float]) -> dict[str, float]:
    return {"median": float(np.median(values)), "min": min(values), "max": max(values)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--drake-python", default=DRAKE_PYTHON)
    args = ap.parse_args()
    model, tool, q0, targets = problem()
    routes: dict[str, Any] = {name: RcmIK(model, tool, solver=name) for name in ("lm", "ipopt")}
    routes["numpy"] = NumpyGaussNewton(model, tool)
    for ik in routes.values():  # build (and compile or load) outside the timing
        ik.solve(targets[0], q0)
    rows: dict[str, list[dict[str, Any]]] = {k: [] for k in (*routes, "drake_default",
                                                              "drake_tight")}  # fmt: skip
    peer: dict[str, Any] | None = None
    for _ in range(args.rounds):
        for name, ik in routes.items():
            rows[name].append(one_round(ik, q0, targets))
        peer = drake_round(args.drake_python)
        if peer is not None:
            for key in ("default", "tight"):
                p = peer[key]
                row = {"us": p["us_per_target"], "rcm": p["rcm_max"], "tip": p["tip_max"]}
                rows[f"drake_{key}"].append({**row, "failures": p["failures"]})
    out: dict[str, Any] = {"problem": _peer().problem_spec(), "rounds": args.rounds}
    out.update({k: summary(v) for k, v in rows.items() if v})
    if peer is not None:
        out["drake_solver"] = peer["solver"]
        out["same_trocar"] = bool(np.allclose(peer["trocar"], tool.trocar, rtol=0, atol=1e-12))
        out["ratios"] = {  # per round (the same minute of load), then the median and range
            f"{k}/{d}": _ratio([a["us"] / b["us"] for a, b in zip(rows[k], rows[d])])
            for k in routes
            for d in ("drake_default", "drake_tight")
        }
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
