"""Meshcat visualisation without a browser: geometry placement, scene, export, CLI, report."""

from __future__ import annotations

import base64
import json
import re
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import umsgpack
from conftest import EXACT, random_q

import rcm_pin
import rcm_pin.viz.snapshot as snap
from rcm_pin.cli import main
from rcm_pin.errors import InvalidInputError, SnapshotError, UnknownFrameError
from rcm_pin.viz import Viewer
from rcm_pin.viz.camera import frame_points, project
from rcm_pin.viz.drawing import fallback_png
from rcm_pin.viz.scene import SceneRecorder, colormap, hex_color
from rcm_pin.viz.snapshot import screenshot_html, snapshot

DATA = Path(__file__).parent / "data"
NO_RCM = "has no RCM frame; valid: a mechanism with a remote centre (rcm_*), or load(..., "


def _commands(html: str) -> list[dict]:
    """Decode the msgpack commands embedded in a static Meshcat page."""
    blobs = re.findall(r"data:application/octet-binary;base64,([A-Za-z0-9+/=]+)", html)
    return [umsgpack.unpackb(base64.b64decode(b)) for b in blobs]


def _sent(viewer: Viewer, path: str) -> np.ndarray:
    """The 4x4 transform last sent to a node of the in-memory scene."""
    node = viewer.vis.window.tree
    for part in path.split("/"):
        node = node[part]
    return np.array(umsgpack.unpackb(node.transform)["matrix"]).reshape(4, 4).T


def test_mimic_visuals_match_no_mimic_model(rcm_mech):
    """Visual geometry built on the mimic model sits where the no-mimic model puts it."""
    visual = pin.buildGeomFromUrdfString(rcm_mech.model, rcm_mech.urdf, pin.GeometryType.VISUAL)
    full = pin.buildGeomFromUrdfString(rcm_mech.model_full, rcm_mech.urdf, pin.GeometryType.VISUAL)
    assert visual.ngeoms == full.ngeoms > 10
    data, gdata = rcm_mech.model.createData(), visual.createData()
    fdata, gfdata = rcm_mech.model_full.createData(), full.createData()
    rng = np.random.default_rng(6)
    moved = 0.0
    for q in random_q(rcm_mech, 5, rng):
        q_pin = rcm_mech.to_pin(q)
        pin.forwardKinematics(rcm_mech.model, data, q_pin)
        pin.updateGeometryPlacements(rcm_mech.model, data, visual, gdata)
        pin.forwardKinematics(rcm_mech.model_full, fdata, rcm_mech.coupling.q_full(q_pin))
        pin.updateGeometryPlacements(rcm_mech.model_full, fdata, full, gfdata)
        for i, obj in enumerate(visual.geometryObjects):
            j = full.getGeometryId(obj.name)
            M, Mf = gdata.oMg[i].homogeneous, gfdata.oMg[j].homogeneous
            assert np.abs(M - Mf).max() < EXACT, obj.name
            moved = max(moved, np.abs(M - visual.geometryObjects[i].placement.homogeneous).max())
    assert moved > 0.01  # the configurations really move the bodies


def test_viewer_places_every_geometry_node(rcm_mech):
    viewer = Viewer(rcm_mech)
    q = random_q(rcm_mech, 1, np.random.default_rng(1))[0]
    viewer.display(q)
    assert viewer.url is None and isinstance(viewer.vis.window, SceneRecorder)
    tree = viewer.vis.window.tree["meshcat"]["pinocchio"]["visuals"]
    for name, T in viewer.placements(q).items():
        node = tree[name.split("/")[-1]]
        assert node.object is not None
        sent = np.array(umsgpack.unpackb(node.transform)["matrix"]).reshape(4, 4).T
        assert np.allclose(sent, T, atol=1e-6), name


def test_default_configuration_is_home(rcm_mech):
    viewer = Viewer(rcm_mech)
    home = rcm_mech.home
    assert np.array_equal(viewer.q, home) and viewer.assembly == "home"
    assert np.array_equal(viewer.inputs, viewer.q) and viewer.closure_gap() == 0.0
    plain = Viewer(rcm_pin.load(DATA / "mimic_tree.urdf", tool_frame="tool_link"))
    mech = plain.mech
    assert np.array_equal(plain.q, mech.home)  # the one default: mid-range of the limits
    bounded = np.isfinite(mech.lower)  # the continuous joint: unbounded, home 0
    expected = np.zeros(mech.nq)
    expected[bounded] = 0.5 * (mech.lower[bounded] + mech.upper[bounded])
    assert np.array_equal(mech.home, expected)


def test_tool_axis_passes_through_rcm_and_tool(rcm_mech):
    viewer = Viewer(rcm_mech)
    viewer.show_rcm()
    viewer.show_tool_axis()
    q = random_q(rcm_mech, 1, np.random.default_rng(2))[0]
    viewer.display(q)
    T = _sent(viewer, "meshcat/overlays/tool_axis")
    axis, centre = T[:3, 1], T[:3, 3]  # Meshcat cylinders lie along their y axis
    tool = rcm_pin.tool_pose(rcm_mech, q)[:3, 3]
    for point in (np.zeros(3), tool):  # A and the tool centre on the rod's line
        d = point - centre
        assert np.linalg.norm(d - (d @ axis) * axis) < 1e-9
    assert np.allclose(_sent(viewer, "meshcat/overlays/rcm")[:3, 3], 0.0, atol=1e-7)


def test_points_animation_and_static_html():
    mech = rcm_pin.load("rcm_bevel")
    viewer = Viewer(mech, snapshot_style=True)
    qs = random_q(mech, 50, np.random.default_rng(3))
    values = np.linspace(0.0, 1.0, 50)
    points = viewer.show_tool_positions("workspace", qs, values, size=0.003)
    assert points.shape == (50, 3)
    traj = np.linspace(mech.lower * 0.5, mech.upper * 0.5, 12)
    anim = viewer.animate(traj, dt=0.1)
    # every body, plus the two moving overlays (RCM sphere and tool-axis rod)
    assert len(anim.clips) == len(viewer.placements(traj[0])) + 2
    html = viewer.static_html(controls=False)
    assert "MeshCat.Viewer" in html and ".dg {display: none" in html
    commands = _commands(html)
    kinds = {c["type"] for c in commands}
    assert kinds == {"set_object", "set_transform", "set_property", "set_animation"}
    cloud = next(c for c in commands if c["path"].endswith("overlays/workspace"))
    assert cloud["object"]["object"]["type"] == "Points"
    (animation,) = [c for c in commands if c["type"] == "set_animation"]
    tracks = animation["animations"][0]["clip"]["tracks"]
    assert len(tracks[0]["keys"]) == 12 and animation["animations"][0]["clip"]["fps"] == 10
    camera = [c for c in commands if c["path"] == "/Cameras/default/rotated/<object>"]
    assert {c["property"] for c in camera} == {"fov", "position"}


def test_live_server_writes_the_same_page(tmp_path):
    """A real meshcat-server on 127.0.0.1 and the in-memory recorder agree."""
    mech = rcm_pin.load("rcm_bevel_4dof")
    q = np.array([0.2, -0.3, 0.08, 0.4])
    pages = []
    for server in (True, False):
        with Viewer(mech, server=server) as viewer:
            viewer.show_rcm()
            viewer.show_tool_axis()
            viewer.display(q)
            if server:
                assert viewer.url is not None and viewer.url.startswith("http://127.0.0.1:")
            pages.append(viewer.static_html())
            if server:
                proc = viewer.vis.window.server_proc
        if server:
            assert proc.poll() is not None  # close() stopped the server
    live, offline = (_commands(p) for p in pages)
    strip = [{k: v for k, v in c.items() if k != "object"} for c in live]
    assert strip == [{k: v for k, v in c.items() if k != "object"} for c in offline]
    assert len(pages[0]) == len(pages[1])


def test_camera_projection_and_framing():
    eye, target = frame_points(np.array([[0.0, 0, 0], [1.0, 1, 1]]))
    assert np.allclose(target, 0.5)
    px = project(eye, target, target)
    assert np.allclose(px, [[400, 300]])
    viewer = Viewer(rcm_pin.load("rcm_bevel"))
    corners = np.array([T[:3, 3] for T in viewer.placements(viewer.q).values()])
    pix = viewer.project(corners)
    assert np.all((pix > 0) & (pix < [800, 600]))


def test_colours():
    rgb = colormap(np.array([0.0, np.nan, 2.0]), "viridis")
    assert rgb.shape == (3, 3) and np.allclose(rgb[1], 0.5)
    assert hex_color((1.0, 0.5, 0.0)) == 0xFF8000 and hex_color(0x123456) == 0x123456


def test_errors_have_exact_messages():
    mech = rcm_pin.load("rcm_bevel")
    with pytest.raises(InvalidInputError) as exc:
        Viewer(mech, zmq_url="tcp://10.0.0.1:6000")
    assert str(exc.value) == "zmq_url 'tcp://10.0.0.1:6000' is not on this machine; " + (
        "valid: tcp://127.0.0.1:PORT"
    )
    viewer = Viewer(mech)
    with pytest.raises(InvalidInputError) as exc:
        viewer.show_points("p", np.zeros((4, 2)))
    assert str(exc.value) == "points have shape (4, 2); valid: (N, 3) finite values"
    with pytest.raises(InvalidInputError) as exc:
        viewer.show_points("p", np.zeros((4, 3)), values=np.zeros(3))
    assert str(exc.value) == "values have shape (3,); valid: (4,)"
    with pytest.raises(InvalidInputError) as exc:
        viewer.animate(np.zeros((3, 4)))
    assert str(exc.value) == "trajectory has shape (3, 4); valid: (N, 6) finite values"
    with pytest.raises(InvalidInputError) as exc:
        viewer.animate(np.zeros((3, 6)), dt=0.0)
    assert str(exc.value) == "dt = 0.0; valid: a positive time step [s]"
    with pytest.raises(InvalidInputError) as exc:
        viewer.display_inputs(np.zeros(6), assembly=1)
    assert str(exc.value) == (
        "assembly 1: rcm_bevel has no loop closures (its inputs give one configuration); valid: 0"
    )
    plain = Viewer(rcm_pin.load(DATA / "mimic_tree.urdf", tool_frame="tool_link"))
    with pytest.raises(InvalidInputError) as exc:
        plain.show_rcm()
    assert str(exc.value) == "mimic_tree " + NO_RCM + "rcm_frame=...)"
    with pytest.raises(InvalidInputError) as exc:
        plain.show_tool_axis()
    assert str(exc.value) == "mimic_tree " + NO_RCM + "rcm_frame=...)"
    with pytest.raises(UnknownFrameError):
        mech.frame_id("nope")


def test_snapshot_fallback_and_missing_chromium(tmp_path, monkeypatch):
    mech = rcm_pin.load("rcm_belt")
    q = np.array([0.3, 0.2, 0.08, 0.0, 0.0, 0.0])
    assert snapshot(mech, q, tmp_path / "f.png", browser=False) == "matplotlib"
    assert (tmp_path / "f.png").stat().st_size > 10_000
    fallback_png(mech, q, tmp_path / "g.png", title="belt")
    monkeypatch.setenv("RCM_PIN_CHROMIUM", "no-such-browser-rcm-pin")
    with pytest.raises(SnapshotError) as exc:
        screenshot_html(tmp_path / "x.html", tmp_path / "x.png")
    assert str(exc.value) == "no Chromium found; valid: install chromium or set RCM_PIN_CHROMIUM"
    assert snapshot(mech, q, tmp_path / "h.png") == "matplotlib"


@pytest.mark.parametrize("name", ["rcm_bevel", "panda", "five_bar", "four_bar"])
def test_fallback_picture_without_a_browser(name, tmp_path, monkeypatch):
    """The one picture helper falls back to matplotlib for serial and closed mechanisms."""
    monkeypatch.setattr(snap, "find_chromium", lambda: None)
    mech = rcm_pin.load(name)
    png, html = tmp_path / f"{name}.png", tmp_path / f"{name}.html"
    assert snapshot(mech, None, png, html=html) == "matplotlib"
    assert png.stat().st_size > 10_000 and html.stat().st_size > 100_000
    with Viewer(mech, snapshot_style=True) as viewer:
        assert snap.picture(viewer, tmp_path / "v.png") == "matplotlib"


def test_cli_view_html_json_and_errors(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("RCM_PIN_CHROMIUM", "no-such-browser-rcm-pin")
    traj = tmp_path / "traj.csv"
    np.savetxt(traj, np.linspace([0, 0, 0.06, 0], [0.4, -0.4, 0.1, 1.0], 5), delimiter=",")
    html, png = tmp_path / "v.html", tmp_path / "v.png"
    argv = ["view", "rcm_bevel_4dof", "--q", "0.1,0.2,0.08,0", "--traj", str(traj)]
    assert main([*argv, "--html", str(html), "--png", str(png), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["html"] == str(html) and out["png_method"] == "matplotlib"
    assert out["q"] == out["q_full"] == [0.1, 0.2, 0.08, 0.0] and out["closure_gap"] == 0.0
    assert out["input_names"] == ["q1", "q2", "q3", "q4"]
    assert "set_animation" in str(_commands(html.read_text()))
    assert main(["view", "rcm_bevel", "--q", "0.1,0.2", "--html", str(html), "--json"]) == 2
    err = json.loads(capsys.readouterr().out)["error"]
    assert err == {"type": "InvalidInputError", "message": "--q has 2 values; valid: exactly 6"}
    bad = tmp_path / "bad.csv"
    np.savetxt(bad, np.zeros((3, 2)), delimiter=",")
    assert main(["view", "rcm_bevel", "--traj", str(bad), "--html", str(html), "--json"]) == 2
    err = json.loads(capsys.readouterr().out)["error"]
    assert err["message"] == "--traj has shape (3, 2); valid: (N, 6) rows of q"
    assert main(["view", "rcm_bevel", "--assembly", "1", "--html", str(html), "--json"]) == 2
    err = json.loads(capsys.readouterr().out)["error"]
    assert err["type"] == "InvalidInputError" and err["message"].endswith("valid: 0")


def test_cli_view_live_server(capsys):
    assert main(["view", "rcm_belt", "--seconds", "0", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["url"].startswith("http://127.0.0.1:") and out["html"] is None


def test_report_section_fallback(tmp_path, monkeypatch):
    from rcm_pin.report.scenes import SCENES, section

    monkeypatch.setenv("RCM_PIN_CHROMIUM", "no-such-browser-rcm-pin")
    result = section(tmp_path)
    assert result.title == "Scenes" and len(result.figures) == len(SCENES)
    assert all((tmp_path / f).stat().st_size > 10_000 for f in result.figures)
    assert result.body.count("URDF visual geometry shaded by matplotlib") == len(SCENES)


def test_a_chromium_past_its_timeout_is_ended_with_its_processes(tmp_path, monkeypatch):
    """A browser that never finishes: a typed error after the timeout, and no process of
    its session left running (the renderers included)."""
    import os
    import stat
    import time

    import rcm_pin.viz.snapshot as snapshot_module

    fake = tmp_path / "chromium"
    pids = tmp_path / "pids"
    fake.write_text(f"#!/bin/sh\nsleep 60 &\necho $! > {pids}\nsleep 60\n")
    fake.chmod(fake.stat().st_mode | stat.S_IEXEC)
    monkeypatch.setenv("RCM_PIN_CHROMIUM", str(fake))
    page = tmp_path / "page.html"
    page.write_text("<html></html>")
    start = time.perf_counter()
    late = r"^Chromium took longer than 1\.0 s on "
    with pytest.raises(snapshot_module.SnapshotError, match=late):
        snapshot_module.screenshot_html(page, tmp_path / "x.png", timeout=1.0)
    assert time.perf_counter() - start < 10.0
    child = int(pids.read_text())
    for _ in range(50):  # the kill is immediate; the kernel may take a moment to reap
        try:
            os.kill(child, 0)
        except ProcessLookupError:
            break
        time.sleep(0.05)
    else:
        raise AssertionError(f"the child process {child} of the fake browser still runs")


def test_scene_commands_are_the_static_pages_commands():
    """``scene_commands`` (the input of the several-viewer page) are the commands the static
    page sends, in its order; no node is loaded twice (no hidden collision copies)."""
    viewer = Viewer(rcm_pin.load("rcm_bevel"))
    packed = viewer.scene_commands()
    decoded = [umsgpack.unpackb(c) for c in packed]
    assert decoded == _commands(viewer.static_html())
    objects = [d["path"] for d in decoded if d["type"] == "set_object"]
    assert len(objects) == len(set(objects))
    assert not [d for d in decoded if "/collisions/" in d["path"]]
    viewer.vis.window = object()  # as with a meshcat-server: its scene is not in memory
    with pytest.raises(InvalidInputError, match=r"^scene_commands needs an in-memory scene; "):
        viewer.scene_commands()
