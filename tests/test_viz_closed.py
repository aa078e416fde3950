"""Closed mechanisms in the one Viewer: shown assembled (passive joints solved), exported."""

from __future__ import annotations

import base64
import json
import re

import numpy as np
import pinocchio as pin
import pytest
import umsgpack

import rcm_pin
from rcm_pin.analysis.closed_position import direct_position_path
from rcm_pin.cli import main
from rcm_pin.errors import InvalidInputError
from rcm_pin.model.constraints import plane_normal
from rcm_pin.viz import Viewer
from rcm_pin.viz.snapshot import snapshot


def _commands(html: str) -> list[dict]:
    blobs = re.findall(r"data:application/octet-binary;base64,([A-Za-z0-9+/=]+)", html)
    return [umsgpack.unpackb(base64.b64decode(b)) for b in blobs]


#: Drives with two assembly modes each [rad].
DRIVES = {"planar_3rrr": [-0.2059, -2.481, 1.671], "five_bar": [2.365, 0.7762], "four_bar": [0.3]}


@pytest.fixture(scope="module", params=list(DRIVES))
def mech(request):
    return rcm_pin.load(request.param)


def test_display_closes_the_loops(mech):
    drives = np.array(DRIVES[mech.name])
    with Viewer(mech) as viewer:
        assert viewer.assembly == "home" and viewer.closure_gap() < 1e-12  # home is closed
        home = mech.home
        assert np.array_equal(viewer.q, home)
        for assembly in range(2):
            q = viewer.display_inputs(drives, assembly)
            assert np.allclose(q[mech.loops.drive_q], drives)
            assert np.allclose(viewer.inputs, drives) and viewer.assembly == f"assembly_{assembly}"
            # the cut frames coincide in the placements Pinocchio's visualizer displayed
            assert viewer.closure_gap() < 1e-12
            for a, b in viewer.cut_frames():
                assert np.linalg.norm(a - b) < 1e-12
        # the open tree at the same drives with passive joints at zero does not close
        open_q = np.zeros(mech.nq)
        open_q[mech.loops.drive_q] = drives
        viewer.display(open_q)
        assert viewer.closure_gap() > 1e-3


def test_html_contains_the_bodies_at_the_displayed_placements(mech, tmp_path):
    with Viewer(mech) as viewer:
        q = viewer.display_inputs(np.array(DRIVES[mech.name]))
        html = viewer.save_html(tmp_path / "scene.html").read_text()
        expected = viewer.placements(q)
        markers = {
            name: viewer.vis.window.tree["meshcat"]["overlays"][name]
            for name in ("cut_0_a", "cut_0_b", "output")
        }
    cmds = _commands(html)
    objects = {c["path"] for c in cmds if c["type"] == "set_object"}
    transforms = {c["path"]: c["matrix"] for c in cmds if c["type"] == "set_transform"}
    links = {f.name for f in mech.model.frames if f.type == pin.FrameType.BODY}
    assert len(expected) >= mech.model.njoints - 1
    for node, T in expected.items():
        path = f"/meshcat/{node}"
        assert path in objects, path
        assert any(node.startswith(f"pinocchio/visuals/{lk}") for lk in links), node
        shown = np.array(transforms[path], dtype=float).reshape(4, 4).T
        assert np.allclose(shown, T, atol=1e-6)  # float32 in the msgpack
    assert {"/meshcat/overlays/cut_0_a", "/meshcat/overlays/output"} <= objects
    # the markers sit at the cut point and the output frame (second route: frame_pose)
    a = rcm_pin.frame_pose(mech, q, mech.loops.closures[0].frame_a)[:3, 3]
    out = rcm_pin.frame_pose(mech, q)[:3, 3]
    for name, p in (("cut_0_a", a), ("cut_0_b", a), ("output", out)):
        sent = np.array(umsgpack.unpackb(markers[name].transform)["matrix"]).reshape(4, 4).T
        assert np.allclose(sent[:3, 3], p, atol=1e-6), name


def test_camera_looks_from_above_the_plane(mech):
    n = plane_normal(mech.model)
    assert n is not None
    with Viewer(mech) as viewer:
        eye, target = viewer.camera
        d = (eye - target) / np.linalg.norm(eye - target)
        assert abs(d @ n) > 0.75  # mostly along the plane normal
        # every joint origin in the picture
        data = mech.model.createData()
        pin.forwardKinematics(mech.model, data, viewer.q)
        pix = viewer.project(np.array([M.translation for M in data.oMi]))
        assert np.all((pix > 0) & (pix < [800, 600]))


def test_animation_and_errors(mech):
    drives = np.array(DRIVES[mech.name])
    with Viewer(mech) as viewer:
        q0 = viewer.display_inputs(drives)
        rows = drives + np.linspace(0, 0.05, 5)[:, None]
        path = viewer.input_path(rows)
        assert np.allclose(path, direct_position_path(mech, rows, q0))
        assert max(np.abs(mech.closure_residual(q)).max() for q in path) < 1e-12
        anim = viewer.animate(path, 0.1)
        assert len(anim.clips) == len(viewer.placements(q0)) + 2 * len(mech.loops.closures) + 1
        assert "set_animation" in {c["type"] for c in _commands(viewer.static_html())}
        with pytest.raises(InvalidInputError, match=r"^trajectory has shape \(3,\); valid"):
            viewer.animate(np.zeros(3))
        with pytest.raises(InvalidInputError, match=r"^assembly 5 out of range; valid: 0\.\.1 "):
            viewer.display_inputs(drives, 5)
        with pytest.raises(InvalidInputError, match=r"^drives has shape"):
            viewer.display_inputs(np.zeros(len(drives) + 1))


def test_png_fallback(tmp_path):
    mech = rcm_pin.load("five_bar")
    png = tmp_path / "f.png"
    assert snapshot(mech, None, png, browser=False) == "matplotlib"
    assert png.stat().st_size > 5000


def test_cli_view_closed_drives_traj_and_assembly(tmp_path, capsys):
    traj = tmp_path / "drives.csv"
    np.savetxt(traj, np.array(DRIVES["planar_3rrr"]) + np.linspace(0, 0.05, 4)[:, None],
               delimiter=",")  # fmt: skip
    html = tmp_path / "v.html"
    argv = ["view", "planar_3rrr", "--q=-0.2059,-2.481,1.671", "--assembly", "1"]
    assert main([*argv, "--traj", str(traj), "--html", str(html), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["input_names"] == ["A1", "A2", "A3"] and out["assembly"] == "assembly_1"
    assert np.allclose(out["q"], DRIVES["planar_3rrr"]) and len(out["q_full"]) == 7
    assert out["closure_gap"] < 1e-12 and len(out["joint_names"]) == 7
    assert "set_animation" in str(_commands(html.read_text()))
    assert main(["view", "four_bar", "--assembly", "1", "--html", str(html), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["assembly"] == "assembly_1" and out["closure_gap"] < 1e-12
