"""The planar 3-RRR's reachability test equals the reach mask of the full inverse problem."""

from __future__ import annotations

import numpy as np
import pytest

import rcm_pin
from rcm_pin.mechanisms.planar_3rrr import closed_form as p3
from rcm_pin.mechanisms.planar_3rrr import geometry
from rcm_pin.mechanisms.planar_3rrr.workspace import Grid


@pytest.mark.parametrize("args", [{}, {"proximal_2": "0.15", "distal_3": "0.3"}])
def test_reachable_equals_the_inverse_problems_mask(args):
    g = geometry(rcm_pin.load("planar_3rrr", **args))
    grid = Grid.around(g, 121)
    for phi in np.random.default_rng(4).uniform(-np.pi, np.pi, 12):
        poses = grid.poses(float(phi))
        np.testing.assert_array_equal(p3.reachable(g, poses), p3.inverse_position(g, poses)[1])
