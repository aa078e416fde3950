"""The example-robot-data arms in the one Viewer: meshes found, bodies placed, HTML export."""

from __future__ import annotations

import base64
import re

import numpy as np
import pytest
import umsgpack
from conftest import random_q

import rcm_pin
from rcm_pin.viz import Viewer


def _commands(html: str) -> list[dict]:
    blobs = re.findall(r"data:application/octet-binary;base64,([A-Za-z0-9+/=]+)", html)
    return [umsgpack.unpackb(base64.b64decode(b)) for b in blobs]


@pytest.fixture(scope="module", params=["panda", "ur5"])
def arm(request):
    mech = rcm_pin.load(request.param)
    with Viewer(mech) as viewer:
        yield viewer


def test_scene_has_the_meshes_at_home(arm):
    mech = arm.mech
    assert arm.viz.visual_model.ngeoms >= 7  # one mesh per link at least
    assert np.array_equal(arm.q, mech.home)
    assert arm.assembly == "home" and arm.closure_gap() == 0.0 and mech.rcm is None
    tree = arm.vis.window.tree["meshcat"]
    assert tree["overlays"]["output"].object is not None  # the tool point marker
    assert "rcm" not in tree["overlays"] and "tool_axis" not in tree["overlays"]


def test_bodies_placed_by_the_frames(arm):
    """Every visual node where its parent frame (rcm_pin.frame_pose) puts it."""
    mech = arm.mech
    q = random_q(mech, 1, np.random.default_rng(4))[0]
    arm.display(q)
    tree = arm.vis.window.tree["meshcat"]["pinocchio"]["visuals"]
    placements = arm.placements(q)
    for obj in arm.viz.visual_model.geometryObjects:
        node = next(n for n in placements if n.endswith("/" + obj.name))
        frame = mech.model.frames[obj.parentFrame]  # obj.placement is on the parent joint
        oMf = rcm_pin.frame_pose(mech, q, int(obj.parentFrame))
        T = oMf @ (frame.placement.inverse() * obj.placement).homogeneous
        assert np.allclose(placements[node], T, atol=1e-12), obj.name
        sent = np.array(umsgpack.unpackb(tree[obj.name].transform)["matrix"]).reshape(4, 4).T
        assert np.allclose(sent, T, atol=1e-6), obj.name
    tool = rcm_pin.tool_pose(mech, q)[:3, 3]
    marker = arm.vis.window.tree["meshcat"]["overlays"]["output"].transform
    assert np.allclose(np.reshape(umsgpack.unpackb(marker)["matrix"], (4, 4)).T[:3, 3], tool,
                       atol=1e-6)  # fmt: skip


def test_static_html_and_animation(arm, tmp_path):
    mech = arm.mech
    traj = np.linspace(arm.q, random_q(mech, 1, np.random.default_rng(5))[0], 4)
    anim = arm.animate(traj, 0.1)
    assert len(anim.clips) == len(arm.placements(traj[0])) + 1  # bodies and the tool point
    html = arm.save_html(tmp_path / f"{mech.name}.html").read_text()
    cmds = _commands(html)
    meshes = [c for c in cmds if c["type"] == "set_object" and "/pinocchio/visuals/" in c["path"]]
    assert len(meshes) == arm.viz.visual_model.ngeoms
    # mesh data embedded in the page (a mesh file object, or buffer geometries)
    assert all(c["object"]["geometries"] or c["object"]["object"]["data"] for c in meshes)
    assert "set_animation" in {c["type"] for c in cmds}
    eye, target = arm.camera
    pix = arm.project(np.array([T[:3, 3] for T in arm.placements(arm.q).values()]))
    assert np.all((pix > 0) & (pix < [800, 600])) and np.linalg.norm(eye - target) > 0.5
