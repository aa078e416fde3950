"""Programmable RCM at 1 kHz: time per QP step beside a bare Pinocchio Jacobian call.

For each arm (panda, ur5) at its chosen trocar
(:func:`rcm_pin.studies.rcm_comparison.choose_trocar`) it runs the full circle, spiral and
arc paths (4000, 6000, 3000 steps at 1 kHz) with the RCM QP (distance formulation), and
times along the circle:

* ``jacobian``: ``pin.computeFrameJacobian`` of the tool frame (the bare baseline);
* ``qp_distance``, ``qp_lambda``: one :meth:`RcmQP.step` (kinematics, both Jacobians, the
  QP through qpsolvers/daqp), point-to-line and λ formulations;
* ``pink``: one :meth:`RcmQP.step_pink` (the same QP built by pin-pink);
* ``mechanical``: one analytic inverse of rcm_bevel (``rcm_pin.inverse`` on the tip).

Prints one JSON document: per path the RCM error max / RMS, tip error max, the goal
verdicts (RCM ≤ 1e-6 m, tip ≤ 1e-4 m), and the median step times [µs] with their ratio to
the Jacobian call measured in the same run (goal: QP step ≤ 200 µs median).

    python benchmarks/bench_rcm_qp.py [--repeat 2000]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np
import pinocchio as pin

from rcm_pin.analysis.position import inverse
from rcm_pin.control.rcm_loop import track
from rcm_pin.studies.rcm_comparison import RcmTrack, controller, make_setup, start_configuration
from rcm_pin.studies.rcm_metrics import errors
from rcm_pin.studies.surgical_paths import PATHS, surgical_path


def median_us(fn, inputs) -> float:
    """Median wall time of ``fn(x)`` over ``inputs`` [µs]."""
    times = np.empty(len(inputs))
    for k, x in enumerate(inputs):
        start = time.perf_counter()
        fn(x)
        times[k] = time.perf_counter() - start
    return float(1e6 * np.median(times))


def arm_figures(name: str, repeat: int) -> dict[str, object]:
    s = make_setup(name)
    out: dict[str, object] = {"trocar": list(s.tool.trocar)}
    for path in PATHS:
        sp = surgical_path(path, s.cone, rate=1000.0)
        ctrl = controller(s, 1e-3)
        run = track(ctrl, start_configuration(s, sp.p[0]), sp.p)
        rcm, tip = errors(RcmTrack(s, path, sp.t, s.chain.to_mechanism(run.q), sp.p,
                                   run.step_time))  # fmt: skip
        out[path] = {
            "steps": len(sp.t) - 1,
            "rcm_error_max": float(rcm.max()),
            "rcm_error_rms": float(np.sqrt(np.mean(rcm**2))),
            "tip_error_max": float(tip.max()),
            "rcm_goal_1e-6": bool(rcm.max() <= 1e-6),
            "tip_goal_1e-4": bool(tip.max() <= 1e-4),
            "step_median_us": float(1e6 * np.median(run.step_time)),
        }
        if path == "circle":
            qs, refs = run.q[:repeat], sp.p[1 : repeat + 1]
    model, data = s.chain.model, s.chain.model.createData()
    fid = s.chain.tool.axis_frame
    pairs = list(zip(qs, refs))
    times = {
        "jacobian": median_us(lambda x: pin.computeFrameJacobian(model, data, x[0], fid), pairs),
    }
    for form in ("distance", "lambda"):
        c = controller(s, 1e-3, formulation=form)
        times[f"qp_{form}"] = median_us(lambda x, c=c: c.step(x[0], x[1]), pairs)
    c = controller(s, 1e-3)
    times["pink"] = median_us(lambda x: c.step_pink(x[0], x[1]), pairs)
    out["step_us"] = times
    out["ratio_to_jacobian"] = {k: v / times["jacobian"] for k, v in times.items()}
    out["qp_goal_200us"] = bool(times["qp_distance"] <= 200.0)
    return out


def mechanical_figures(repeat: int) -> dict[str, object]:
    s = make_setup("rcm_bevel")
    sp = surgical_path("circle", s.cone, rate=1000.0)
    pts = sp.p[:repeat]
    t = median_us(lambda p: inverse(s.mech, p, ("x", "y", "z"), limits=True), pts)
    mech, data = s.mech, s.mech.model.createData()
    q = mech.to_pin(s.home)
    jac = median_us(
        lambda _: pin.computeFrameJacobian(mech.model, data, q, mech.tool_frame_id), pts
    )
    return {"analytic_ik_us": t, "jacobian_us": jac, "ratio": t / jac}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=2000, help="timed steps per case")
    args = parser.parse_args()
    doc = {name: arm_figures(name, args.repeat) for name in ("panda", "ur5")}
    doc["rcm_bevel"] = mechanical_figures(args.repeat)
    print(json.dumps(doc, indent=2))


if __name__ == "__main__":
    main()
