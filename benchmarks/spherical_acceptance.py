"""Acceptance run of issue 12 (the spherical 3-RRR), run on demand, never in the test suite.

Prints one JSON document with the figures of each check:

1. ``inverse_forward``: ``--n`` random orientations (Haar), every working mode of the inverse
   (Pinocchio-polished): the closure residual, then the forward problem from its drives (every
   assembly mode): the smallest orientation error |log₃(R Rᵀ_target)| [rad]; and the distance
   of the platform point at O from O;
2. ``forward_inverse``: ``--n`` random drive triples, every assembly mode of the forward
   problem, each through the inverse: the smallest drive error [rad] among its working modes;
3. ``verdicts``: type-1 / type-2 verdicts of Pinocchio's A/B, the screw test and the family's
   closed form on ``--n`` random poses (random working modes) and on poses placed on each
   singular set (the six type-1 curves of the Agile Eye, their meeting points, and type-2
   points off the type-1 set of a general design, located by ``brentq`` on det A);
4. ``velocity``: the output angular velocity ω = −A⁻¹B φ̇ (closed form) against Pinocchio's
   output Jacobian (max relative difference) on every pose of 1, and against central finite
   differences of the forward problem (h = 1e-6, and its Richardson extrapolation with h/2,
   O(h⁴), for poses near a type-2 set where the O(h²) truncation error is large) on
   ``--n-fd`` of them.

Both the default Agile Eye and a general design (θ_i1 = 80°, θ_i2 = 70°) are run.

    python benchmarks/spherical_acceptance.py               # about 5 min on one core
    python benchmarks/spherical_acceptance.py --n 100       # quick
"""

from __future__ import annotations

import argparse
import json
import time
from typing import Any

import numpy as np
import pinocchio as pin
from scipy.optimize import brentq

import rcm_pin
from rcm_pin.analysis.loop_velocity import (
    SINGULAR_TOL,
    classify,
    closure_jacobian,
    velocity_matrices,
)
from rcm_pin.analysis.screws import screw_test
from rcm_pin.errors import UnreachablePoseError
from rcm_pin.mechanisms import spherical_3rrr as s3
from rcm_pin.mechanisms.spherical_3rrr import closed_form as sc
from rcm_pin.mechanisms.spherical_3rrr import maps
from rcm_pin.rotations import random_rotations

GENERAL = {f"theta_{i}{k}": t for i in (1, 2, 3) for k, t in ((1, 80), (2, 70))}


def _origin_offset(mech: rcm_pin.Mechanism, q: np.ndarray) -> float:
    pin.framesForwardKinematics(mech.model, mech.data, mech.q_pin(q))
    return float(np.linalg.norm(mech.data.oMf[mech.output.frame_id].translation))


def inverse_forward(mech: rcm_pin.Mechanism, rots: np.ndarray) -> dict[str, Any]:
    g = s3.geometry(mech)
    res, err, off, n_sol, skipped = 0.0, 0.0, 0.0, 0, 0
    for R in rots:
        if np.any(sc.leg_roots(g, R)[1] < 1e-9):  # unreachable (general design) or on type 1
            skipped += 1
            continue
        for sol in rcm_pin.inverse(mech, R).solutions:
            n_sol += 1
            res = max(res, float(np.linalg.norm(mech.closure_residual(sol.q))))
            off = max(off, _origin_offset(mech, sol.q))
            fwd = rcm_pin.forward(mech, sol.q[mech.require_loops().drive_q], all_modes=True)
            e = min(float(np.linalg.norm(pin.log3(f.output.reshape(3, 3) @ R.T)))
                    for f in fwd.solutions)  # fmt: skip
            err = max(err, e)
    return {"orientations": len(rots) - skipped, "skipped": skipped, "solutions": n_sol,
            "max_closure_residual": res, "max_inverse_forward_error_rad": err,
            "max_platform_point_offset_m": off}  # fmt: skip


def forward_inverse(mech: rcm_pin.Mechanism, drives: np.ndarray) -> dict[str, Any]:
    counts: dict[int, int] = {}
    err, res = 0.0, 0.0
    dq = mech.require_loops().drive_q
    for phi in drives:
        try:
            fwd = rcm_pin.forward(mech, phi, all_modes=True)
        except UnreachablePoseError:  # a general design: drives without an assembly
            counts[0] = counts.get(0, 0) + 1
            continue
        counts[fwd.count] = counts.get(fwd.count, 0) + 1
        for f in fwd.solutions:
            res = max(res, float(np.linalg.norm(mech.closure_residual(f.q))))
            back = rcm_pin.inverse(mech, f.output).solutions
            e = min(float(np.max(np.abs(np.angle(np.exp(1j * (s.q[dq] - phi)))))) for s in back)
            err = max(err, e)
    return {"inputs": len(drives), "assembly_mode_counts": counts,
            "max_closure_residual": res, "max_forward_inverse_drive_error_rad": err}  # fmt: skip


def _verdict(mech: rcm_pin.Mechanism, q: np.ndarray) -> tuple[tuple[bool, bool], ...]:
    m1, m2 = sc.measures(s3.geometry(mech), *s3.pose_and_drives(mech, q))
    c, s = classify(mech, q), screw_test(mech, q)
    return (m1 < SINGULAR_TOL, m2 < SINGULAR_TOL), (c.type1, c.type2), (s.type1, s.type2)


def _tally(mech: rcm_pin.Mechanism, qs: list[np.ndarray]) -> dict[str, int]:
    out = {"poses": len(qs), "type1": 0, "type2": 0, "disagree": 0, "closed_form_vs_screw": 0,
           "passive_rank_deficient": 0}  # fmt: skip
    for q in qs:
        fam, pv, sv = _verdict(mech, q)
        out["type1"] += int(fam[0])
        out["type2"] += int(fam[1])
        out["disagree"] += int(not fam == pv == sv)
        out["closed_form_vs_screw"] += int(fam != sv)
        n_passive = len(mech.require_loops().passive_v)
        out["passive_rank_deficient"] += int(_passive_rank(mech, q) < n_passive)
    return out


def _passive_rank(mech: rcm_pin.Mechanism, q: np.ndarray) -> int:
    """Rank of the passive columns [J_c,p; J_x,p] that Pinocchio's A/B route assumes full."""
    full = np.vstack([closure_jacobian(mech, q), mech.output_jacobian(q)])
    return int(np.linalg.matrix_rank(full[:, mech.require_loops().passive_v], tol=1e-9))


def _type2_points(mg: rcm_pin.Mechanism, rng: np.random.Generator, n: int) -> list[np.ndarray]:
    gg, out = s3.geometry(mg), []
    while len(out) < n:
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)

        def det_a(s: float, axis: np.ndarray = axis) -> float:
            R = pin.exp3(s * axis)
            return float(np.linalg.det(sc.ab_matrices(gg, R, sc.inverse_position(gg, R)[0])[0]))

        grid = np.linspace(0.0, 1.5, 61)
        ok = [bool(np.all(sc.leg_roots(gg, pin.exp3(s * axis))[1] > 1e-6)) for s in grid]
        for k in range(60):
            if ok[k] and ok[k + 1] and det_a(grid[k]) * det_a(grid[k + 1]) < 0:
                s_star = brentq(det_a, grid[k], grid[k + 1], xtol=1e-15, rtol=1e-15)
                R = pin.exp3(s_star * axis)
                out.append(s3.full_q(mg, R, sc.inverse_position(gg, R)[0]))
                break
    return out


def verdicts(ms, mg, rots: np.ndarray, rng: np.random.Generator) -> dict[str, Any]:
    g = s3.geometry(ms)
    rand = [s3.full_q(ms, R, sc.inverse_position(g, R)[int(rng.integers(8))]) for R in rots]
    curve: list[np.ndarray] = []
    meet: list[np.ndarray] = []
    for leg in range(3):
        for sign in (1.0, -1.0):
            for R in maps.curve_rotations(g, leg, sign, rng.uniform(0, 2 * np.pi, 50)):
                phi = sc.inverse_position(g, R)[int(rng.integers(8))]
                phi[leg] = rng.uniform(-np.pi, np.pi)  # the aligned leg closes for any drive
                curve.append(s3.full_q(ms, R, phi))
    for R in sc.direct_position(g, np.zeros(3), degenerate=True)[:8]:
        if np.all(np.abs(np.sum(g.u * (g.v0 @ R.T), axis=1)) > 1 - 1e-9):  # all legs aligned
            for phi in rng.uniform(-np.pi, np.pi, (10, 3)):
                meet.append(s3.full_q(ms, R, phi))
    return {
        "random (Agile Eye)": _tally(ms, rand),
        "type-1 curves (Agile Eye)": _tally(ms, curve),
        "curve meeting points (Agile Eye)": _tally(ms, meet),
        "type-2 off type-1 (general design)": _tally(mg, _type2_points(mg, rng, 50)),
    }


def velocity(mech: rcm_pin.Mechanism, rots: np.ndarray, n_fd: int) -> dict[str, Any]:
    g, h = s3.geometry(mech), 1e-6
    jac, fd, fd_rich, n = 0.0, 0.0, 0.0, 0
    for k, R in enumerate(rots):
        if np.any(sc.leg_roots(g, R)[1] < 1e-6):
            continue
        phis = sc.inverse_position(g, R)
        q = rcm_pin.inverse(mech, R).solutions[k % 8].q
        R_q, phi = s3.pose_and_drives(mech, q)
        a_mat, b_mat = sc.ab_matrices(g, R_q, phi)
        j_cf = -np.linalg.solve(a_mat, b_mat)
        j_pin = velocity_matrices(mech, q).output_jacobian()
        jac = max(jac, float(np.max(np.abs(j_pin - j_cf)) / max(1.0, np.max(np.abs(j_cf)))))
        n += 1
        if n <= n_fd:
            for j in range(3):
                central = [_central(mech, q, phi, j, step) for step in (h, h / 2)]
                rich = (4.0 * central[1] - central[0]) / 3.0  # Richardson: O(h⁴)
                fd = max(fd, float(np.max(np.abs(central[0] - j_pin[:, j]))))
                fd_rich = max(fd_rich, float(np.max(np.abs(rich - j_pin[:, j]))))
        del phis
    return {"poses": n, "max_rel_jacobian_closed_form_vs_pinocchio": jac,
            "finite_difference_poses": min(n, n_fd), "max_abs_fd_vs_pinocchio": fd,
            "max_abs_richardson_fd_vs_pinocchio": fd_rich}  # fmt: skip


def _central(mech: rcm_pin.Mechanism, q: np.ndarray, phi: np.ndarray, j: int, h: float):
    """Central difference of ω along drive j (step h [rad]) through the forward problem."""
    dp = h * np.eye(3)[j]
    plus, minus = (rcm_pin.forward(mech, phi + s * dp, q_guess=q).solutions[0] for s in (1, -1))
    return pin.log3(plus.output.reshape(3, 3) @ minus.output.reshape(3, 3).T) / (2 * h)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1000, help="random orientations / drive triples")
    ap.add_argument("--n-general", type=int, default=200, help="the same, general design")
    ap.add_argument("--n-fd", type=int, default=100, help="poses checked by finite differences")
    ap.add_argument("--only", default="", help="comma-separated checks (default: all)")
    args = ap.parse_args()
    ms, mg = rcm_pin.load("spherical_3rrr"), rcm_pin.load("spherical_3rrr", **GENERAL)
    rng = np.random.default_rng(2026)
    rots, rots_g = random_rotations(rng, args.n), random_rotations(rng, args.n_general)
    drives = rng.uniform(-np.pi, np.pi, (args.n, 3))
    out: dict[str, Any] = {"n": args.n, "singular_tol": SINGULAR_TOL}
    runs = {
        "inverse_forward": lambda: {"agile_eye": inverse_forward(ms, rots),
                                    "general": inverse_forward(mg, rots_g)},
        "forward_inverse": lambda: {"agile_eye": forward_inverse(ms, drives),
                                    "general": forward_inverse(mg, drives[: args.n_general])},
        "verdicts": lambda: verdicts(ms, mg, rots, rng),
        "velocity": lambda: {"agile_eye": velocity(ms, rots, args.n_fd),
                             "general": velocity(mg, rots_g, args.n_fd // 2)},
    }  # fmt: skip
    for name, run in runs.items():
        if args.only and name not in args.only.split(","):
            continue
        t0 = time.perf_counter()
        out[name] = run()
        out[name]["seconds"] = round(time.perf_counter() - t0, 1)
    print(json.dumps(out, indent=2, default=str))


if __name__ == "__main__":
    main()
