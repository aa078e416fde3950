"""Every joint axis passes through the visuals of both bodies it joins (issue 29 item 4):
the numeric check (rcm_pin.analysis.axis_visuals) over the catalogue at the home pose, and the
line–solid distances it rests on (rcm_pin.model.line_distance) on hand-made cases."""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from functools import cache

import coal
import numpy as np
import pytest
from conftest import EXACT, SOLVER
from hypothesis import given, settings
from hypothesis import strategies as st

import rcm_pin
from rcm_pin.analysis.axis_visuals import MOVING, AxisMiss, _cut_axes, axis_misses, shape_miss
from rcm_pin.catalog import mechanisms
from rcm_pin.catalog.loading import from_urdf
from rcm_pin.errors import InvalidInputError
from rcm_pin.model.line_distance import (
    line_box,
    line_cylinder,
    line_sphere,
    line_triangles,
    point_line_distance,
)
from rcm_pin.viz.triangles import box

#: Rows of descriptions rcm-pin does not ship (example-robot-data), with the reason.
VENDOR = {
    ("panda", "panda_finger_joint1", "child"): "the vendor's finger mesh is beside its slide",
    ("panda", "panda_finger_joint2", "child"): "the vendor's finger mesh is beside its slide",
}


@cache
def rows_of(name: str) -> tuple[AxisMiss, ...]:
    return axis_misses(rcm_pin.load(name))


def _moving_joints(name: str) -> list[str]:
    entry = next(e for e in mechanisms() if e.name == name)
    root = ET.fromstring(entry.urdf_path.read_text())
    return [str(j.get("name")) for j in root.iter("joint") if j.get("type") in MOVING]


CASES = [
    pytest.param(e.name, joint, side, id=f"{e.name}-{joint}-{side}", marks=marks)
    for e in mechanisms()
    for joint in _moving_joints(e.name)
    for side in ("parent", "child")
    for marks in [
        [pytest.mark.skip(reason=VENDOR[(e.name, joint, side)])]
        if (e.name, joint, side) in VENDOR
        else []
    ]
]


@pytest.mark.parametrize(("name", "joint", "side"), CASES)
def test_every_joint_axis_passes_through_both_bodies(name, joint, side):
    rows = [r for r in rows_of(name) if r.joint == joint and r.side == side]
    assert len(rows) == 1
    assert rows[0].miss <= SOLVER, f"{joint} misses {rows[0].link} by {rows[0].miss * 1e3:.2f} mm"


CLOSED = [e.name for e in mechanisms() if e.kind == "closed"]


@pytest.mark.parametrize("name", CLOSED)
def test_every_cut_joint_passes_through_both_bodies(name):
    cuts = [r for r in rows_of(name) if "~" in r.joint]
    assert all(r.miss <= SOLVER for r in cuts), [r for r in cuts if r.miss > SOLVER]


@pytest.mark.parametrize(
    ("name", "cut", "present"),
    [
        ("four_bar", "coupler_tip~rocker_tip", True),  # the pin B: its axis is the normal
        ("eye_4dof", "finger_K~crank_K", True),  # the pin K, a spatial loop
        ("translational_3ppapa", "tip_2~platform_2", False),  # leg 2 fixed to the platform
    ],
)
def test_cut_joints_are_pins_and_welds_are_none(name, cut, present):
    sides = [r.side for r in rows_of(name) if r.joint == cut]
    assert sides == (["parent", "child"] if present else [])


Z = np.array([[0.0], [0.0], [2.0]])


@pytest.mark.parametrize(
    ("closed", "tree", "lines"),
    [
        (Z, np.eye(3), [(0, 0, 1)]),  # a pin: the loop turns the bodies about z only
        (np.eye(3)[:, :2], np.eye(3), list(map(tuple, np.eye(3)))),  # a ball: three lines
        (np.zeros((3, 1)), Z, [(0, 0, 1)]),  # turning alike here, the tree allows z only
        (np.zeros((3, 1)), np.eye(3), []),  # a weld: no relative rotation in the loop
    ],
)
def test_the_lines_of_a_cut_joint(closed, tree, lines):
    got = np.abs(np.array(_cut_axes(closed, tree))).reshape(-1, 3)  # a line has no sign
    np.testing.assert_allclose(got, np.array(lines).reshape(-1, 3), rtol=0, atol=EXACT)


ARM = """<robot name="arm">
  <link name="base"><visual><geometry><box size="0.2 0.2 0.2"/></geometry></visual></link>
  <link name="arm">
    <visual><origin xyz="0.3 0 0"/><geometry><box size="0.2 0.1 0.1"/></geometry></visual>
  </link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <link name="tool"/>
  <joint name="t" type="fixed"><parent link="arm"/><child link="tool"/></joint>
</robot>"""


def test_no_visual_geometry_misses_by_inf():
    """A body without visual geometry has nothing to pass through (the viewer draws rods
    between its joint origins): its rows miss by inf."""
    bare = re.sub(r"<visual>.*?</visual>", "", ARM, flags=re.S)
    rows = axis_misses(from_urdf(bare, tool_frame="tool"))
    assert [(r.side, r.miss) for r in rows] == [("parent", math.inf), ("child", math.inf)]


def test_a_joint_axis_beside_its_child_is_reported():
    """The arm's box (x in [0.2, 0.4]) misses the axis z through the origin by 0.2 m, at
    every angle; the base's box holds it."""
    mech = from_urdf(ARM, tool_frame="tool")
    for q in (0.0, 0.7):
        rows = axis_misses(mech, np.array([q]))
        assert rows[0] == AxisMiss("j", "parent", "base", 0.0)
        assert (rows[1].joint, rows[1].side, rows[1].link) == ("j", "child", "arm")
        assert rows[1].miss == pytest.approx(0.2, abs=EXACT)
        assert len(rows) == 2


def test_bad_coordinates_are_refused():
    mech = from_urdf(ARM, tool_frame="tool")
    with pytest.raises(InvalidInputError, match=r"^q has shape \(2,\); valid: \(1,\)"):
        axis_misses(mech, np.zeros(2))


# ---------------------------------------------------------------- line–solid distances
HALF = np.array([1.0, 2.0, 3.0])


@pytest.mark.parametrize(
    ("p", "d", "miss"),
    [
        ((0, 0, 0), (1, 0, 0), 0.0),  # through the centre
        ((5, 1.9, -2.9), (1, 0, 0), 0.0),  # through, near an edge
        ((0, 2, 0), (1, 0, 0), 0.0),  # along a face: touching counts
        ((0, 2.5, 0), (1, 0, 0), 0.5),  # parallel to a face
        ((0, 2 + 3, 3 + 4), (1, 0, 0), 5.0),  # parallel to an edge (3-4-5)
        ((0, 0, 3 + 2), (1, 1, 0), 2.0),  # skew, over the top face
        ((1 + 1, 2 + 1, 0), (1, -1, 0), math.sqrt(2)),  # skew, past the edge at (1, 2)
        ((3, 3, 3), (-1, -1, -1), 0.0),  # the diagonal
    ],
)
def test_line_box(p, d, miss):
    assert line_box(p, d, HALF) == pytest.approx(miss, abs=EXACT)


@pytest.mark.parametrize(
    ("p", "d", "miss"),
    [
        ((0, 0, 0), (0, 0, 1), 0.0),  # the cylinder's axis
        ((0.5, 0, 0), (0, 1, 0), 0.0),  # across, through the side
        ((0, 0, 2), (1, 0, 0), 0.0),  # across the cap: touching
        ((3, 0, 0), (0, 0, 1), 2.0),  # parallel to the axis
        ((0, 0, 2 + 3), (1, 0, 0), 3.0),  # over the cap
        ((0, 0, 2 + 3), (1, 1, 0), 3.0),  # over the cap, another direction
        ((1 + 3, 0, 2 + 4), (0, 1, 0), 5.0),  # past the rim (3-4-5)
        ((0, 4, 0), (1, 0, 1), 3.0),  # skew, beside the side
    ],
)
def test_line_cylinder(p, d, miss):
    assert line_cylinder(p, d, 1.0, 2.0) == pytest.approx(miss, abs=EXACT)


@pytest.mark.parametrize(
    ("p", "d", "miss"),
    [((0, 0.5, 0), (1, 0, 0), 0.0), ((0, 1, 0), (1, 0, 0), 0.0), ((0, 3, 4), (1, 0, 0), 4.0)],
)
def test_line_sphere(p, d, miss):
    assert line_sphere(p, d, 1.0) == pytest.approx(miss, abs=EXACT)


@pytest.mark.parametrize(
    ("c", "p", "d", "distance"),
    [((0, 0, 0), (0, 3, 4), (1, 0, 0), 5.0), ((1, 1, 1), (0, 0, 0), (2, 2, 2), 0.0)],
)
def test_point_line_distance(c, p, d, distance):
    assert point_line_distance(c, p, d) == pytest.approx(distance, abs=EXACT)


coords = st.floats(-5.0, 5.0, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(st.tuples(coords, coords, coords), st.tuples(coords, coords, coords))
def test_a_box_mesh_gives_the_box_distance(p, d):
    """A box's triangles are its surface: a line misses the mesh as it misses the solid."""
    if np.linalg.norm(d) < 1e-3:
        d = (1.0, 0.0, 0.0)
    v, f = box(HALF)
    assert line_triangles(p, d, v, f) == pytest.approx(line_box(p, d, HALF), abs=EXACT)


@settings(max_examples=200, deadline=None)
@given(st.tuples(coords, coords, coords), st.tuples(coords, coords, coords))
def test_the_cylinder_distance_is_the_smallest_over_the_line(p, d):
    """No point of the line is nearer the cylinder than the miss (the minimiser is exact to
    1e-12 m), and the miss is attained."""
    if np.linalg.norm(d) < 1e-3:
        d = (0.0, 0.0, 1.0)
    miss = line_cylinder(p, d, 1.0, 2.0)
    u = np.asarray(d) / np.linalg.norm(d)
    t0 = -float(np.asarray(p) @ u)
    ts = t0 + np.linspace(-20.0, 20.0, 4001)
    x = np.asarray(p) + ts[:, None] * u
    radial = np.maximum(np.hypot(x[:, 0], x[:, 1]) - 1.0, 0.0)
    gaps = np.hypot(radial, np.maximum(np.abs(x[:, 2]) - 2.0, 0.0))
    assert miss <= gaps.min() + EXACT
    assert miss >= gaps.min() - 0.005  # samples 0.01 apart, the gap's slope at most 1


def test_shapes_the_check_cannot_measure_are_refused():
    with pytest.raises(InvalidInputError) as err:
        shape_miss(coal.Capsule(1.0, 1.0), np.zeros(3), np.array([1.0, 0.0, 0.0]))
    assert str(err.value) == (
        "visual shape Capsule cannot be measured; valid: box, cylinder, sphere, mesh"
    )


def test_a_line_needs_a_direction():
    with pytest.raises(InvalidInputError) as err:
        line_box((0, 0, 0), (0, 0, 0), HALF)
    assert str(err.value) == "line direction [0.0, 0.0, 0.0] has zero length; valid: |d| > 0"
