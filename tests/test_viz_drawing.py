"""The no-browser picture: shaded visual geometry and markers of every catalogue mechanism."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from PIL import Image
from scipy.ndimage import binary_erosion

import rcm_pin
from rcm_pin.analysis.position import forward
from rcm_pin.catalog.loading import from_urdf
from rcm_pin.errors import InvalidInputError
from rcm_pin.viz import overlays as ov
from rcm_pin.viz import snapshot as snap
from rcm_pin.viz.drawing import WHAT, describe, fallback_png
from rcm_pin.viz.shading import cluster
from rcm_pin.viz.triangles import box, shape_triangles
from rcm_pin.viz.viewer import Viewer

SIZE = (640, 480)


def _image(png) -> np.ndarray:
    return np.asarray(Image.open(png).convert("RGB"), dtype=int)


def _red(img: np.ndarray) -> np.ndarray:
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    return (r > 120) & (r - g > 60) & (r - b > 60)


def _green(img: np.ndarray) -> np.ndarray:
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    return (g > 80) & (g - r > 40) & (g - b > 30)


def _marker(img: np.ndarray) -> np.ndarray:
    """Red, green or the olive of green over red (translucent markers)."""
    return _red(img) | _green(img) | (np.ptp(img, axis=2) > 40) & (img[..., 2] < 80)


def _near(mask: np.ndarray, pixel: np.ndarray, half: int = 4) -> int:
    col, row = np.round(pixel).astype(int)
    return int(mask[max(row - half, 0) : row + half + 1, max(col - half, 0) : col + half + 1].sum())


def _solid(img: np.ndarray) -> float:
    """Share of the picture inside filled areas (5x5 blocks all drawn): <= 0.001 for the
    former stick figures of joint frames (800x600), >= 0.018 for shaded bodies."""
    return float(binary_erosion((img < 230).any(axis=2), np.ones((5, 5))).mean())


@pytest.fixture(scope="module", params=rcm_pin.names())
def scene(request, tmp_path_factory):
    """(viewer, png) of the fallback picture of each catalogue mechanism."""
    mech = rcm_pin.load(request.param)
    png = tmp_path_factory.mktemp("drawing") / f"{request.param}.png"
    with Viewer(mech, snapshot_style=True) as viewer:
        fallback_png(mech, viewer.q, png, size=SIZE, camera=viewer.camera,
                     geom=viewer.viz.visual_model)  # fmt: skip
        yield viewer, png


def test_picture_size_and_bodies(scene):
    """Its size, filled areas and material colours (no wall-clock bound: the time a
    picture takes measures the machine, not the drawing)."""
    viewer, png = scene
    img = _image(png)
    assert img.shape == (SIZE[1], SIZE[0], 3)
    has_bodies = viewer.viz.visual_model.ngeoms > 0
    assert _solid(img) > (0.005 if has_bodies else 0.002), f"solid area {_solid(img):.3f}"
    if has_bodies:  # the URDF material colours show (shaded, so darker or equal)
        colours = {tuple(np.round(o.meshColor[:3] * 255)) for o in
                   viewer.viz.visual_model.geometryObjects}  # fmt: skip
        drawn = img[(img < 230).any(axis=2)]
        for c in colours:
            ratio = drawn / np.maximum(np.array(c), 1.0)
            close = (np.ptp(ratio, axis=1) < 0.15) & (ratio.max(axis=1) <= 1.05)
            assert close.any(), f"no pixel shaded from the material colour {c}"


def test_markers_where_the_camera_projects_them(scene):
    viewer, png = scene
    mech, img = viewer.mech, _image(png)
    data = mech.model.createData()
    pin.forwardKinematics(mech.model, data, mech.to_pin(viewer.q))
    if mech.rcm is not None:
        a = ov.frame_point(mech.model, data, mech.rcm.point_frame_id)[:3, 3]
        assert _near(_red(img), viewer.project(a, SIZE)[0]) >= 10, "no red sphere at A"
        T, (lo, hi) = ov.axis_transform(mech, data, ov.axis_span(mech)), ov.axis_span(mech)
        ends = T[:3, 3] + np.outer([-0.45, 0.45], (hi - lo) * T[:3, 1])
        samples = np.linspace(ends[0], ends[1], 15)
        px = viewer.project(samples, SIZE)
        inside = np.all((px > 2) & (px < np.array(SIZE) - 3), axis=1)
        hits = [_near(_green(img), p, 2) > 0 for p in px[inside]]
        assert np.mean(hits) > 0.6, f"green rod along the axis at {np.mean(hits):.0%} of samples"
    else:
        out = ov.frame_point(mech.model, data, mech.output.frame_id)[:3, 3]  # green (on red)
        assert _near(_marker(img), viewer.project(out, SIZE)[0]) >= 5, "no output marker"
    for c in mech.loops.closures if mech.loops is not None else ():
        cut = ov.frame_point(mech.model, data, c.frame_a_id)[:3, 3]
        found = _near(_marker(img), viewer.project(cut, SIZE)[0])
        assert found >= 5, "no marker at the cut point"


def _moved(mech, step: float) -> tuple[np.ndarray, np.ndarray]:
    """Two configurations of mech (closed ones for closed mechanisms): q1 moves the first
    two joints (serial) or the first drive (closed) of the viewer's q0 by ``step`` [rad]."""
    q0 = mech.home  # the viewer's q0
    if mech.loops is None:
        move = np.where(np.arange(mech.nq) < 2, step, 0.0)
        return q0, np.clip(q0 + move, mech.lower, mech.upper)
    drives = q0[mech.loops.drive_q] + np.where(np.arange(len(mech.loops.drive_q)) < 1, step, 0.0)
    return q0, forward(mech, drives, q_guess=q0).solutions[0].q


@pytest.mark.parametrize(
    ("name", "step"), [("rcm_bevel", 0.4), ("panda", 0.4), ("four_bar", 0.4), ("planar_3rrr", 0.2)]
)
def test_a_body_moved_by_q_moves_in_the_picture(name, step, tmp_path):
    mech = rcm_pin.load(name)
    q0, q1 = _moved(mech, step)
    with Viewer(mech, snapshot_style=True) as viewer:
        camera, geom = viewer.camera, viewer.viz.visual_model
        at = [viewer.project(np.array([T[:3, 3] for T in viewer.placements(q).values()]), SIZE)
              for q in (q0, q1)]  # fmt: skip
    assert np.linalg.norm(at[1] - at[0], axis=1).max() > 10  # a body moves on the picture
    first, second = (
        _image(
            fallback_png(mech, q, tmp_path / f"{k}.png", "-", size=SIZE, camera=camera, geom=geom)
        )
        for k, q in enumerate((q0, q1))
    )
    changed = (np.abs(second - first).sum(axis=2) > 60).mean()
    assert changed > 0.005, f"only {changed:.2%} of the pixels changed"
    assert np.abs(second - first).sum() > 0


#: A one-joint arm with no visual geometry (drawn as rods).
BARE = """<robot name="bare">
  <link name="base"/><link name="arm"/><link name="tool"/>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="t" type="fixed"><parent link="arm"/><child link="tool"/>
    <origin xyz="0.3 0 0"/></joint>
</robot>"""


def test_snapshot_without_browser_uses_the_renderer(tmp_path, monkeypatch):
    monkeypatch.setattr(snap, "find_chromium", lambda: None)
    mech = rcm_pin.load("rcm_bevel_4dof")
    png = tmp_path / "s.png"
    assert snap.snapshot(mech, np.array([0.4, 0.3, 0.1, 0.8]), png, size=(500, 400)) == "matplotlib"
    img = _image(png)
    assert img.shape == (400, 500, 3) and _solid(img) > 0.03
    assert describe(mech) == WHAT[True] == "visual geometry shaded by matplotlib"
    assert describe(from_urdf(BARE, tool_frame="tool")) == WHAT[False]
    default = fallback_png(mech, np.array([0.4, 0.3, 0.1, 0.8]), tmp_path / "d.png")
    assert _image(default).shape == (600, 800, 3)
    with pytest.raises(InvalidInputError):
        fallback_png(mech, np.zeros(3), tmp_path / "bad.png")


def test_shapes_and_clustering():
    v, f = box(np.array([0.1, 0.2, 0.3]))
    assert v.shape == (8, 3) and f.shape == (12, 3)
    normals = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    assert np.all(np.einsum("ij,ij->i", normals, v[f].mean(axis=1)) > 0)  # outward
    for shape in (pin.hppfcl.Cylinder(0.1, 0.4), pin.hppfcl.Sphere(0.2),
                  pin.hppfcl.Capsule(0.1, 0.4), pin.hppfcl.Cone(0.1, 0.4)):  # fmt: skip
        v, f = shape_triangles(shape)
        tri = v[f]
        normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        assert np.all(np.einsum("ij,ij->i", normals, tri.mean(axis=1)) > -1e-12)
        assert np.all(np.linalg.norm(normals, axis=1) > 0)
        shape.computeLocalAABB()
        assert np.allclose(v.min(0), shape.aabb_local.min_, atol=1e-12)
    v, f = shape_triangles(pin.hppfcl.Sphere(0.2))
    merged, kept = cluster(v, f, 0.05)
    assert len(merged) < len(v) and len(kept) < len(f) and kept.max() < len(merged)
