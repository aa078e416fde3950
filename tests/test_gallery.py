"""The explained scene (per-body colours, base plate, triads, drive rings, joint axes) in
both picture routes, and the gallery of docs/gallery.md (tools/gallery.py --check)."""

from __future__ import annotations

import base64
import json
import re
import sys
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import umsgpack
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

import rcm_pin
from rcm_pin.cli import main
from rcm_pin.errors import InvalidInputError
from rcm_pin.viz.caption import KEY_PX, explained_png, key, place_labels
from rcm_pin.viz.decorations import AXIS_COLORS, DRIVE_COLOR, drives, joint_axis, ring_site
from rcm_pin.viz.drawing import fallback_png
from rcm_pin.viz.explain import EXPLAINED, SceneStyle
from rcm_pin.viz.palette import COLOR_MODES, GROUND, PALETTE, paint
from rcm_pin.viz.scene import hex_color
from rcm_pin.viz.triangles import visual_model
from rcm_pin.viz.viewer import Viewer

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
import gallery  # noqa: E402

EXACT = 1e-12


def _node(viewer: Viewer, path: str):
    node = viewer.vis.window.tree
    for part in path.strip("/").split("/"):
        node = node[part]
    return node


def _pinocchio_hex(rgba) -> int:
    """A colour as Pinocchio's Meshcat loader writes it (each channel truncated)."""
    r, g, b = (int(c * 255) for c in rgba[:3])
    return r << 16 | g << 8 | b


def _material_color(node) -> int:
    """The colour of the material of a node's Meshcat object."""
    obj = umsgpack.unpackb(node.object)["object"]
    return int(obj["materials"][0]["color"])


@pytest.fixture(scope="module")
def spherical():
    """The explained in-memory scene of the spherical 3-RRR (the gallery's style)."""
    with Viewer(rcm_pin.load("spherical_3rrr"), snapshot_style=True, style=EXPLAINED) as v:
        yield v


def test_every_body_has_its_own_colour_and_the_ground_is_grey(spherical):
    """The URDF sets no material: each body (objects of one parent joint) gets one colour
    of the palette, distinct from the other bodies'; the base (world joint) is grey."""
    geom = spherical.viz.visual_model
    by_body: dict[int, set[int]] = {}
    for obj in geom.geometryObjects:
        path = spherical.viz.getViewerNodeName(obj, pin.GeometryType.VISUAL)
        node = _node(spherical, f"meshcat/{path}")
        by_body.setdefault(int(obj.parentJoint), set()).add(_material_color(node))
    assert all(len(colours) == 1 for colours in by_body.values())
    assert by_body.pop(0) == {_pinocchio_hex(GROUND)}
    moving = [c for colours in by_body.values() for c in colours]
    assert len(set(moving)) == len(moving) == 7  # proximal and distal arcs, platform
    assert set(moving) <= {_pinocchio_hex(c) for c in PALETTE}


def test_scene_holds_plate_triads_drive_rings_and_axes(spherical):
    overlays = _node(spherical, "meshcat/overlays")
    mech = spherical.mech
    assert overlays["ground"].object is not None
    assert _material_color(overlays["ground"]) == hex_color(GROUND)
    for k, axis in enumerate("xyz"):  # red, green, blue arrows at the output frame
        assert _material_color(overlays["triad_output"][axis]) == hex_color(AXIS_COLORS[k])
    assert "triad_A" not in overlays  # no remote centre
    for name in ("u1", "u2", "u3"):
        assert _material_color(overlays[f"drive_{name}"]) == hex_color(DRIVE_COLOR)
    axes = {n.removeprefix("axis_") for n in overlays if n.startswith("axis_")}
    assert axes == {mech.model.names[j] for j in range(1, mech.model.njoints)}
    assert [d.label for d in spherical.decorations() if d.label] == ["output", "u1", "u2", "u3"]


def test_drive_rings_sit_on_their_joint_axes_and_follow_the_pose(spherical):
    """Each ring's centre lies on its joint's axis, at the configuration shown and at
    another closed configuration (the rings follow :meth:`display`)."""
    mech = spherical.mech
    q1 = rcm_pin.forward(mech, np.array([0.3, -0.2, 0.4]), q_guess=mech.home).solutions[0].q
    for q in (spherical.q, q1):
        data = mech.model.createData()
        pin.forwardKinematics(mech.model, data, mech.to_pin(q))
        rings = {d.label: d for d in spherical.decorations() if d.kind == "drive"}
        for label, joint_name in drives(mech).items():
            j = mech.model.getJointId(joint_name)
            axis, prismatic = joint_axis(mech.model, j, mech.to_pin(q))
            assert not prismatic
            M = data.oMi[j]
            e = M.rotation @ axis
            centre = rings[label].transform(data)[:3, 3]
            off = centre - M.translation
            assert np.linalg.norm(off - (off @ e) * e) < EXACT, label
            assert abs(rings[label].transform(data)[:3, 2] @ e) == pytest.approx(1.0, abs=EXACT)


def test_matplotlib_route_draws_the_same_decorations(tmp_path):
    """The no-browser picture gets the viewer's decorations: the plate under the bodies and
    a magenta ring around each base pivot (the planar 3-RRR, seen from above)."""
    mech = rcm_pin.load("planar_3rrr")
    size = (480, 360)
    with Viewer(mech, snapshot_style=True, style=EXPLAINED) as viewer:
        under, over = viewer.decoration_meshes()
        assert len(under) == 1  # the plate, behind the plane (seen from above)
        up = np.array([0.0, 0.0, 1.0])
        bodies = viewer.scene_points(viewer.q)
        assert (under[0].vertices @ up).max() < (bodies @ up).min()
        png = fallback_png(mech, viewer.q, tmp_path / "p.png", "-", size=size,
                           camera=viewer.camera, geom=viewer.viz.visual_model,
                           decorations=(under, over))  # fmt: skip
        labels = dict(viewer.labels())
        img = np.asarray(Image.open(png).convert("RGB"), dtype=int)
        r, g, b = img[..., 0], img[..., 1], img[..., 2]
        magenta = (r > 150) & (b > 110) & (g < 90)
        for name in ("A1", "A2", "A3"):
            col, row = np.round(viewer.project(labels[name], size)[0]).astype(int)
            window = magenta[row - 15 : row + 16, col - 15 : col + 16]
            assert window.sum() >= 15, f"no magenta ring around {name}"


@pytest.mark.parametrize(
    ("name", "colors", "painted"),
    [
        ("spherical_3rrr", "urdf", 0),  # no materials: Pinocchio's grey kept
        ("spherical_3rrr", "auto", 20),  # no materials: every object its body's colour
        ("rcm_bevel", "auto", 0),  # every object has a URDF material: kept
        ("rcm_bevel", "bodies", 27),  # replaced: all 27 objects (hubs included)
        ("panda", "auto", 0),  # meshes keep their own materials
        ("panda", "bodies", 11),
    ],
)
def test_colour_modes(name, colors, painted):
    geom = visual_model(rcm_pin.load(name))
    before = [o.meshColor.copy() for o in geom.geometryObjects]
    paint(geom, colors)
    after = [o.meshColor for o in geom.geometryObjects]
    assert sum(not np.array_equal(a, b) for a, b in zip(after, before, strict=True)) == painted


def test_unknown_colour_mode_is_refused():
    message = "colors 'rainbow' is unknown; valid: auto, urdf, bodies"
    with pytest.raises(InvalidInputError) as exc:
        SceneStyle("rainbow")
    assert str(exc.value) == message
    with pytest.raises(InvalidInputError) as exc:
        paint(visual_model(rcm_pin.load("four_bar")), "rainbow")
    assert str(exc.value) == message


def test_ring_site_is_where_the_body_meets_the_axis():
    arc = np.array([[0.004, 0.0, 0.1], [0.0, 0.05, 0.09], [0.0, 0.09, 0.05]])  # from z = 0.1
    assert ring_site(arc, 0.01) == pytest.approx(0.1, abs=EXACT)
    assert ring_site(arc + [0.5, 0.0, 0.0], 0.01) is None  # far from the axis
    assert ring_site(np.zeros((0, 3)), 0.01) is None


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.floats(0, 799), st.floats(0, 559), st.text("qA1", min_size=1,
                                                                         max_size=6)),
                max_size=12))  # fmt: skip
def test_placed_labels_never_overlap(raw):
    placed = place_labels([(t, np.array([c, r])) for c, r, t in raw], (800, 560))
    assert len(placed) == len(raw)
    boxes = []
    for text, _, at in placed:
        w = 6.5 * len(text) + 6
        boxes.append((at[0], at[1] - 14, at[0] + w, at[1]))
    for i, a in enumerate(boxes):
        for b in boxes[:i]:
            assert a[2] < b[0] or a[0] > b[2] or a[3] < b[1] or a[1] > b[3]


def test_explained_png_adds_key_panel_and_caption(tmp_path):
    scene = tmp_path / "scene.png"
    Image.new("RGB", (400, 300), "white").save(scene)
    rows = key([((0.6, 0.6, 0.62, 1.0), ["base"])], drives=True, triads=True, axes=True,
               rcm=True, closed=False)  # fmt: skip
    assert [t for _, t in rows][:2] == ["base", "ring: a driven joint"]
    out = explained_png(scene, tmp_path / "out.png", "a caption " * 40,
                        [("u1", np.array([100.0, 100.0]))], rows)  # fmt: skip
    w, h = Image.open(out).size
    assert w == 400 + KEY_PX and h > 300 + 3 * 17


def test_cli_view_explain_png(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("RCM_PIN_CHROMIUM", "no-such-browser-rcm-pin")
    png, html = tmp_path / "v.png", tmp_path / "v.html"
    argv = ["view", "four_bar", "--explain", "--colors", "bodies", "--png", str(png)]
    assert main([*argv, "--html", str(html), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["png_method"] == "matplotlib" and png.stat().st_size > 10_000
    blobs = re.findall(r"data:application/octet-binary;base64,([A-Za-z0-9+/=]+)", html.read_text())
    paths = {umsgpack.unpackb(base64.b64decode(b)).get("path") for b in blobs}
    assert {"/meshcat/overlays/ground", "/meshcat/overlays/drive_O1"} <= paths
    assert main(["view", "four_bar", "--colors", "rainbow", "--json"]) == 2
    assert json.loads(capsys.readouterr().out)["error"]["type"] == "UsageError"
    assert COLOR_MODES == ("auto", "urdf", "bodies")  # the CLI's choices


def test_gallery_is_complete_and_up_to_date():
    """Every catalogue mechanism has a shot, a picture and a caption in docs/gallery.md,
    and each picture's scene digest matches the manifest (python tools/gallery.py)."""
    assert gallery.check() == []
    manifest = json.loads(gallery.MANIFEST.read_text())
    assert list(manifest) == list(rcm_pin.names())
    page = gallery.PAGE.read_text()
    for name, entry in manifest.items():
        assert f"![{name}](images/gallery/{name}.png)" in page and entry["caption"] in page


def test_gallery_check_finds_what_is_missing_or_stale(monkeypatch):
    """--check fails on a mechanism without a shot, on a changed pose (the scene digest)
    and on a changed caption, naming the mechanism and the command that fixes it."""
    shots = dict(gallery.SHOTS)
    del shots["ur5"]
    shots["four_bar"] = gallery.Shot(shots["four_bar"].text, (0.7,))
    monkeypatch.setattr(gallery, "SHOTS", shots)
    assert gallery.check(["four_bar"]) == [
        "ur5: no shot in tools/gallery.py SHOTS",
        "four_bar: stale scene (run python tools/gallery.py four_bar)",
    ]
    shots["four_bar"] = gallery.Shot("Another text.")
    assert gallery.check(["four_bar"])[-1] == (
        "four_bar: stale caption (run python tools/gallery.py four_bar)"
    )
