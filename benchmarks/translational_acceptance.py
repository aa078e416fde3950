"""Acceptance run of the translational 3-PPaPa (issue 13), run once by hand (minutes).

    .venv/bin/python benchmarks/translational_acceptance.py [--points 1000] [--seed 0]

1. ``--points`` random platform points of the reach (|p_k| < 0.95 min(l1, l2)), every one of
   the 64 working modes: the paper's explicit inverse gives the drives; the batched direct
   solver (:mod:`rcm_pin.mechanisms.translational_3ppapa.direct`) must return the point in
   its mode (max position error, count of misses); Pinocchio's Newton on the mimic model's
   closures from that solution (``rcm_pin.forward`` with a guess) gives the closure residual
   and the point again; ``rcm_pin.inverse`` (Pinocchio polish of the 64 modes) its residuals.
2. The two models: one random mode per point, the loop model (4R parallelograms) from the same
   closed-form configuration: platform points of both models agree (max difference).
3. Verdicts on the random points (their random mode) and on points placed on each singular
   set (det A = 0 by bisection in random modes; a stretched parallelogram): Pinocchio's A/B
   classifier and the screw test on both models, and the paper's (scaled) A, B.
"""

from __future__ import annotations

import argparse
import time
from collections import Counter

import numpy as np

import rcm_pin
from rcm_pin.analysis.loop_velocity import classify
from rcm_pin.analysis.screws import screw_test
from rcm_pin.mechanisms import translational_3ppapa as tp
from rcm_pin.mechanisms.translational_3ppapa import verdicts as vd


def closure(m: rcm_pin.Mechanism, q: np.ndarray) -> float:
    return float(np.linalg.norm(m.closure_residual(q)))


def screw_label(m: rcm_pin.Mechanism, q: np.ndarray) -> str:
    st = screw_test(m, q)
    if st.type1 and st.type2:
        return "type 1+2"
    return "type 1" if st.type1 else "type 2" if st.type2 else "regular"


def _ratio(angles: np.ndarray) -> float:
    sv = np.linalg.svd(tp.a_from_angles(angles), compute_uv=False)
    return float(sv[-1] / sv[0])


def round_trip(mm: rcm_pin.Mechanism, g: tp.Geometry3PPaPa, pts: np.ndarray) -> None:
    t0 = time.perf_counter()
    inv = [tp.inverse_position(g, p) for p in pts]
    drives = np.array([[q for _, q, _ in sols] for sols in inv]).reshape(-1, 3)
    t1 = time.perf_counter()
    sol = tp.direct_batch(g, drives)
    t2 = time.perf_counter()
    err, miss, found = np.zeros(len(drives)), 0, np.zeros((len(drives), 3))
    target = np.repeat(pts, 64, axis=0)
    mode = np.tile(np.arange(64), len(pts))
    order = np.lexsort((sol.mode, sol.sample))
    s_sample, s_mode, s_point = sol.sample[order], sol.mode[order], sol.point[order]
    starts = np.searchsorted(s_sample, np.arange(len(drives)))
    ends = np.searchsorted(s_sample, np.arange(len(drives)), side="right")
    for j in range(len(drives)):
        sel = slice(starts[j], ends[j])
        mine = s_point[sel][s_mode[sel] == mode[j]]
        if not len(mine):
            miss += 1
            err[j] = np.inf
            continue
        dist = np.max(np.abs(mine - target[j]), axis=1)
        err[j], found[j] = np.min(dist), mine[np.argmin(dist)]
    print(f"[1] {len(pts)} points x 64 modes = {len(drives)} drive sets")
    print(f"    closed-form inverse: {t1 - t0:.2f} s; batched direct: {t2 - t1:.2f} s "
          f"({1e3 * (t2 - t1) / len(drives):.2f} ms per drive set), {len(sol.sample)} "
          f"assemblies, at most {np.bincount(sol.sample).max()} per drive set")  # fmt: skip
    ratio = np.array([_ratio(ang) for sols in inv for _, _, ang in sols])
    near = ratio < 1e-6  # next to the type-2 set: error ≈ rounding / σ_min(A)
    print(f"    {near.sum()} drive sets have σ_min/σ_max(A) < 1e-6 (min {ratio.min():.1e}): "
          f"max position error there {np.max(err[near], initial=0.0):.2e} m, elsewhere "
          f"{np.max(err[~near], initial=0.0):.2e} m")  # fmt: skip
    print(f"    inverse -> direct: misses {miss}, max position error {np.max(err):.2e} m, "
          f"max |F| {sol.residual.max():.2e} m")  # fmt: skip
    t3 = time.perf_counter()
    res_f, err_f, res_i, err_i = 0.0, 0.0, 0.0, 0.0
    for j, (p, sols) in enumerate(zip(pts, inv, strict=True)):
        for k, (_, q, _) in enumerate(sols):
            d = found[64 * j + k]  # the direct solver's point, seeding Pinocchio's Newton
            legs = [tp.leg_angles(g, d, i, tp.SIGN_PATTERNS[k][i]) for i in range(3)]
            ang = np.array([x[1:] for x in legs if x is not None])
            s = rcm_pin.forward(mm, q, q_guess=tp.mech_q(mm, q, ang)).solutions[0]
            res_f = max(res_f, closure(mm, s.q))
            err_f = max(err_f, float(np.max(np.abs(s.output - p))))
        for s in rcm_pin.inverse(mm, p).solutions:
            res_i = max(res_i, closure(mm, s.q))
            err_i = max(err_i, float(np.max(np.abs(s.output - p))))
    print(
        f"    Pinocchio forward from the direct solutions: max closure {res_f:.2e} m, "
        f"max position error {err_f:.2e} m; rcm_pin.inverse (64 modes each): max closure "
        f"{res_i:.2e} m, max output error {err_i:.2e} m ({time.perf_counter() - t3:.1f} s)"
    )


def models(mm, ml, g, pts, rng) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """Both models in one random mode per point; returns (mode, P, angles) of each."""
    diff, res, picked = 0.0, 0.0, []
    for p in pts:
        lab, q, ang = tp.inverse_position(g, p)[int(rng.integers(64))]
        outs = []
        for m in (mm, ml):
            s = rcm_pin.forward(m, q, q_guess=tp.mech_q(m, q, ang)).solutions[0]
            res = max(res, closure(m, s.q))
            outs.append(s.output)
        diff = max(diff, float(np.max(np.abs(outs[0] - outs[1]))))
        picked.append((lab, p, ang))
    print(f"[2] two models, {len(pts)} points (one random mode each): max platform difference "
          f"{diff:.2e} m, max closure {res:.2e} m")  # fmt: skip
    return picked


def verdicts(mm, ml, g, rng, random_set, n_sing) -> None:
    sets: dict[str, list[tuple[str, np.ndarray]]] = {"random": [(m, p) for m, p, _ in random_set]}
    sets["det A = 0"] = []
    for p_mode in rng.integers(0, 64, n_sing):
        signs = np.array(tp.SIGN_PATTERNS[int(p_mode)], dtype=float)
        sets["det A = 0"].append((tp.MODES[int(p_mode)], vd.type2_points(g, signs, 1, rng)[0]))
    sets["stretched"] = [(tp.MODES[int(k)], p) for k, p in
                         zip(rng.integers(0, 64, n_sing), vd.type1_points(g, n_sing, rng),
                             strict=True)]  # fmt: skip
    for name, items in sets.items():
        counts: Counter[str] = Counter()
        disagree, unscaled = 0, Counter()
        for lab, p in items:
            sols = {m: (q, a) for m, q, a in tp.inverse_position(g, p)}
            q, ang = sols[lab]
            paper = vd.paper_verdict(ang)
            labels = {"paper A', B'": paper.label}
            for m in (mm, ml):
                qm = tp.mech_q(m, q, ang)
                labels[f"{m.name} A/B"] = classify(m, qm).label
                labels[f"{m.name} screws"] = screw_label(m, qm)
            disagree += len(set(labels.values())) > 1
            counts[paper.label] += 1
            unscaled["A finite" if paper.a_finite else "A infinite"] += 1
        print(
            f"[3] {name}: {len(items)} points, verdicts {dict(counts)}, routes disagree on "
            f"{disagree}; paper's unscaled A: {dict(unscaled)}, B = I (never singular)"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--singular", type=int, default=200)
    args = ap.parse_args()
    mm, ml = rcm_pin.load("translational_3ppapa"), rcm_pin.load("translational_3ppapa_loops")
    g = tp.geometry(mm)
    rng = np.random.default_rng(args.seed)
    r = 0.95 * min(g.l1, g.l2)
    pts = rng.uniform(-r, r, (args.points, 3))
    t0 = time.perf_counter()
    round_trip(mm, g, pts)
    picked = models(mm, ml, g, pts, rng)
    verdicts(mm, ml, g, rng, picked, args.singular)
    print(f"total {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
