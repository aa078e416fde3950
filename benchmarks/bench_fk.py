"""Forward kinematics: the Mechanism wrapper vs bare Pinocchio calls, in one run.

Prints per-call times [µs] and the wrapper's overhead ratio against
``pin.framesForwardKinematics`` (+ reading ``data.oMf[tool]``) and against the
minimal ``pin.forwardKinematics`` + ``pin.updateFramePlacement``.

    python benchmarks/bench_fk.py [--n 20000] [--name rcm_bevel]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import pinocchio as pin

import rcm_pin
from rcm_pin import closed_form


def per_call(fn, qs) -> float:
    """Median over 5 repeats of the mean time per call [s]."""
    times = []
    for _ in range(5):
        start = time.perf_counter()
        for q in qs:
            fn(q)
        times.append((time.perf_counter() - start) / len(qs))
    return float(np.median(times))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--n", type=int, default=20_000)
    parser.add_argument("--name", default="rcm_bevel")
    args = parser.parse_args()
    mech = rcm_pin.load(args.name)
    model, data, fid = mech.model, mech.data, mech.tool_frame_id
    qs = np.random.default_rng(0).uniform(mech.lower, mech.upper, (args.n, mech.nq))

    def bare_frames(q):
        pin.framesForwardKinematics(model, data, q)
        return data.oMf[fid].homogeneous

    def bare_minimal(q):
        pin.forwardKinematics(model, data, q)
        return pin.updateFramePlacement(model, data, fid).homogeneous

    t_frames = per_call(bare_frames, qs)
    t_minimal = per_call(bare_minimal, qs)
    t_wrapper = per_call(lambda q: rcm_pin.tool_pose(mech, q), qs)
    t_closed = per_call(lambda q: closed_form.tool_pose(q, mech.wrist_type), qs[:2000])
    start = time.perf_counter()
    closed_form.tool_pose(qs, mech.wrist_type)
    t_closed_vec = (time.perf_counter() - start) / len(qs)
    print(f"{args.name}: {args.n} configurations")
    print(f"  pin.framesForwardKinematics + oMf[tool] : {t_frames * 1e6:8.2f} µs/call")
    print(f"  pin.forwardKinematics + updateFramePlacement: {t_minimal * 1e6:8.2f} µs/call")
    print(f"  rcm_pin.tool_pose (wrapper)               : {t_wrapper * 1e6:8.2f} µs/call")
    print(f"  closed form, one pose per call            : {t_closed * 1e6:8.2f} µs/call")
    print(f"  closed form, vectorised                   : {t_closed_vec * 1e6:8.3f} µs/pose")
    print(f"  ratio wrapper / framesForwardKinematics   : {t_wrapper / t_frames:6.2f}")
    print(f"  ratio wrapper / minimal bare call         : {t_wrapper / t_minimal:6.2f}")


if __name__ == "__main__":
    main()
