"""The 3-PPaPa's batched direct solver (:mod:`rcm_pin.mechanisms.translational_3ppapa.direct`).

Routes cross-checked: the paper's explicit inverse (round trip, every working mode), the
older seeded Newton on F (``closed_form.direct_position``), Pinocchio's purely numeric
multistart on the closures of both parallelogram models, and ``rcm_pin.forward`` (the
family hook, polished on Pinocchio's closures).
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import EXACT

import rcm_pin
from rcm_pin.analysis.closed_position import direct_position_multistart
from rcm_pin.errors import InvalidInputError
from rcm_pin.mechanisms import translational_3ppapa as tp


@pytest.fixture(scope="module")
def mm():
    return rcm_pin.load("translational_3ppapa")


@pytest.fixture(scope="module")
def ml():
    return rcm_pin.load("translational_3ppapa_loops")


@pytest.fixture(scope="module")
def g(mm):
    return tp.geometry(mm)


def drives_and_points(g, n, seed):
    """n random points of the reach (|p| < 0.95 min(l1, l2)) in random modes, their drives."""
    rng = np.random.default_rng(seed)
    r = 0.95 * min(g.l1, g.l2)
    pts, modes = rng.uniform(-r, r, (n, 3)), rng.integers(0, 64, n)
    q = np.array([{lab: q for lab, q, _ in tp.inverse_position(g, p)}[tp.MODES[k]]
                  for p, k in zip(pts, modes, strict=True)])  # fmt: skip
    return q, pts, modes


def as_set(sols):
    return {(lab, tuple(np.round(p, 8))) for lab, p in sols}


def test_inverse_then_direct_returns_every_point_in_its_mode(g):
    q, pts, modes = drives_and_points(g, 150, seed=1)
    sol = tp.direct_batch(g, q)
    assert sol.residual.max() <= 1e-13
    for j, (p, k) in enumerate(zip(pts, modes, strict=True)):
        mine = sol.point[(sol.sample == j) & (sol.mode == k)]
        assert len(mine) >= 1
        np.testing.assert_allclose(mine[np.argmin(np.abs(mine - p).max(1))], p, atol=1e-12)
    counts = np.bincount(sol.sample, minlength=len(q))
    assert counts.max() <= 64  # Bezout: 4³ complex roots of the squared system


def test_every_solution_is_an_inverse_solution_with_its_label(g):
    """Each (label, P) solves F = 0 in that mode and the inverse gives back the drives."""
    q, _, _ = drives_and_points(g, 30, seed=2)
    sol = tp.direct_batch(g, q)
    for j, lab, p in zip(sol.sample, sol.labels(), sol.point, strict=True):
        inv = {m: qq for m, qq, _ in tp.inverse_position(g, p)}
        np.testing.assert_allclose(inv[lab], q[j], atol=1e-12)


def test_batched_solver_matches_the_seeded_newton(g):
    q, _, _ = drives_and_points(g, 6, seed=3)
    for qi in q:
        assert as_set(tp.direct_all(g, qi)) == as_set(tp.direct_position(g, qi))


@pytest.mark.parametrize("name", ["translational_3ppapa", "translational_3ppapa_loops"])
def test_pinocchio_multistart_finds_no_assembly_the_solver_misses(name, mm, ml, g):
    m = mm if name == "translational_3ppapa" else ml
    q, _, _ = drives_and_points(g, 2, seed=4)
    for qi in q:
        mine = tp.direct_all(g, qi)
        numeric = direct_position_multistart(m, qi, n_starts=24, seed=5)
        assert numeric.solutions
        for s in numeric.solutions:
            ang = tp.crank_angles(m, s.q)
            lab = tp.label(tuple(tuple(int(v) for v in np.where(np.cos(a) >= 0, 1, -1))
                                 for a in ang))  # fmt: skip
            assert s.residual <= 1e-12
            assert any(m_ == lab and np.max(np.abs(p - s.output)) < 1e-10 for m_, p in mine)


def test_forward_uses_the_solver_on_both_models(mm, ml, g):
    q, _, _ = drives_and_points(g, 3, seed=6)
    for qi in q:
        mine = tp.direct_all(g, qi)
        for m in (mm, ml):
            res = rcm_pin.forward(m, qi, all_modes=True)
            assert res.method == "closed-form seeds + Newton on Pinocchio closures"
            assert len(res.solutions) == len({tuple(np.round(p, 8)) for _, p in mine})
            for s, (_, p) in zip(res.solutions, mine, strict=False):
                assert s.residual <= EXACT
                np.testing.assert_allclose(s.output, p, atol=1e-10)
        a, b = (rcm_pin.forward(m, qi, all_modes=True).solutions for m in (mm, ml))
        for sa, sb in zip(a, b, strict=True):
            np.testing.assert_allclose(sa.output, sb.output, atol=EXACT)


@pytest.mark.parametrize("eps", [1e-3, 1e-4, 1e-5])
def test_two_close_assembly_modes_near_a_type_2_point_are_both_found(g, eps):
    """Next to det A = 0 two assembly modes of the same working mode nearly merge (their
    roots of g(z) fall in one grid interval): both are found by the extremum split."""
    from rcm_pin.mechanisms.translational_3ppapa.verdicts import type2_points

    rng = np.random.default_rng(9)
    for k in rng.integers(0, 64, 6):
        signs = np.array(tp.SIGN_PATTERNS[int(k)], dtype=float)
        p = type2_points(g, signs, 1, rng)[0] + eps * rng.normal(size=3)
        inv = {lab: q for lab, q, _ in tp.inverse_position(g, p)}
        if tp.MODES[int(k)] not in inv:
            continue
        sol = tp.direct_batch(g, inv[tp.MODES[int(k)]][None])
        mine = sol.point[sol.mode == k]
        assert np.min(np.max(np.abs(mine - p), axis=1)) < 1e-9, (k, p)


def test_unreachable_drives_have_no_assembly(g):
    sol = tp.direct_batch(g, np.array([[5.0, 5.0, 5.0], [1.0, 1.0, 1.0]]))
    assert set(sol.sample.tolist()) == {1}


@pytest.mark.parametrize("bad", [np.zeros(3), np.zeros((2, 2)), np.array([[np.nan, 1.0, 1.0]])])
def test_bad_drives_are_refused(g, bad):
    with pytest.raises(InvalidInputError) as e:
        tp.direct_batch(g, bad)
    assert str(e.value) == (
        f"3-PPaPa drives have shape {bad.shape} (or are not finite); valid: finite (M, 3) [m]"
    )
