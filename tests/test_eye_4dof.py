"""The whole eye linkage ``eye_4dof`` (issue 15 point 3): closures, gaze, mobility, inverse.

Routes: the Pinocchio closures solved numerically (Newton from perturbed seeds, continuation
along drive paths) against the closed forms of each sub-linkage written in
rcm_pin.linkage (pitch four-bar) and here (the yaw yoke l4 sin α = l10 sin θ2, the
parallelogram, the paper's slot chain from rcm_pin.mechanisms.eye_4dof.design).
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from conftest import EXACT

import rcm_pin
from rcm_pin.analysis.capabilities import position_solver
from rcm_pin.analysis.closed_position import direct_position_path, solve_drives
from rcm_pin.analysis.mobility import mobility
from rcm_pin.errors import UnreachablePoseError
from rcm_pin.linkage.fourbar import rocker_angle
from rcm_pin.mechanisms.eye_4dof import design as dz
from rcm_pin.mechanisms.eye_4dof.closed_form import gaze_angles
from rcm_pin.mechanisms.eye_4dof.family import gaze_range, geometry, outputs
from rcm_pin.model.newton import constraint_rank
from rcm_pin.rotations import rot_x, rot_y, rot_z

#: Gaze outputs against the closed forms: Newton stops at a closure residual < 1e-13 m,
#: which moves an angle by at most ~1e-13 m / 0.035 m (the shortest arm) ≈ 3e-12 rad.
GAZE = 1e-10


@pytest.fixture(scope="module")
def eye():
    return rcm_pin.load("eye_4dof")


def frame_rotation(m, q, frame):
    pin.framesForwardKinematics(m.model, m.data, q)
    return m.data.oMf[m.frame_id(frame)].rotation.copy()


def closed_forms(g, drives):
    """(e, α) from the sub-linkages' own formulas."""
    e = float(rocker_angle(g.pitch, np.array(drives[0]))) - math.pi / 2
    return e, math.asin(g.l10 * math.sin(drives[1]) / g.l4)


def check_outputs(m, g, q, drives):
    e, alpha = closed_forms(g, drives)
    out = outputs(m, q)
    expected = [e, alpha, e, alpha, drives[2], math.remainder(drives[3], 2 * math.pi)]
    got = [out[k] for k in ("elevation_1", "azimuth_1", "elevation_2", "azimuth_2", "lid", "roll")]
    np.testing.assert_allclose(got, expected, rtol=0, atol=GAZE)
    for frame in ("eye_1", "eye_2", "camera_2"):
        ge, ga, gr = gaze_angles(frame_rotation(m, q, frame))
        np.testing.assert_allclose([ge, ga], [e, alpha], rtol=0, atol=GAZE)
        if frame == "camera_2":
            assert abs(math.remainder(gr - drives[3], 2 * math.pi)) < GAZE
    lid = frame_rotation(m, q, "lid_arm")  # Ry(λ)
    assert abs(math.atan2(lid[0, 2], lid[0, 0]) - drives[2]) < GAZE


def test_numeric_closures_reproduce_every_sub_linkage(eye):
    """Newton on Pinocchio's closures from seeds 0.05 rad / 5 mm off the closed form."""
    g, rng = geometry(eye), np.random.default_rng(1)
    for _ in range(40):
        drives = rng.uniform([-np.pi, -np.pi, -1.0, -np.pi], [np.pi, np.pi, 1.0, np.pi])
        q_cf = position_solver(eye).direct(eye, drives).seeds[0]
        assert np.abs(eye.closure_residual(q_cf)).max() <= EXACT
        q, _, res = solve_drives(eye, drives, q_cf + rng.normal(0.0, 0.05, eye.nq) * 0.1)
        assert res <= EXACT and np.abs(eye.closure_residual(q)).max() <= EXACT
        check_outputs(eye, g, q, drives)


def test_continuation_through_the_motion_keeps_the_loops_closed(eye):
    """Both cranks turn fully (the pitch one twice as fast): continuation on Pinocchio."""
    g = geometry(eye)
    t = np.linspace(0.0, 1.0, 241)
    path = np.column_stack(
        [4 * np.pi * t, 2 * np.pi * t, 0.5 * np.sin(2 * np.pi * t), np.pi * np.sin(4 * np.pi * t)]
    )
    qs = direct_position_path(eye, path, eye.home)
    worst = max(np.abs(eye.closure_residual(q)).max() for q in qs)
    assert worst <= EXACT
    for q, drives in zip(qs[::8], path[::8], strict=True):
        check_outputs(eye, g, q, drives)


def test_slot_coordinate_is_the_papers_dimension_chain(eye):
    """Pair E's value equals the chain (9)/(10) generalised (design.slot_coordinate) with
    the cradle turned β = φ − e from the up pose."""
    g, rng = geometry(eye), np.random.default_rng(2)
    d = dz.EyeDesign(l4=g.l4, l44=g.l44, yaw_built=math.asin(g.l10 / g.l4), l00=g.l00,
                     up=g.up)  # fmt: skip
    e_index = eye.model.joints[eye.model.getJointId("E")].idx_q
    for _ in range(30):
        drives = np.r_[rng.uniform(-np.pi, np.pi, 2), 0.0, 0.0]
        q = position_solver(eye).direct(eye, drives).seeds[0]
        e, _ = closed_forms(g, drives)
        s = dz.slot_coordinate(d, np.array(g.up - e), np.array(drives[1]))
        assert abs(q[e_index] - float(s)) < EXACT


def test_mobility_from_the_rank_and_the_redundant_constraints(eye):
    """12 tree joints, 9 kept closure rows of rank 8: mobility 4 (four drives). One kept row
    is redundant: the pair K (points K, K') and the planar group E, F, U never rotate the
    finger about the pitch-plane normal independently. The spatial formula counts each point
    closure as a spherical pair and gives 0 (4 = 3 dropped planar rows + 1 dependent row)."""
    rng = np.random.default_rng(3)
    count = mobility(eye)
    assert count.rank_mobility == 4 and count.W == 0 and count.redundant == 4
    for _ in range(5):
        q = position_solver(eye).direct(eye, rng.uniform(-3, 3, 4)).seeds[0]
        jac = eye.residual_and_jacobian(q)[1]
        assert jac.shape == (9, 12) and constraint_rank(jac) == 8


def test_inverse_every_mode_reaches_the_target(eye):
    g, rng = geometry(eye), np.random.default_rng(4)
    (lo, hi), amax = gaze_range(g)
    for _ in range(10):
        e, a, r = rng.uniform(lo, hi), rng.uniform(-amax, amax), rng.uniform(-3, 3)
        target = rot_y(-e) @ rot_z(a) @ rot_x(r)
        res = rcm_pin.inverse(eye, target)
        assert res.count == 4
        for sol in res.solutions:
            rot = frame_rotation(eye, eye.to_pin(sol.q), "camera_2")
            np.testing.assert_allclose(rot, target, rtol=0, atol=GAZE)
            assert np.abs(eye.closure_residual(eye.to_pin(sol.q))).max() <= EXACT


def test_unreachable_gaze(eye):
    g = geometry(eye)
    (lo, hi), amax = gaze_range(g)
    with pytest.raises(UnreachablePoseError) as e:
        rcm_pin.inverse(eye, rot_z(math.radians(60)))
    assert str(e.value) == (
        f"eye_4dof: gaze elevation 0 deg, azimuth 60 deg is not reachable; valid: elevation "
        f"in [{math.degrees(lo):.6g}, {math.degrees(hi):.6g}] deg, |azimuth| <= "
        f"{math.degrees(amax):.6g} deg"
    )
    assert math.degrees(amax) == pytest.approx(50.0, abs=1e-9)  # l10 = l4 sin 50°
