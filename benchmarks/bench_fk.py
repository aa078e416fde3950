"""Forward kinematics: ``rcm_pin.tool_pose`` vs bare Pinocchio calls, in one run.

Prints a JSON document: per-call times [µs] (median over ``--repeat`` passes of the mean
time per call over ``--n`` random configurations) of

* ``pin.framesForwardKinematics`` + reading ``data.oMf[tool]`` (baseline 1),
* ``pin.forwardKinematics`` + ``pin.updateFramePlacement`` (baseline 2, the minimal call),
* ``rcm_pin.tool_pose(mech, q)`` (the wrapper: validation, coordinate mapping, the call),
* for the RCM family also the papers' closed form, one pose per call and vectorised,

and the wrapper's overhead ratios against both bare baselines. The bare calls get the
Pinocchio configuration (``mech.to_pin``) precomputed; the wrapper maps it itself.

    python benchmarks/bench_fk.py [--n 20000] [--name rcm_bevel] [--repeat 5]
    python benchmarks/bench_fk.py --n 2000 --repeat 3    # quick
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable

import numpy as np
import pinocchio as pin

import rcm_pin
from rcm_pin.mechanisms import rcm
from rcm_pin.mechanisms.rcm import closed_form

#: A timed case: (function, inputs, batched).
Case = tuple[Callable[[np.ndarray], object], np.ndarray, bool]


def per_call(cases: dict[str, Case], repeat: int) -> dict[str, float]:
    """Median over ``repeat`` passes of the time per call (per pose when batched) [µs].

    Each case is (function, inputs, batched): a pass calls the function once per input, or
    once on the whole array when batched. The passes of the cases are interleaved (one
    pass of each case per round), so a slow drift of the machine load hits every case
    alike and the ratios stay fair.
    """
    times: dict[str, list[float]] = {name: [] for name in cases}
    for fn, qs, batched in cases.values():  # warm-up
        fn(qs[:10] if batched else qs[0])
    for _ in range(repeat):
        for name, (fn, qs, batched) in cases.items():
            start = time.perf_counter()
            if batched:
                fn(qs)
            else:
                for q in qs:
                    fn(q)
            times[name].append((time.perf_counter() - start) / len(qs))
    return {name: 1e6 * float(np.median(t)) for name, t in times.items()}


def ratio(measured: str, baseline: str, times: dict[str, float]) -> dict[str, object]:
    """A ratio with both sides named (same run, same configurations)."""
    return {"measured": measured, "baseline": baseline,
            "ratio": times[measured] / times[baseline]}  # fmt: skip


def main(argv: list[str] | None = None) -> dict[str, object]:
    """Run the benchmark and print the JSON document."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=20_000, help="random configurations")
    parser.add_argument("--name", default="rcm_bevel", help="catalogue mechanism")
    parser.add_argument("--repeat", type=int, default=5, help="passes (median taken)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)

    mech = rcm_pin.load(args.name)
    model, data, fid = mech.model, mech.data, mech.tool_frame_id
    lo = np.where(np.isfinite(mech.lower), mech.lower, -np.pi)
    hi = np.where(np.isfinite(mech.upper), mech.upper, np.pi)
    qs = np.random.default_rng(args.seed).uniform(lo, hi, (args.n, mech.nq))
    qs_pin = mech.to_pin(qs)

    def bare_frames(q: np.ndarray) -> np.ndarray:
        pin.framesForwardKinematics(model, data, q)
        return data.oMf[fid].homogeneous

    def bare_minimal(q: np.ndarray) -> np.ndarray:
        pin.forwardKinematics(model, data, q)
        return pin.updateFramePlacement(model, data, fid).homogeneous

    frames = "pin.framesForwardKinematics + data.oMf[tool]"
    minimal = "pin.forwardKinematics + pin.updateFramePlacement"
    wrapper = "rcm_pin.tool_pose"
    cases: dict[str, Case] = {
        frames: (bare_frames, qs_pin, False),
        minimal: (bare_minimal, qs_pin, False),
        wrapper: (lambda q: rcm_pin.tool_pose(mech, q), qs, False),
    }
    ratios = [(wrapper, frames), (wrapper, minimal)]
    errors = {}
    if mech.family is rcm.FAMILY and mech.nq == 6:
        wrist = closed_form.wrist_type(mech)
        single, batched = "closed form, one pose per call", "closed form, vectorised (per pose)"
        cases[single] = (lambda q: closed_form.tool_pose(q, wrist), qs[:2000], False)
        cases[batched] = (lambda q: closed_form.tool_pose(q, wrist), qs, True)
        ratios += [(wrapper, single), (single, batched)]
        errors["max |tool_pose - closed form|"] = float(max(
            np.abs(rcm_pin.tool_pose(mech, q) - closed_form.tool_pose(q, wrist)).max()
            for q in qs[:200]
        ))  # fmt: skip
    times = per_call(cases, args.repeat)
    doc: dict[str, object] = {
        "benchmark": "forward kinematics",
        "mechanism": args.name,
        "configurations": args.n,
        "repeat": args.repeat,
        "statistic": "median over interleaved passes of the mean time per call",
        "per_call_us": times,
        "ratios": [ratio(m, b, times) for m, b in ratios],
        "checks": errors,
    }
    print(json.dumps(doc, indent=2))
    return doc


if __name__ == "__main__":
    main()
