"""Velocity problem and singularities: Pinocchio A/B vs closed form F1..F3 vs screw route."""

from __future__ import annotations

import numpy as np
import pytest

import rcm_pin
from rcm_pin.analysis.loop_velocity import classify, passive_velocity, velocity_matrices
from rcm_pin.analysis.screws import screw_test
from rcm_pin.errors import SingularConfigurationError
from rcm_pin.mechanisms import five_bar as fb
from rcm_pin.mechanisms import planar_3rrr
from rcm_pin.mechanisms.planar_3rrr import closed_form as p3
from rcm_pin.mechanisms.planar_3rrr import workspace as ws
from rcm_pin.report.closed_loops import random_poses, singularity_agreement


@pytest.fixture(scope="module")
def g3(m3):
    return planar_3rrr.geometry(m3)


def test_output_velocities_pinocchio_vs_closed_form_and_fd(m3, g3):
    rng = np.random.default_rng(4)
    for pose in random_poses(g3, 200, seed=4):
        mode = int(rng.integers(8))
        qd = p3.inverse_position(g3, pose)[0][mode]
        q = p3.full_q(g3, pose, qd)
        a_cf, b_cf = p3.ab_matrices(g3, pose, qd)
        if np.linalg.cond(a_cf) > 1e6:
            continue
        rate = rng.normal(size=3)
        xdot_cf = -np.linalg.solve(a_cf, b_cf @ rate)
        xdot_pin = velocity_matrices(m3, q).output_jacobian() @ rate
        assert np.max(np.abs(xdot_pin - xdot_cf)) < 1e-9 * max(1.0, np.max(np.abs(xdot_cf)))
    # finite differences along the closed-loop motion, one pose
    v = passive_velocity(m3, q, rate)
    eps = 1e-6
    fd = (m3.output_value(q + eps * v) - m3.output_value(q - eps * v)) / (2 * eps)
    assert np.max(np.abs(fd - xdot_pin)) < 1e-8


def test_singular_sets_agree_on_random_and_curve_poses(m3):
    """10^3 random poses + points on type-1/type-2 curves: classifier = det A/B = screws."""
    res = singularity_agreement(m3, n_random=1000, n_curve=60, seed=1)
    assert res["random"]["poses"] == 1000
    assert res["random"]["disagree"] == 0
    assert res["random"]["type1"] == res["random"]["type2"] == 0
    assert res["type 2 curve"]["poses"] >= 40
    assert res["type 2 curve"]["type2"] == res["type 2 curve"]["poses"]
    assert res["type 2 curve"]["disagree"] == 0
    assert res["type 1 curve"]["type1"] == res["type 1 curve"]["poses"] == 60
    assert res["type 1 curve"]["disagree"] == 0


def test_type2_point_det_and_wrench_lines_concurrent(m3, g3):
    pose = ws.type2_points(g3, 0.0, 3, max_points=1)[0]
    qd = p3.inverse_position(g3, pose)[0][3]
    q = p3.full_q(g3, pose, qd)
    assert classify(m3, q).label == "type 2"
    st = screw_test(m3, q)
    assert st.type2 and not st.type1
    # the three force lines B_iC_i meet in one point (or are parallel): rank W·T = 2
    assert np.linalg.matrix_rank(st.W, 1e-9) == 2
    with pytest.raises(SingularConfigurationError, match="type-2 singularity"):
        velocity_matrices(m3, q).output_jacobian()


def test_five_bar_singular_point_both_routes():
    m5 = rcm_pin.load("five_bar")
    g = fb.geometry(m5)
    p = np.array([0.0, np.sqrt(0.2**2 - 0.15**2)])  # distal links aligned, elbows out
    qd = fb.inverse_position(g, p)[0][1]
    q = fb.full_q(g, p, qd)
    assert fb.type2_measure(g, p, qd) < 1e-15
    assert classify(m5, q).type2 and screw_test(m5, q).type2
    a_cf, b_cf = fb.ab_matrices(g, p, qd)
    assert abs(np.linalg.det(a_cf)) < 1e-15
    # extra drives are regular there
    assert fb.extra_type2_measure(g, p) > 0.5
    assert not classify(m5.with_drives(m5.loops.extra_drives), q).type2
