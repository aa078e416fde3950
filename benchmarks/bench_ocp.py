"""Speed of the CasADi layer (run on demand, never in the test suite).

    python benchmarks/bench_ocp.py            # twin, IK, tracking (about 2 min)
    python benchmarks/bench_ocp.py --jit      # also JIT-compiled tracking (compiles ~1 min)
    python benchmarks/bench_ocp.py --only ik  # one part: twin | ik | closed | tracking
    python benchmarks/bench_ocp.py --only tracking --sizes 100 --json  # ratios as JSON
    python benchmarks/bench_ocp.py --only tracking --sizes 100 --json --mechanism rcm_two_mass \
        --configs vm_exact_screen default default_compiled --repeats 3

Prints markdown tables: per-call times of the symbolic twin (CasADi VM vs JIT vs numeric
Pinocchio), IK solve times (cold and warm, per solver) against the analytic IK, the IK of
the closed mechanisms' outputs (closures as constraints) against ``rcm_pin.inverse``, and
the tracking OCP's solve time and iterations for N = 50, 100, 200 with IPOPT and fatrop.
Models come from the catalogue (``rcm_pin.load``; panda from example-robot-data).

``--json`` (tracking part): the drive-limited OCP against its floor, the unlimited OCP,
side by side in one run, for each configuration (CasADi VM, compiled stage functions
with the exact or the cost-only Hessian, compiled + screening) and case (URDF limits,
inactive; 0.8 x the exact solution's peak efforts on q1..q3 with the wrist locked,
binding): build and cached rebuild times, median solve times of ``--repeats`` solves,
iterations, the ratios to the unlimited solve of the same configuration and of the VM,
and the solution's largest differences from the VM exact-Hessian solution (the first
configuration's). ``--mechanism`` (default rcm_bevel, the paper's; rcm_two_mass is the
peers harness's, whose ``tracking_*`` rows time rcm-pin against Crocoddyl:
``benchmarks/peers``), ``--configs`` a subset of the configurations.
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable
from functools import partial
from typing import Any

import numpy as np
import pinocchio as pin

import rcm_pin
from ocp import IKProblem, SymbolicModel
from ocp import paper000 as paper
from rcm_pin.mechanisms.rcm import analytic_ik, closed_form

#: Closed mechanisms and an output target of each (x, y, rz / x, y / rz).
CLOSED_TARGETS = {"planar_3rrr": [0.01, 0.02, 0.1], "five_bar": [0.02, 0.25], "four_bar": [1.0]}


def _per_call(fun: Callable[[], object], n: int = 2000) -> float:
    fun()
    start = time.perf_counter()
    for _ in range(n):
        fun()
    return 1e6 * (time.perf_counter() - start) / n  # [us]


def bench_twin() -> None:
    print("\n## Symbolic twin: time per evaluation [us] (mapped over 2000 states)\n")
    print("| model | backend | compile [s] | placement | jacobian | rnea | M | FD |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for name in ("rcm_bevel", "panda"):
        mech = rcm_pin.load(name)
        model, fid = mech.model, mech.tool_frame_id
        q, v = pin.neutral(model), np.ones(model.nv)
        for jit in (False, True):
            start = time.perf_counter()
            sm = SymbolicModel(model, jit=jit)
            funs = [
                (sm.frame_placement(fid), (q,)),
                (sm.frame_jacobian(fid), (q,)),
                (sm.rnea(), (q, v, v)),
                (sm.mass_matrix(), (q,)),
                (sm.forward_dynamics(), (q, v, v)),
            ]
            for f, args in funs:
                f(*args)
            compile_s = time.perf_counter() - start
            cells = [f"{_mapped_time(f, args):.2f}" for f, args in funs]
            print(f"| {name} | {'JIT' if jit else 'VM'} | {compile_s:.1f} | {' | '.join(cells)} |")
        numeric = " | ".join(f"{c:.2f}" for c in _pinocchio_times(model, fid))
        print(f"| {name} | Pinocchio (Python call) | - | {numeric} |")


def _mapped_time(f: Any, args: tuple[np.ndarray, ...], n: int = 2000) -> float:
    """Time per evaluation [us] of ``f`` mapped over ``n`` copies of ``args``."""
    mapped = f.map(n)
    tiled = [np.tile(np.asarray(a).reshape(-1, 1), (1, n)) for a in args]
    return _per_call(lambda: mapped(*tiled), 5) / n


def _pinocchio_times(model: pin.Model, fid: int) -> list[float]:
    """Per-call times [us] of the numeric counterparts (FD: not applicable, mimic)."""
    data = model.createData()
    q, v = pin.neutral(model), np.ones(model.nv)
    return [
        _per_call(lambda: pin.updateFramePlacement(model, data, fid)),
        _per_call(lambda: pin.computeFrameJacobian(model, data, q, fid)),
        _per_call(lambda: pin.rnea(model, data, q, v, v)),
        _per_call(lambda: pin.crba(model, data, q, pin.Convention.WORLD)),
        float("nan"),
    ]


def _ik_cases(n: int, seed: int = 0) -> tuple[rcm_pin.Mechanism, np.ndarray, np.ndarray]:
    mech = rcm_pin.load("rcm_bevel")
    q = np.random.default_rng(seed).uniform(mech.lower, mech.upper, size=(n, 6))
    return mech, q, closed_form.tool_pose(q)


def bench_ik(n: int = 1000) -> None:
    print(f"\n## IK of rcm_bevel's tool pose, {n} random reachable poses\n")
    print("| solver | start | success | median iterations | median [ms] | p90 [ms] |")
    print("| --- | --- | --- | --- | --- | --- |")
    mech, q_true, poses = _ik_cases(n)
    rng = np.random.default_rng(1)
    scale = np.array([0.3, 0.3, 0.03, 0.3, 0.3, 0.3])
    warm = np.clip(q_true + rng.uniform(-scale, scale, q_true.shape), mech.lower, mech.upper)
    for solver, jit, count in (
        ("lm", False, n),
        ("lm", True, n),
        ("sqpmethod", False, n // 10),
        ("ipopt", False, n // 10),
    ):
        prob = IKProblem(mech.model, "tool", jit=jit, restarts=10)
        for label, starts in (("warm (<= 0.3 rad)", warm), ("cold (mid-range)", None)):
            times, iters, ok = [], [], 0
            for k in range(count):
                q0 = None if starts is None else mech.to_pin(starts[k])
                start = time.perf_counter()
                res = prob.solve(poses[k], q0, solver=solver, raise_on_failure=False)  # type: ignore[arg-type]
                times.append(time.perf_counter() - start)
                iters.append(res.iterations)
                ok += res.success
            name = f"{solver}{' (JIT)' if jit else ''}"
            print(
                f"| {name} | {label} | {ok / count:.1%} | {np.median(iters):.0f} | "
                f"{1e3 * np.median(times):.3f} | {1e3 * np.percentile(times, 90):.3f} |"
            )
    one = [_per_call(partial(analytic_ik.ik_pose, poses[k]), 1) for k in range(200)]
    start = time.perf_counter()
    analytic_ik.ik_pose(poses)
    batch = 1e6 * (time.perf_counter() - start) / n
    print(
        f"\nAnalytic IK (all 8 branches): {np.median(one):.1f} us per single-pose call, "
        f"{batch:.2f} us per pose vectorised over {n} poses."
    )


def bench_closed(n: int = 100) -> None:
    print(f"\n## IK of closed mechanisms' outputs, IPOPT, {n} random starts\n")
    print("| mechanism | working modes | found | success | median iterations | median [ms] |")
    print("| --- | --- | --- | --- | --- | --- |")
    for name, target in CLOSED_TARGETS.items():
        mech = rcm_pin.load(name)
        modes = rcm_pin.inverse(mech, target).solutions
        prob = IKProblem(mech, seed=0)
        found, times, iters, ok = set(), [], [], 0
        for _ in range(n):
            q0 = prob.random_configuration()
            start = time.perf_counter()
            res = prob.solve(target, q0, raise_on_failure=False)
            times.append(time.perf_counter() - start)
            iters.append(res.iterations)
            if res.success:
                ok += 1
                d = [np.abs(np.angle(np.exp(1j * (mech.from_pin(res.q) - s.q)))).max()
                     for s in modes]  # fmt: skip
                found.add(modes[int(np.argmin(d))].mode)
        print(
            f"| {name} | {len(modes)} | {len(found)} | {ok / n:.0%} | {np.median(iters):.0f} | "
            f"{1e3 * np.median(times):.2f} |"
        )


def bench_tracking(jit: bool, sizes: list[int]) -> None:
    print("\n## Tracking OCP, paper 000 reference, rcm_bevel (six DOF), Radau d = 3\n")
    print(
        "| N | solver | drive-limit constraints | build [s] | iterations | solve [ms] | "
        "function evals [ms] | tracking error [m] |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    configs = [("ipopt", False, False), ("fatrop", False, False), ("ipopt", True, False)]
    if jit:
        configs.append(("ipopt", True, True))
    for n in sizes:
        for solver, limits, use_jit in configs:
            start = time.perf_counter()
            ocp, mech = paper.build(n_intervals=n, solver=solver, drive_limits=limits, jit=use_jit)
            build = time.perf_counter() - start
            lim = mech.model.effortLimit.copy() if limits else None
            res = min(
                (paper.solve(ocp, mech, effort_limits=lim) for _ in range(3)),
                key=lambda r: r.solve_time,
            )
            fun = sum(v for k, v in ocp.solver.stats().items() if k.startswith("t_wall_nlp"))
            tag = f"{solver}{' JIT' if use_jit else ''}"
            print(
                f"| {n} | {tag} | {'yes' if limits else 'no'} | {build:.1f} | "
                f"{res.iterations} | {1e3 * res.solve_time:.1f} | {1e3 * fun:.1f} | "
                f"{res.tracking_error:.1e} |"
            )


#: Configurations of the JSON tracking benchmark: build and solve keyword arguments.
#: ``vm_exact`` (the full NLP, exact Hessian, no screening) is the solve before issue 17 and
#: the reference solution; ``vm_exact_screen`` the default of issue 17; ``default`` the
#: default since issue 27 (the reduced problem: Newton's method, IPOPT with the cost Hessian
#: when limits bind; ``ocp.tracking_reduced``), ``default_compiled`` with ``compile=True``.
FULL: dict[str, Any] = {"reduced": False, "hessian": "exact"}
TRACKING_CONFIGS: dict[str, tuple[dict[str, Any], dict[str, Any]]] = {
    "vm_exact": (FULL, {"screen": False}),
    "vm_exact_screen": (FULL, {"screen": True}),
    "compiled_exact": ({**FULL, "compile": "-O1"}, {"screen": False}),
    "compiled_exact_O0": ({**FULL, "compile": "-O0"}, {"screen": False}),
    "compiled_cost": ({**FULL, "compile": "-O1", "hessian": "cost"}, {"screen": False}),
    "compiled_exact_screen": ({**FULL, "compile": "-O1"}, {"screen": True}),
    "default": ({}, {}),
    "default_compiled": ({"compile": "-O1"}, {}),
}
#: Cases: (drive-limit constraints, wrist locked, limits) and the floor each is compared to.
TRACKING_CASES = {
    "unlimited": (False, False, "none"),
    "unlimited_locked_wrist": (False, True, "none"),
    "urdf_limits": (True, False, "urdf"),
    "binding_limits": (True, True, "binding"),
}
FLOORS = {"urdf_limits": "unlimited", "binding_limits": "unlimited_locked_wrist"}


def _limits(mech: rcm_pin.Mechanism, kind: str) -> np.ndarray | None:
    if kind == "urdf":
        return mech.model.effortLimit.copy()
    if kind == "binding":
        lim = np.full(mech.nq, np.inf)
        lim[:3] = 0.8 * paper.peak_efforts(mech)[:3]
        return lim
    return None


def tracking_json(
    n: int, repeats: int, mechanism: str = paper.MECHANISM, configs: list[str] | None = None
) -> dict[str, Any]:
    """The ratios of the drive-limited to the unlimited tracking OCP at ``n`` intervals
    (``configs``: keys of :data:`TRACKING_CONFIGS`, default all; the first is the reference
    of ``vs_<first>`` and of ``ratio_vs_<first>_floor``)."""
    names = list(TRACKING_CONFIGS) if configs is None else configs
    out: dict[str, Any] = {"mechanism": mechanism, "n_intervals": n, "repeats": repeats}
    out["configs"] = {}
    ref: dict[str, Any] = {}
    for cname in names:
        build_kw, solve_kw = TRACKING_CONFIGS[cname]
        built: dict[str, Any] = {}
        for case, (limited, lock, kind) in TRACKING_CASES.items():
            timed = []
            for _ in range(2):  # first build (may compile), then the cached rebuild
                start = time.perf_counter()
                ocp, mech = paper.build(
                    mechanism, n, drive_limits=limited, lock_wrist=lock, **build_kw
                )
                timed.append(time.perf_counter() - start)
            built[case] = (ocp, mech, _limits(mech, kind), timed)
        runs: dict[str, list[Any]] = {case: [] for case in built}
        for _ in range(repeats):  # round robin: the cases share the machine's load
            for case, (ocp, mech, lim, _) in built.items():
                x0 = paper.initial_state(mech)
                runs[case].append(
                    ocp.solve(paper.reference_position, x0, effort_limits=lim,
                              raise_on_failure=False, **solve_kw)
                )  # fmt: skip
        rows: dict[str, Any] = {}
        for case, (_, _, _, timed) in built.items():
            res = runs[case][0]
            row = {
                "build_s": timed[0],
                "rebuild_s": timed[1],
                "solve_ms": 1e3 * float(np.median([r.solve_time for r in runs[case]])),
                "iterations": res.iterations,
                "status": res.status,
                "objective": res.objective,
            }
            base = ref.setdefault(case, res)
            row[f"vs_{names[0]}"] = {
                "q_max_diff": float(np.abs(res.q_colloc - base.q_colloc).max()),
                "tau_max_diff": float(np.abs(res.tau - base.tau).max()),
                "objective_diff": abs(res.objective - base.objective),
            }
            rows[case] = row
        for case, floor in FLOORS.items():
            rows[case]["floor"] = f"{floor} ({cname})"
            rows[case]["ratio"] = rows[case]["solve_ms"] / rows[floor]["solve_ms"]
        out["configs"][cname] = rows
    first = out["configs"][names[0]]
    for rows in out["configs"].values():
        for case, floor in FLOORS.items():
            ratio = rows[case]["solve_ms"] / first[floor]["solve_ms"]
            rows[case][f"ratio_vs_{names[0]}_floor"] = ratio
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--jit", action="store_true", help="also time JIT-compiled tracking")
    parser.add_argument("--only", choices=("twin", "ik", "closed", "tracking"))
    parser.add_argument("--poses", type=int, default=1000)
    parser.add_argument("--sizes", type=int, nargs="+", default=[50, 100, 200])
    parser.add_argument("--json", action="store_true", help="tracking ratios as JSON")
    parser.add_argument("--repeats", type=int, default=5, help="solves per case (--json)")
    parser.add_argument("--mechanism", default=paper.MECHANISM, help="tracking (--json)")
    parser.add_argument("--configs", nargs="+", choices=list(TRACKING_CONFIGS),
                        help="tracking configurations (--json; default all)")  # fmt: skip
    args = parser.parse_args()
    if args.json:
        if args.only not in (None, "tracking"):
            parser.error("--json applies to the tracking part (--only tracking)")
        runs = [tracking_json(n, args.repeats, args.mechanism, args.configs) for n in args.sizes]
        print(json.dumps(runs[0] if len(runs) == 1 else runs, indent=2))
        return
    if args.only in (None, "twin"):
        bench_twin()
    if args.only in (None, "ik"):
        bench_ik(args.poses)
    if args.only in (None, "closed"):
        bench_closed()
    if args.only in (None, "tracking"):
        bench_tracking(args.jit, args.sizes)


if __name__ == "__main__":
    main()
