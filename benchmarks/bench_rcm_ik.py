"""RCM inverse kinematics of panda: rcm-pin's own routes, rounds interleaved.

The case is the harness's row ``rcm_ik`` (``benchmarks/peers/rows.py``,
:func:`rcm_ik_case`: ``rcm_pin.studies.rcm_comparison.make_setup("panda")`` at its chosen
trocar, 100 tip targets along the ``surgical_paths`` circle after its start, the start
configuration on the path's first point), each solve warm-started from the previous one.
Per round:

* ``lm``: :class:`ocp.rcm.RcmIK` with ``solver="lm"`` (compiled projected LM, the default);
* ``ipopt``: the same with ``solver="ipopt"`` (the NLP, tol 1e-12; the route before);
* ``numpy``: a plain Pinocchio + numpy Gauss–Newton on the same residual (frame Jacobian,
  ``lstsq``, clipped to the limits; :class:`NumpyGaussNewton`), the pure-Python alternative.

Drake (InverseKinematics + SNOPT, in its own venv) on the same case is the harness's row:
``PYTHONPATH=. python benchmarks/peers/run.py --venvs DIR --rows rcm_ik``.

Prints one JSON document: µs per target (median over the rounds), the worst RCM distance
and tip error over the circle (Pinocchio forward kinematics), failures, and the ratios of
the routes to ``lm``, round by round (each pair measured within the same seconds of load):
their median and range.

    python benchmarks/bench_rcm_ik.py [--rounds 5]
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pinocchio as pin

from ocp.rcm import RcmIK
from rcm_pin.control.rcm_task import RcmTool
from rcm_pin.studies.rcm_comparison import make_setup

PEERS = Path(__file__).resolve().parent / "peers"
ARM, N_TARGETS = "panda", 100


def problem() -> tuple[pin.Model, RcmTool, np.ndarray, np.ndarray, dict[str, Any]]:
    """(model, tool, start q, targets, case summary) of the harness's row ``rcm_ik``."""
    sys.path.insert(0, str(PEERS))
    from rows import rcm_ik_case

    with tempfile.TemporaryDirectory(prefix="rcm-pin-rcm-ik-") as scratch:
        case = rcm_ik_case(ARM, N_TARGETS)(Path(scratch))
    s = make_setup(case["arm"])
    assert s.chain is not None
    spec = {k: case[k] for k in ("arm", "axis_frame", "axis", "tip_offset", "trocar")}
    spec["n_targets"] = len(case["targets"])
    return s.chain.model, s.chain.tool, np.asarray(case["q0"]), np.asarray(case["targets"]), spec


def _skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


class NumpyGaussNewton:
    """Gauss–Newton on [tip − target; (R e_i, R e_j)ᵀ (p_T − p_s)] (e_i, e_j the axes
    orthogonal to the shaft) with Pinocchio's LOCAL_WORLD_ALIGNED Jacobian of the axis
    frame (d(R e)/dq = −[R e]× J_ω); ``solve`` mimics :meth:`ocp.rcm.RcmIK.solve`
    (errors by the same FK)."""

    def __init__(self, model: pin.Model, tool: RcmTool) -> None:
        self.ik = RcmIK(model, tool)  # its errors() only
        self.model, self.data, self.tool = model, model.createData(), tool
        self.trocar = np.asarray(tool.trocar)
        self.across = [i for i in range(3) if i != tool.axis]

    def _rj(self, q: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        m, d, f = self.model, self.data, self.tool.axis_frame
        pin.computeJointJacobians(m, d, q)
        M = pin.updateFramePlacement(m, d, f)
        J = pin.getFrameJacobian(m, d, f, pin.LOCAL_WORLD_ALIGNED)
        R, ps, jv, jw = M.rotation, M.translation, J[:3], J[3:]
        a, dt = R[:, self.tool.axis], self.trocar - ps
        jtip = jv - self.tool.tip_offset * _skew(a) @ jw
        rows = [(_skew(R[:, i]) @ dt) @ jw - R[:, i] @ jv for i in self.across]
        r = np.concatenate([ps + self.tool.tip_offset * a - p, [R[:, i] @ dt for i in self.across]])
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
    args = ap.parse_args()
    model, tool, q0, targets, spec = problem()
    routes: dict[str, Any] = {name: RcmIK(model, tool, solver=name) for name in ("lm", "ipopt")}
    routes["numpy"] = NumpyGaussNewton(model, tool)
    for ik in routes.values():  # build (and compile or load) outside the timing
        ik.solve(targets[0], q0, raise_on_failure=False)
    rows: dict[str, list[dict[str, Any]]] = {k: [] for k in routes}
    for _ in range(args.rounds):
        for name, ik in routes.items():
            rows[name].append(one_round(ik, q0, targets))
    out: dict[str, Any] = {"problem": spec, "rounds": args.rounds}
    out.update({k: summary(v) for k, v in rows.items()})
    out["ratios"] = {  # per round (the same seconds of load), then the median and range
        f"{k}/lm": _ratio([a["us"] / b["us"] for a, b in zip(rows[k], rows["lm"])])
        for k in routes
        if k != "lm"
    }
    out["drake"] = "PYTHONPATH=. python benchmarks/peers/run.py --venvs DIR --rows rcm_ik"
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
