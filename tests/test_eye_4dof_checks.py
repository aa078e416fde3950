"""Design checks of the eye linkage (issue 15 point 4): interference, gaze range, Listing.

Routes: coal distances of the GeometryModel against a hand check (a box pair placed here),
the deliberately lengthened yaw crank; Listing's roll from the half-angle formula against
the Listing rotation built from its axis; the gaze range against the four-bar dead centres.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from conftest import EXACT

import rcm_pin
from rcm_pin.linkage.fourbar import performance
from rcm_pin.mechanisms.eye_4dof.checks import (
    geometry_model,
    interference,
    listing_roll,
    listing_roll_from_rotation,
)
from rcm_pin.mechanisms.eye_4dof.closed_form import gaze_angles
from rcm_pin.mechanisms.eye_4dof.family import gaze_range, geometry
from rcm_pin.rotations import rot_x, rot_y, rot_z


@pytest.fixture(scope="module")
def eye():
    return rcm_pin.load("eye_4dof")


def test_default_design_is_free_of_interference(eye):
    c = interference(eye, 9)
    pair, clearance, _ = c.worst
    assert c.colliding() == [] and clearance > 0.005
    assert c.map.shape == (9, 9) and np.all(np.isfinite(c.map))
    assert len(c.pairs) == len(set(c.pairs)) > 50


def test_a_lengthened_yaw_crank_hits_the_assur_group_and_is_named():
    """l10 from 26.8 mm to 34 mm (still < l4, the yoke still closes)."""
    c = interference(rcm_pin.load("eye_4dof", l10=0.034), 9)
    assert ("crank2", "link8") in c.colliding()
    pair, clearance, where = c.worst
    assert pair[0] == "crank2" and clearance < 0.0 and where.shape == (2,)


def test_coal_distance_of_one_pair_equals_a_hand_computation(eye):
    """lid arm (box w/2 × CL × w/2 at radius lid_arm about Y) and camera block (2w × w × w/2
    at the eye-2 centre) at straight gaze, lid at 0: the boxes are axis-aligned, so the gap
    along X is lid_arm − w/4 − 2w [m] (w = 6 mm)."""
    gm, pairs = geometry_model(eye)
    gd = pin.GeometryData(gm)
    q = eye.configurations["straight"]
    pin.computeDistances(eye.model, eye.data, gm, gd, q)
    names = [(gm.geometryObjects[i].name, gm.geometryObjects[k].name) for i, k in pairs]
    d = gd.distanceResults[names.index(("lid_arm_0", "camera_2_0"))].min_distance
    assert d == pytest.approx(0.065 - 0.006 / 4 - 2 * 0.006, abs=1e-9)


def test_gaze_range_of_the_built_linkage(eye):
    """Elevation from the pitch four-bar's dead centres, azimuth asin(l10 / l4) = 50°."""
    g = geometry(eye)
    (lo, hi), amax = gaze_range(g)
    p = performance(g.pitch)
    np.testing.assert_allclose([hi, -lo], [p.up, p.down], rtol=0, atol=EXACT)
    np.testing.assert_allclose(math.degrees(amax), 50.0, rtol=0, atol=1e-9)


def test_listing_roll_two_routes_and_the_law():
    rng = np.random.default_rng(5)
    for e, a in rng.uniform(-0.8, 0.8, (50, 2)):
        rho = listing_roll(e, a)
        assert abs(rho - listing_roll_from_rotation(e, a)) < EXACT
        # the rotation with this roll has its axis in the frontal plane (x component 0)
        axis = pin.log3(rot_y(-e) @ rot_z(a) @ rot_x(rho))
        assert abs(axis[0]) < EXACT
        ge, ga, gr = gaze_angles(rot_y(-e) @ rot_z(a) @ rot_x(rho))
        np.testing.assert_allclose([ge, ga, gr], [e, a, rho], rtol=0, atol=EXACT)
    assert listing_roll(0.3, 0.0) == 0.0 and listing_roll(0.0, 0.4) == 0.0
