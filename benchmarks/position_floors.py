"""``rcm_pin.inverse`` / ``rcm_pin.forward`` of every catalogue mechanism against its floor.

A part of ``bench_ik.py`` (``--families``). Per mechanism, per-call times [µs] (median
over every timed call of ``repeat`` interleaved passes over the same targets) of

* ``rcm_pin.inverse(mech, target)`` (all branches / working modes, every check) against
  its floor, the candidates alone: the scalar analytic IK (``ik_pose``: rcm 6-DOF;
  ``ik_pose_4dof``: 4-DOF), else the family's position solver (closed form or multistart,
  :func:`rcm_pin.analysis.capabilities.position_solver`) and, for a closed mechanism,
  the Newton polish of each candidate on Pinocchio's closures (``closed_position.polish``).
  Where the serial branch kernel answers (:mod:`rcm_pin.model.serial_branches`, compiled
  up front), also the same ``inverse`` on the numpy route (kernels disabled), interleaved:
  ``ratio_numpy_route`` is the ratio without the kernel;
* ``rcm_pin.forward``: serial ``forward(mech, q)`` against one Pinocchio forward
  kinematics of the output frame; closed ``forward(mech, drives, q_guess=...)`` against
  ``solve_drives`` from the same guess (the compiled closure kernel, compiled up front).

Targets: serial, the tool pose at seeded random coordinates inside the limits; closed,
the output at drive values within ±0.05 of home (solved from home), the guess the
solution at drives 0.001 away.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np
import pinocchio as pin

import rcm_pin
from rcm_pin.analysis import closed_position as cp
from rcm_pin.analysis.capabilities import position_solver
from rcm_pin.analysis.position import _as_value
from rcm_pin.errors import RcmPinError
from rcm_pin.mechanisms.rcm.analytic_ik import ik_pose, ik_pose_4dof
from rcm_pin.mechanisms.rcm.closed_form import wrist_type
from rcm_pin.model import kernels, serial_branches

#: Mechanisms on the numeric multistart (tens of ms a call): this many targets.
SLOW_TARGETS = 2


def timed(cases: dict[str, Callable[[Any], Any]], args: list, repeat: int) -> dict[str, float]:
    """Median time per call [µs] of each case over ``repeat`` interleaved passes."""
    for fn in cases.values():
        fn(args[0])
    times: dict[str, list[float]] = {name: [] for name in cases}
    for _ in range(repeat):
        for name, fn in cases.items():
            for a in args:
                start = time.perf_counter()
                fn(a)
                times[name].append(time.perf_counter() - start)
    return {name: 1e6 * float(np.median(t)) for name, t in times.items()}


def _serial_targets(mech: rcm_pin.Mechanism, n: int, seed: int) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    lo, hi = np.maximum(mech.lower, -np.pi), np.minimum(mech.upper, np.pi)
    qs = rng.uniform(lo + 0.01 * (hi - lo), hi - 0.01 * (hi - lo), (n, mech.nq))
    return [q for q in qs]


def _closed_cases(mech: rcm_pin.Mechanism, n: int, seed: int) -> list[tuple]:
    """(drives, guess, output value) near home."""
    loops = mech.loops
    assert loops is not None
    rng, home, out = np.random.default_rng(seed), mech.home, []
    for _ in range(n):
        d = home[loops.drive_q] + rng.uniform(-0.05, 0.05, loops.dof)
        try:
            q = cp.solve_drives(mech, d, home)[0]
            guess = cp.solve_drives(mech, d + 0.001, q)[0]
        except RcmPinError:
            continue
        out.append((d, guess, mech.output_value(q) if mech.output.present else None))
    return out


def _inverse_floor(mech: rcm_pin.Mechanism) -> tuple[str, Callable[[Any], Any]]:
    """The floor of ``inverse`` (module docstring): its name and a function of a target."""
    output = mech.output
    if mech.family.name == "rcm" and mech.nq == 6:
        wrist = wrist_type(mech)
        return "analytic_ik.ik_pose (scalar fast path)", lambda T: ik_pose(T, wrist)
    if mech.family.name == "rcm" and mech.nq == 4:
        return "analytic_ik.ik_pose_4dof", ik_pose_4dof
    solver = position_solver(mech)

    def candidates(t: Any) -> Any:
        value = output.coerce(_as_value(output, t))
        found = solver.inverse(mech, value, output)
        if mech.loops is None:
            return found
        return [cp.polish(mech, value, output, b.q) for b in found.branches]

    what = "the position solver's candidates" + ("" if mech.loops is None else " + polish")
    return what, candidates


def compile_now(kernel: object) -> None:
    """Compile a kernel's function now (benchmarks measure the compiled state)."""
    shared = getattr(kernel, "shared", None)
    if shared is not None and shared.compile_after is not None:
        shared.compile()


def _numpy_inverse(mech: rcm_pin.Mechanism, target: Any) -> Any:
    with kernels.disabled():
        return rcm_pin.inverse(mech, target)


def bench_mechanism(name: str, n: int, repeat: int, seed: int) -> dict[str, object]:
    """Both ratios of one mechanism."""
    mech = rcm_pin.load(name)
    doc: dict[str, object] = {"mechanism": name, "family": mech.family.name}
    if mech.loops is None:
        qs = _serial_targets(mech, n if mech.family.name == "rcm" else SLOW_TARGETS, seed)
        model, data, fid = mech.model, mech.data, mech.output.frame_id

        def fk(q: np.ndarray) -> Any:
            pin.forwardKinematics(model, data, q if mech.identity_order else mech.to_pin(q))
            return pin.updateFramePlacement(model, data, fid)

        targets = [rcm_pin.tool_pose(mech, q) for q in qs]
        compile_now(serial_branches.warm(mech))
        fwd = {"forward": lambda q: rcm_pin.forward(mech, q), "floor": fk}
        fwd_args, floor_fwd = qs, "Pinocchio forward kinematics of the output frame"
    else:
        cases = _closed_cases(mech, n, seed)
        compile_now(kernels.warm(mech))
        fwd = {"forward": lambda c: rcm_pin.forward(mech, c[0], q_guess=c[1]),
               "floor": lambda c: cp.solve_drives(mech, c[0], c[1])}  # fmt: skip
        fwd_args, floor_fwd = cases, "solve_drives from the guess (closure kernel)"
        targets = [c[2] for c in cases] if mech.output.present else []
    t = timed(fwd, fwd_args, repeat)
    doc["forward"] = {"floor": floor_fwd, "per_call_us": t, "ratio": t["forward"] / t["floor"]}
    if targets:
        floor_inv, floor_fn = _inverse_floor(mech)
        cases = {"inverse": lambda x: rcm_pin.inverse(mech, x), "floor": floor_fn}
        kernel = mech.loops is None and serial_branches.serial_branches(mech) is not None
        if kernel:  # the same call on the numpy route, interleaved (before / after)
            cases["inverse_numpy_route"] = lambda x: _numpy_inverse(mech, x)
        t = timed(cases, targets, repeat)
        doc["inverse"] = {"floor": floor_inv, "targets": len(targets), "per_call_us": t,
                          "ratio": t["inverse"] / t["floor"]}  # fmt: skip
        if kernel:
            doc["inverse"]["ratio_numpy_route"] = t["inverse_numpy_route"] / t["floor"]
    return doc


def bench_families(n: int, repeat: int, seed: int) -> list[dict[str, object]]:
    """Every catalogue mechanism (module docstring)."""
    return [bench_mechanism(name, n, repeat, seed) for name in rcm_pin.names()]


__all__ = ["bench_families", "bench_mechanism", "compile_now", "timed"]
