"""Closed-loop direct position solvers (run on demand, never in the test suite).

Prints a JSON document (per-call times [µs] are medians over every timed call of
``--repeat`` interleaved passes):

1. ``sweep``: per-pose direct solves, each pose warm-started from the previous pose's
   solution: planar_3rrr (drives of working mode +++ along a closed Lissajous sweep of
   the platform, |φ| ≤ 0.3), five_bar and four_bar (a closed curve of the drives around
   home, ±0.15 rad), and on a quarter of the poses (±0.05 rad) the other closed
   mechanisms (spherical_3rrr, translational_3ppapa, eye_4dof and
   translational_3ppapa_loops, whose kernel stays in the VM: too large to compile in a
   user's loop). Side by side in one run:

   * ``solve_drives`` with the compiled closure kernel (:mod:`rcm_pin.model.kernels`,
     provider :mod:`ocp.kernels`, the default route; compiled up front here, as it is
     after ``ocp.kernels.closure_kernel.COMPILE_AFTER`` calls of a structure),
   * the same kernel function run in CasADi's VM (no C compiler),
   * ``solve_drives`` on the numpy route (kernels disabled: Newton on Pinocchio's
     closure residual; the floor the issue names is a compiled Newton step),
   * ``rcm_pin.forward(mech, drives, q_guess=...)`` (validation, output value, limits
     flag) on both routes,

   with the agreement of the two routes (max |Δq|, iteration counts) and the floor: one
   evaluation of the kernel function on bound buffers (``CHUNK`` = 4 iterations);
2. ``call_overhead``: one evaluation of the planar_3rrr kernel function by
   ``Function.__call__`` on numpy arrays, by ``Function.call`` on a list of numpy
   arrays and on bound buffers (``ocp.buffered.BufferedFunction.evaluate``);
3. ``batched``: the vectorised planar Newton (``rcm_pin.analysis.batch_planar``) on
   ``--n-batch`` poses at once, each warm-started from its neighbour on the sweep (time
   per pose, median of batched runs), against the per-pose ``solve_drives`` (kernel);
4. ``all_modes``: ``rcm_pin.forward(mech, drives, all_modes=True)`` (the family's
   closed-form seeds, a Newton polish of each, deduplication) for planar_3rrr, five_bar and
   four_bar at drive values near the home configuration, against one warm ``solve_drives``
   from home and against the family's closed-form seeds alone.

    python benchmarks/bench_closed_loop.py                # about 40 s
    python benchmarks/bench_closed_loop.py --n-sweep 200 --n-batch 2000 --n-drives 10 \\
        --repeat 2                                        # quick
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

import rcm_pin
from ocp.buffered import BufferedFunction
from ocp.kernels import CHUNK, provider
from ocp.kernels.closure_kernel import ClosureNewtonKernel, SharedFunction
from rcm_pin.analysis.batch_planar import PlanarTree, batch_solve_passive
from rcm_pin.analysis.capabilities import position_solver
from rcm_pin.analysis.closed_position import solve_drives
from rcm_pin.mechanisms.planar_3rrr import closed_form as p3
from rcm_pin.mechanisms.planar_3rrr import geometry
from rcm_pin.model import kernels

#: Mechanisms of the ``sweep`` and ``all_modes`` parts.
ALL_MODES = ("planar_3rrr", "five_bar", "four_bar")
#: The other closed mechanisms of the ``sweep`` part (``--n-sweep`` / 4 poses, drives
#: within ±0.05 rad of home).
OTHERS = ("spherical_3rrr", "translational_3ppapa", "eye_4dof", "translational_3ppapa_loops")


def sweep(g: p3.Geometry3RRR, n: int) -> tuple[np.ndarray, np.ndarray]:
    """A closed curve of poses (Lissajous, |φ| ≤ 0.3) and its drives in working mode +++."""
    s = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    poses = np.column_stack([0.06 * np.sin(s), 0.05 * np.sin(2 * s), 0.3 * np.sin(3 * s)])
    qs, ok = p3.inverse_position(g, poses)
    assert ok.all()
    return poses, qs[:, 0]


def timed(cases: dict[str, Callable[[Any], Any]], args: Sequence[Any],
          repeat: int) -> tuple[dict[str, float], dict[str, list]]:  # fmt: skip
    """Median time per call [µs] of each case over ``repeat`` passes over ``args``, and
    each case's results of the last pass.

    The passes are interleaved (one pass of each case per round), so a slow drift of the
    machine load hits every case alike and the ratios stay fair.
    """
    for fn in cases.values():  # warm-up
        fn(args[0])
    times: dict[str, list[float]] = {name: [] for name in cases}
    out: dict[str, list] = {}
    for _ in range(repeat):
        for name, fn in cases.items():
            out[name] = []
            for a in args:
                start = time.perf_counter()
                out[name].append(fn(a))
                times[name].append(time.perf_counter() - start)
    return {name: 1e6 * float(np.median(t)) for name, t in times.items()}, out


def ratio(measured: str, baseline: str, times: dict[str, float]) -> dict[str, object]:
    """A ratio with both sides named (same run)."""
    return {"measured": measured, "baseline": baseline,
            "ratio": times[measured] / times[baseline]}  # fmt: skip


def compiled_kernel(mech: rcm_pin.Mechanism) -> ClosureNewtonKernel:
    """The closure kernel of ``mech`` on its default route, compiled now where it would
    be after ``COMPILE_AFTER`` calls (functions above ``COMPILE_MAX_INSTRUCTIONS`` stay
    in the VM)."""
    kernel = kernels.warm(mech)
    assert isinstance(kernel, ClosureNewtonKernel)
    if kernel.shared.compile_after is not None:
        kernel.shared.compile()
    return kernel


def numpy_route(fn: Callable[[Any], Any]) -> Callable[[Any], Any]:
    """``fn`` with the kernels disabled (the numpy Newton of ``rcm_pin.model.newton``)."""

    def run(c: Any) -> Any:
        with kernels.disabled():
            return fn(c)

    return run


def sweep_cases(
    mech: rcm_pin.Mechanism, n: int, amplitude: float = 0.15
) -> tuple[list, np.ndarray | None]:
    """(drives of pose k, solution of pose k − 1) along a closed sweep, and the platform
    poses (planar_3rrr) or None. The others: drives on a closed curve around home
    (± ``amplitude`` [rad, m]), solutions by a numpy-route continuation."""
    if mech.name == "planar_3rrr":
        g = geometry(mech)
        poses, qd = sweep(g, n)
        q_true = p3.full_q(g, poses, qd)
        return [(qd[k], q_true[k - 1]) for k in range(1, n)], poses[1:]
    loops = mech.loops
    assert loops is not None
    home = mech.home
    s = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)[:, None]
    phase = np.arange(loops.dof)[None, :]
    drives = home[loops.drive_q] + amplitude * np.sin(s * (1 + phase) + phase)
    qs = [home]
    with kernels.disabled():
        for d in drives:
            qs.append(solve_drives(mech, d, qs[-1])[0])
    return [(drives[k], qs[k]) for k in range(1, n)], None


def bench_sweep(
    mech: rcm_pin.Mechanism, n: int, repeat: int, amplitude: float = 0.15
) -> dict[str, object]:
    """Per-pose warm-started direct solves along the sweep (part 1)."""
    cases, poses = sweep_cases(mech, n, amplitude)
    kernel = compiled_kernel(mech)
    vm = ClosureNewtonKernel(
        SharedFunction(provider.newton_function(mech, vm=True), "", None), CHUNK
    )
    kern, kern_vm = "solve_drives (kernel)", "closure kernel in the CasADi VM"
    base, direct = "solve_drives (numpy route)", "rcm_pin.forward(q_guess=...) (kernel)"
    direct_np = "rcm_pin.forward(q_guess=...) (numpy route)"

    def fwd(c: Any) -> Any:
        return rcm_pin.forward(mech, c[0], q_guess=c[1])

    times, out = timed({kern: lambda c: solve_drives(mech, c[0], c[1]),
                        kern_vm: lambda c: vm(c[1], c[0], max_iter=60, max_step=0.5),
                        base: numpy_route(lambda c: solve_drives(mech, c[0], c[1])),
                        direct: fwd, direct_np: numpy_route(fwd)},
                       cases, repeat)  # fmt: skip
    fast, slow = out[kern], out[base]
    floor = evaluation_us(kernel, cases[0])
    doc: dict[str, object] = {
        "mechanism": mech.name,
        "poses": len(cases),
        "per_call_us": times,
        "ratios": [
            ratio(base, kern, times),
            ratio(kern, kern_vm, times),
            ratio(direct, kern, times),
            ratio(direct_np, direct, times),
        ],
        "max_abs_dq_kernel_vs_numpy": float(
            max(np.max(np.abs(a[0] - b[0])) for a, b in zip(fast, slow))
        ),
        "max_abs_dq_vm_vs_numpy": float(
            max(np.max(np.abs(a.q - b[0])) for a, b in zip(out[kern_vm], slow))
        ),
        "iteration_mismatches": int(sum(a[1] != b[1] for a, b in zip(fast, slow))),
        "mean_iterations": float(np.mean([r[1] for r in slow])),
        "worst_residual_m": float(max(r[2] for r in fast)),
        "floor_us": {FLOOR: floor},
        "ratio_to_floor": {"measured": kern, "floor": FLOOR, "ratio": times[kern] / floor},
        "forward_over_kernel_solve": ratio(direct, kern, times),  # goal <= 2
        "kernel_compiled": kernel.shared.compiled,
        "vm_instructions": vm.shared.function.n_instructions(),
        "target": "<= 20 us per pose (kernel)",
    }
    if poses is not None:
        values = np.array([s.solutions[0].output for s in out[direct]])
        doc["max_output_error"] = float(np.max(np.abs(values - poses)))
    return doc


#: The floor of a warm solve: one call of the kernel function on bound buffers.
FLOOR = f"one evaluation of the kernel function on bound buffers ({CHUNK} iterations)"


def evaluation_us(kernel: ClosureNewtonKernel, case: tuple, calls: int = 5000) -> float:
    """Best of 5 loops: one evaluation of ``kernel``'s function on its buffers [µs]."""
    buf = kernel._buffers()
    buf.inputs[0][:], buf.inputs[1][:], buf.inputs[2][0] = case[1], case[0], 0.5
    best = np.inf
    for _ in range(5):
        start = time.perf_counter()
        for _ in range(calls // 5):
            buf.evaluate()
        best = min(best, (time.perf_counter() - start) / (calls // 5))
    return 1e6 * best


def bench_call_overhead(mech: rcm_pin.Mechanism, calls: int = 20000) -> dict[str, object]:
    """One evaluation of the compiled kernel function, three ways of calling it (part 2)."""
    fun = provider.newton_function(mech)
    home = mech.home
    kernel = compiled_kernel(mech)
    args = [home, home[mech.loops.drive_q], np.array([0.5]), kernel.bounds]  # type: ignore[union-attr]
    buf = BufferedFunction(fun)
    for dst, src in zip(buf.inputs, args):
        dst[:] = src
    ways = {"Function.__call__ (numpy in, DM out)": lambda: fun(*args),
            "Function.call (list of numpy)": lambda: fun.call(args),
            "BufferedFunction.evaluate (bound buffers)": buf.evaluate}  # fmt: skip
    per: dict[str, float] = {}
    for name, fn in ways.items():
        best = np.inf
        for _ in range(5):
            start = time.perf_counter()
            for _ in range(calls // 5):
                fn()
            best = min(best, (time.perf_counter() - start) / (calls // 5))
        per[name] = 1e6 * best
    return {"mechanism": mech.name, "function": fun.name(), "iterations_per_call": CHUNK,
            "per_call_us": per, "statistic": "best of 5 loops"}  # fmt: skip


def bench_batched(mech: rcm_pin.Mechanism, n: int, repeat: int, per_pose_us: float) -> dict:
    """The vectorised planar Newton on n poses at once (part 3)."""
    g = geometry(mech)
    tree = PlanarTree.from_mechanism(mech)
    poses, qd = sweep(g, n)
    guess = np.roll(p3.full_q(g, poses, qd), 1, axis=0)  # start from the neighbour's solution
    batch_solve_passive(mech, tree, qd, guess)  # warm-up (first touch of the big arrays)
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        q, norms = batch_solve_passive(mech, tree, qd, guess)
        times.append(time.perf_counter() - start)
    batched, base = "batch_solve_passive (per pose)", "solve_drives (kernel, warm start, per pose)"
    per = {batched: 1e6 * float(np.median(times)) / n, base: per_pose_us}
    return {
        "mechanism": mech.name,
        "poses": n,
        "per_pose_us": per,
        "total_ms": 1e3 * float(np.median(times)),
        "ratios": [ratio(base, batched, per)],
        "max_residual_m": float(np.max(norms)),
        "max_output_error": float(np.max(np.abs(tree.output(q) - poses))),
        "target": "< 2 us per pose",
    }


def bench_all_modes(name: str, n: int, repeat: int, seed: int) -> dict[str, object]:
    """``forward(all_modes=True)`` near the home configuration (part 4)."""
    mech = rcm_pin.load(name)
    compiled_kernel(mech)
    loops = mech.loops
    assert loops is not None
    home = mech.home
    rng = np.random.default_rng(seed)
    drives = home[loops.drive_q] + rng.uniform(-0.05, 0.05, (n, loops.dof))
    full = "rcm_pin.forward(all_modes=True) (kernel)"
    full_np = "rcm_pin.forward(all_modes=True) (numpy route)"
    warm = "solve_drives (kernel, warm start from home)"
    seeds = "position_solver(mech).direct (closed-form seeds only)"
    solver = position_solver(mech)
    times, out = timed({full: lambda d: rcm_pin.forward(mech, d, all_modes=True),
                        full_np: numpy_route(lambda d: rcm_pin.forward(mech, d, all_modes=True)),
                        warm: lambda d: solve_drives(mech, d, home),
                        seeds: lambda d: solver.direct(mech, d)},
                       list(drives), repeat)  # fmt: skip
    results = out[full]
    counts = sorted({r.count for r in results})
    return {
        "mechanism": name,
        "drive_sets": n,
        "method": results[0].method,
        "assembly_modes": counts,
        "per_call_us": times,
        "ratios": [
            ratio(full_np, full, times),
            ratio(full, warm, times),
            ratio(full, seeds, times),
        ],
        "max_abs_dq_kernel_vs_numpy": float(
            max(
                np.max(np.abs(a.q - b.q))
                for ra, rb in zip(results, out[full_np])
                for a, b in zip(ra.solutions, rb.solutions, strict=True)
            )
        ),
        "worst_residual_m": float(max(s.residual for r in results for s in r.solutions)),
    }


def main(argv: list[str] | None = None) -> dict[str, object]:
    """Run the three parts and print the JSON document."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n-sweep", type=int, default=2000, help="poses of the per-pose sweep")
    ap.add_argument("--n-batch", type=int, default=100_000, help="poses of the batched solve")
    ap.add_argument("--n-drives", type=int, default=200, help="drive sets per mechanism "
                    "(all_modes)")  # fmt: skip
    ap.add_argument("--repeat", type=int, default=3, help="passes (median taken)")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)

    sweeps = [bench_sweep(rcm_pin.load(nm), args.n_sweep, args.repeat) for nm in ALL_MODES]
    sweeps += [bench_sweep(rcm_pin.load(nm), args.n_sweep // 4, args.repeat, 0.05)
               for nm in OTHERS]  # fmt: skip
    mech = rcm_pin.load("planar_3rrr")
    per_pose = sweeps[0]["per_call_us"]["solve_drives (kernel)"]  # type: ignore[index]
    doc: dict[str, object] = {
        "benchmark": "closed-loop direct position",
        "repeat": args.repeat,
        "statistic": "median over every timed call of interleaved passes "
        "(batched: median run / poses)",
        "sweep": sweeps,
        "call_overhead": bench_call_overhead(mech),
        "batched": bench_batched(mech, args.n_batch, args.repeat, per_pose),
        "all_modes": [
            bench_all_modes(nm, args.n_drives, args.repeat, args.seed) for nm in ALL_MODES
        ],
    }
    print(json.dumps(doc, indent=2))
    return doc


if __name__ == "__main__":
    main()
