"""Singularity verdicts of the 3-PPaPa: the paper's (scaled) A, B vs Pinocchio vs screws.

A small version of the acceptance run (``benchmarks/translational_acceptance.py``: 10^3
points): random reach points in random modes, points placed on det A = 0 by bisection and
points with a stretched parallelogram; every route gives the same verdict on both models.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import EXACT

import rcm_pin
from rcm_pin.analysis.loop_velocity import classify
from rcm_pin.analysis.screws import screw_test
from rcm_pin.mechanisms import translational_3ppapa as tp
from rcm_pin.mechanisms.translational_3ppapa import verdicts as vd


@pytest.fixture(scope="module")
def models():
    return [rcm_pin.load(n) for n in tp.MODELS]


@pytest.fixture(scope="module")
def g(models):
    return tp.geometry(models[0])


def screw_label(m, q):
    st = screw_test(m, q)
    return "type 1+2" if st.type1 and st.type2 else (
        "type 1" if st.type1 else "type 2" if st.type2 else "regular")  # fmt: skip


def routes(models, g, mode, p):
    q, ang = {lab: (q, a) for lab, q, a in tp.inverse_position(g, p)}[mode]
    paper = vd.paper_verdict(ang)
    labels = {paper.label}
    for m in models:
        qm = tp.mech_q(m, q, ang)
        assert float(np.linalg.norm(m.closure_residual(qm))) <= EXACT
        labels |= {classify(m, qm).label, screw_label(m, qm)}
    return labels, paper


def test_random_points_are_regular_for_every_route(models, g):
    rng = np.random.default_rng(20)
    for p in rng.uniform(-0.38, 0.38, (12, 3)):
        labels, paper = routes(models, g, tp.MODES[int(rng.integers(64))], p)
        assert labels == {"regular"} and paper.a_finite


def test_points_on_det_a_zero_are_type_2_for_every_route(models, g):
    rng = np.random.default_rng(21)
    for k in rng.integers(0, 64, 4):
        signs = np.array(tp.SIGN_PATTERNS[int(k)], dtype=float)
        p = vd.type2_points(g, signs, 1, rng)[0]
        assert abs(np.linalg.det(tp.a_matrix(g, p, signs))) < EXACT
        labels, paper = routes(models, g, tp.MODES[int(k)], p)
        assert labels == {"type 2"} and paper.a_finite  # the paper's A finds this set


def test_stretched_parallelograms_are_type_1_and_hidden_from_the_unscaled_a(models, g):
    rng = np.random.default_rng(22)
    for k, p in zip(rng.integers(0, 64, 4), vd.type1_points(g, 4, rng), strict=True):
        labels, paper = routes(models, g, tp.MODES[int(k)], p)
        assert labels == {"type 1"} and not paper.a_finite  # A infinite, B = I regular


def test_scaled_matrices_give_the_same_velocities(g):
    """A' = D A, B' = D: −A'⁻¹B' = −A⁻¹ (B = I) away from the singular sets."""
    rng = np.random.default_rng(23)
    for p in rng.uniform(-0.3, 0.3, (5, 3)):
        for _, _, ang in tp.inverse_position(g, p)[::21]:
            a2, b2 = vd.scaled_ab(ang)
            a = tp.a_from_angles(ang)
            np.testing.assert_allclose(np.linalg.solve(a2, b2), np.linalg.inv(a), atol=1e-11)
