"""The one circle–circle intersection (rcm_pin.geometry) and the order of its two points in
every closed form that uses it: the point left of the line between the centres first."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import EXACT

import rcm_pin
from rcm_pin.geometry import circle_intersections, circle_offsets, circle_points
from rcm_pin.linkage.fourbar import crank_angles, crank_point, rocker_angles, rocker_point
from rcm_pin.mechanisms import five_bar
from rcm_pin.mechanisms import four_bar as fb
from rcm_pin.mechanisms.eye_4dof.closed_form import pitch_cranks
from rcm_pin.mechanisms.eye_4dof.family import gaze_range
from rcm_pin.mechanisms.eye_4dof.family import geometry as eye_geometry


def side(c0, c1, p) -> float:
    """> 0 when p is left of the line c0 → c1 (counter-clockwise side)."""
    u, w = np.asarray(c1) - np.asarray(c0), np.asarray(p) - np.asarray(c0)
    return float(u[0] * w[1] - u[1] * w[0])


def test_points_on_both_circles_left_one_first_and_broadcast():
    rng = np.random.default_rng(3)
    c0, c1 = rng.normal(size=(200, 2)), rng.normal(size=(200, 2))
    d = np.linalg.norm(c1 - c0, axis=1)
    r0 = rng.uniform(0.2, 1.5, 200) * d
    r1 = rng.uniform(0.2, 1.5, 200) * d
    pts = circle_intersections(c0, r0, c1, r1)
    meet = (d <= r0 + r1) & (d >= np.abs(r0 - r1))
    assert 50 < meet.sum() < 200  # both cases are drawn
    assert np.isnan(pts[~meet]).all()
    for k in np.flatnonzero(meet):
        left, right = pts[k]
        for p in (left, right):
            assert abs(np.linalg.norm(p - c0[k]) - r0[k]) < EXACT * (1 + r0[k])
            assert abs(np.linalg.norm(p - c1[k]) - r1[k]) < EXACT * (1 + r1[k])
        assert side(c0[k], c1[k], left) >= 0.0 >= side(c0[k], c1[k], right)
        listed = circle_points(c0[k], r0[k], c1[k], r1[k])
        np.testing.assert_array_equal(np.array(listed), pts[k])


def test_touching_concentric_and_apart():
    assert len(circle_points((0.0, 0.0), 1.0, (3.0, 0.0), 2.0)) == 1  # touching outside
    assert len(circle_points((0.0, 0.0), 3.0, (1.0, 0.0), 2.0)) == 1  # touching inside
    np.testing.assert_array_equal(circle_points((0.0, 0.0), 1.0, (3.0, 0.0), 2.0)[0], [1.0, 0.0])
    assert circle_points((1.0, 1.0), 1.0, (1.0, 1.0), 1.0) == []  # concentric
    assert circle_points((0.0, 0.0), 1.0, (3.5, 0.0), 2.0) == []  # apart
    assert circle_points((0.0, 0.0), 3.0, (0.5, 0.0), 2.0) == []  # one inside the other
    a, h = circle_offsets(np.array([2.0, 9.0]), 1.5, 1.5)
    assert a[0] == 1.0 and abs(h[0] - math.sqrt(1.25)) < EXACT and np.isnan([a[1], h[1]]).all()


@pytest.fixture(scope="module")
def four_bar():
    return fb.geometry(rcm_pin.load("four_bar"))


def test_four_bar_direct_has_b_left_of_a_to_o2_first(four_bar):
    g, o2 = four_bar, np.array([four_bar.l0, 0.0])
    for theta in np.linspace(-np.pi, np.pi, 37):
        a = crank_point(g, theta)
        first, second = (rocker_point(g, psi) for psi in rocker_angles(g, theta))
        assert side(a, o2, first) > 0.0 > side(a, o2, second)


def test_four_bar_inverse_has_a_left_of_o1_to_b_first(four_bar):
    g = four_bar
    lo, hi = fb.rocker_range(g)
    for psi in np.linspace(lo, hi, 25)[1:-1]:
        b = rocker_point(g, psi)
        first, second = (crank_point(g, t) for t in crank_angles(g, psi))
        assert side((0.0, 0.0), b, first) > 0.0 > side((0.0, 0.0), b, second)


def test_five_bar_direct_has_p_left_of_b1_to_b2_first():
    g = five_bar.geometry(rcm_pin.load("five_bar"))
    rng = np.random.default_rng(5)
    seen = 0
    for q in rng.uniform(-np.pi, np.pi, (60, 2)):
        pts = five_bar.direct_position(g, q)
        if len(pts) == 2:
            bb = g.elbows(q)
            assert side(bb[0], bb[1], pts[0]) > 0.0 > side(bb[0], bb[1], pts[1])
            np.testing.assert_allclose(np.linalg.norm(pts - bb[0], axis=1), g.l2[0], atol=EXACT)
            np.testing.assert_allclose(np.linalg.norm(pts - bb[1], axis=1), g.l2[1], atol=EXACT)
            seen += 1
    assert seen > 10


def test_eye_pitch_cranks_have_a_left_of_o1_to_b_first_and_stay_continuous():
    """The eye's θ1 is ∠B ± δ, not wrapped: the ``+`` mode passes π without a jump."""
    g = eye_geometry(rcm_pin.load("eye_4dof"))
    (lo, hi), _ = gaze_range(g)
    elevations = np.linspace(lo, hi, 201)[1:-1]
    cranks = np.array([pitch_cranks(g, e) for e in elevations])
    for e, (t_plus, t_minus) in zip(elevations, cranks, strict=True):
        b = rocker_point(g.pitch, e + math.pi / 2)
        first, second = (crank_point(g.pitch, t) for t in (t_plus, t_minus))
        assert side((0.0, 0.0), b, first) > 0.0 > side((0.0, 0.0), b, second)
        # the same two angles as the four-bar's working modes, up to whole turns
        for t, u in zip((t_plus, t_minus), crank_angles(g.pitch, e + math.pi / 2), strict=True):
            assert abs(math.remainder(t - u, 2.0 * math.pi)) < EXACT
    assert cranks[:, 0].max() > math.pi  # the + mode crosses π here ...
    assert np.abs(np.diff(cranks, axis=0)).max() < 0.2  # ... continuously
