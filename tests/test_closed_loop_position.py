"""Position problems: round trips, mode counts, continuation (closure residual < 1e-12)."""

from __future__ import annotations

import numpy as np
import pytest

import rcm_pin
from rcm_pin.analysis.batch_planar import PlanarTree, batch_solve_passive
from rcm_pin.analysis.closed_position import direct_position_multistart, direct_position_path
from rcm_pin.analysis.position import forward as direct_position
from rcm_pin.analysis.position import inverse as inverse_position
from rcm_pin.errors import SolverError
from rcm_pin.mechanisms import five_bar as fb
from rcm_pin.mechanisms import planar_3rrr
from rcm_pin.mechanisms.planar_3rrr import closed_form as p3
from rcm_pin.model.newton import RESIDUAL_TOL, solve_passive
from rcm_pin.report.closed_loops import random_poses

TOL = 1e-12


@pytest.fixture(scope="module")
def g3(m3):
    return planar_3rrr.geometry(m3)


def test_inverse_gives_eight_working_modes(m3, g3):
    for pose in random_poses(g3, 20, seed=3):
        res = inverse_position(m3, pose)
        assert res.count == 8
        for s in res.solutions:
            assert np.linalg.norm(m3.closure_residual(s.q)) < TOL
            assert np.max(np.abs(s.output - pose)) < 1e-12
        assert res.to_json()["count"] == 8


def _regular(g3, poses, q):
    """Poses whose type-2 measure σ_min/σ_max(A) exceeds 1e-2 (assembly modes well apart)."""
    a_mat, _ = p3.ab_matrices(g3, poses, q)
    sv = np.linalg.svd(a_mat * np.array([1.0, 1.0, 1.0 / 0.225]), compute_uv=False)
    return sv[:, -1] / sv[:, 0] > 1e-2


def test_direct_of_inverse_round_trip_all_modes(m3, g3):
    """direct(inverse(x)) ∋ x to 1e-10 on 10^3 random poses, every working mode's drives."""
    rng = np.random.default_rng(7)
    poses = random_poses(g3, 1000, seed=11)
    qs, ok = p3.inverse_position(g3, poses)
    assert ok.all()
    worst_pose, worst_res = 0.0, 0.0
    for pose, q8 in zip(poses, qs, strict=True):
        sols = direct_position(m3, q8[int(rng.integers(8))], all_modes=True).solutions
        worst_res = max(worst_res, max(s.residual for s in sols))
        worst_pose = max(worst_pose, min(float(np.max(np.abs(s.output - pose))) for s in sols))
    assert worst_res < TOL
    assert worst_pose < 1e-10


def test_direct_of_inverse_round_trip_newton_from_guess(m3, g3):
    """Single-branch Newton (Pinocchio closures) from a 1e-3 rad perturbation, 10^3 poses."""
    rng = np.random.default_rng(8)
    poses = random_poses(g3, 1400, seed=12)
    modes = rng.integers(8, size=len(poses))
    qs = p3.inverse_position(g3, poses)[0][np.arange(len(poses)), modes]
    keep = _regular(g3, poses, qs)
    poses, qs = poses[keep][:1000], qs[keep][:1000]
    assert len(poses) == 1000
    worst_pose, worst_res = 0.0, 0.0
    for pose, qd in zip(poses, qs, strict=True):
        guess = p3.full_q(g3, pose, qd) + rng.normal(0.0, 1e-3, 7)
        sol = direct_position(m3, qd, q_guess=guess).solutions[0]
        worst_res = max(worst_res, sol.residual)
        worst_pose = max(worst_pose, float(np.max(np.abs(sol.output - pose))))
    assert worst_res < TOL
    assert worst_pose < 1e-10


def test_direct_of_inverse_round_trip_batched(m3, g3):
    tree = PlanarTree.from_mechanism(m3)
    poses = random_poses(g3, 1400, seed=5)
    qs, _ = p3.inverse_position(g3, poses)
    keep = _regular(g3, poses, qs[:, 0])
    poses, qd = poses[keep][:1000], qs[keep][:1000, 0]
    q_true = p3.full_q(g3, poses, qd)
    rng = np.random.default_rng(1)
    q, norms = batch_solve_passive(m3, tree, qd, q_true + rng.normal(0, 1e-3, (1000, 7)))
    assert np.max(norms) < TOL
    assert np.max(np.abs(tree.output(q) - poses)) < 1e-10
    # the batched kinematics is the Pinocchio tree
    for i in range(0, 1000, 250):
        assert np.max(np.abs(tree.output(q[i : i + 1])[0] - m3.output_value(q[i]))) < 1e-14


@pytest.mark.parametrize("name", ["planar_3rrr", "five_bar", "four_bar"])
def test_batched_newton_is_the_pinocchio_newton(name):
    """batch_planar is a vectorised speed twin of rcm_pin.model.newton.solve_passive (its
    own numpy planar tree, a world-frame residual, N poses per LAPACK call): from seeded
    random drives and starts both close the loops at the same configuration (1e-9)."""
    mech = rcm_pin.load(name)
    loops, tree = mech.loops, PlanarTree.from_mechanism(mech)
    home = mech.home
    rng = np.random.default_rng(2412)
    drives = home[loops.drive_q] + rng.uniform(-0.2, 0.2, (200, loops.dof))
    starts = home + rng.normal(0.0, 0.05, (200, mech.nq))
    q, norms = batch_solve_passive(mech, tree, drives, starts)
    closed = 0
    for k in range(200):
        try:
            ref, _, res = solve_passive(mech.model, mech.data, loops, drives[k], starts[k])
        except SolverError:  # drives the loops cannot close near this start
            continue
        closed += 1
        assert norms[k] < TOL and res < RESIDUAL_TOL
        np.testing.assert_allclose(q[k], ref, rtol=0, atol=1e-9)
    assert closed >= 150


def test_assembly_mode_counts_closed_form_vs_multistart(m3, g3):
    rng = np.random.default_rng(2)
    counts = []
    for pose in random_poses(g3, 12, seed=9):
        qd = p3.inverse_position(g3, pose)[0][int(rng.integers(8))]
        closed = direct_position(m3, qd, all_modes=True)
        multi = direct_position_multistart(m3, qd, n_starts=64, seed=1)
        assert closed.count == multi.count
        assert closed.count <= 6 and closed.count % 2 == 0
        for s in closed.solutions:
            assert s.residual < TOL
            assert any(np.max(np.abs(s.q - t.q)) < 1e-7 for t in multi.solutions)
        assert any(np.max(np.abs(s.output - pose)) < 1e-10 for s in closed.solutions)
        counts.append(closed.count)
    assert max(counts) >= 4  # several assembly modes do occur


def test_five_bar_modes(m5):
    g = fb.geometry(m5)
    p = np.array([0.03, 0.25])
    inv = inverse_position(m5, p)
    assert inv.count == 4
    for s in inv.solutions:
        d = direct_position(m5, s.q[m5.loops.drive_q], all_modes=True)
        assert d.count == 2 == len(fb.direct_position(g, s.q[m5.loops.drive_q]))
        assert direct_position_multistart(m5, s.q[m5.loops.drive_q], 32).count == 2
        assert all(x.residual < TOL for x in d.solutions)
        assert any(np.max(np.abs(x.output - p)) < 1e-12 for x in d.solutions)


def test_continuation_stays_on_one_branch(m3, g3):
    pose0 = np.array([0.0, 0.0, 0.0])
    q0 = inverse_position(m3, pose0).solutions[0].q
    qa0 = q0[m3.loops.drive_q]
    path = qa0 + np.linspace(0, 1, 60)[:, None] * np.array([0.25, -0.2, 0.15])
    qs = direct_position_path(m3, path, q0)
    for q in qs:
        assert np.linalg.norm(m3.closure_residual(q)) < TOL
    steps = np.max(np.abs(np.diff(np.unwrap(qs, axis=0), axis=0)), axis=1)
    assert np.max(steps) < 0.1  # continuous: no branch jump
    # same branch as the batched sweep warm-started from the previous pose
    tree = PlanarTree.from_mechanism(m3)
    q = q0[None].copy()
    for k, qa in enumerate(path):
        q, n = batch_solve_passive(m3, tree, qa[None], q)
        assert n[0] < TOL
        assert np.max(np.abs(np.angle(np.exp(1j * (q[0] - qs[k]))))) < 1e-9
