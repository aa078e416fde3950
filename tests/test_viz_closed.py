"""Closed mechanisms in Meshcat: shown assembled (passive joints solved), exported to HTML."""

from __future__ import annotations

import base64
import re

import numpy as np
import pinocchio as pin
import pytest
import umsgpack

from rcm_pin.closed_loop import direct_position_path, load_closed
from rcm_pin.errors import InvalidInputError
from rcm_pin.viz_closed import ClosedViewer, snapshot_closed


def _commands(html: str) -> list[dict]:
    blobs = re.findall(r"data:application/octet-binary;base64,([A-Za-z0-9+/=]+)", html)
    return [umsgpack.unpackb(base64.b64decode(b)) for b in blobs]


@pytest.fixture(scope="module", params=["planar_3rrr", "five_bar"])
def mech(request):
    return load_closed(request.param)


DRIVES = {"planar_3rrr": [-0.2059, -2.481, 1.671], "five_bar": [2.365, 0.7762]}


def test_display_closes_the_loops(mech):
    with ClosedViewer(mech) as viewer:
        for assembly in range(2):
            q = viewer.display(np.array(DRIVES[mech.name]), assembly)
            assert np.allclose(q[mech.idx_driven], DRIVES[mech.name])
            # the cut frames coincide in the placements Pinocchio's visualizer displayed
            assert viewer.closure_gap() < 1e-12
            for a, b in viewer.cut_frames():
                assert np.linalg.norm(a - b) < 1e-12
        # the open tree at the same drives with passive joints at zero does not close
        viewer.display_full(mech.assemble(np.array(DRIVES[mech.name]), np.zeros(len(mech.passive))))
        assert viewer.closure_gap() > 1e-3


def test_html_contains_the_bodies_at_the_displayed_placements(mech, tmp_path):
    with ClosedViewer(mech) as viewer:
        q = viewer.display(np.array(DRIVES[mech.name]))
        html = viewer.save_html(tmp_path / "scene.html").read_text()
        expected = viewer.placements(q)
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


def test_animation_and_errors(mech, tmp_path):
    with ClosedViewer(mech) as viewer:
        q0 = viewer.display(np.array(DRIVES[mech.name]))
        path = direct_position_path(
            mech, np.array(DRIVES[mech.name]) + np.linspace(0, 0.05, 5)[:, None], q0
        )
        viewer.animate(path, 0.1)
        assert "set_animation" in {c["type"] for c in _commands(viewer.static_html())}
        with pytest.raises(InvalidInputError, match=r"^trajectory has shape \(3,\); valid"):
            viewer.animate(np.zeros(3))
        with pytest.raises(InvalidInputError, match=r"^assembly 5 out of range; valid: 0\.\.1 "):
            viewer.display(np.array(DRIVES[mech.name]), 5)


def test_png_fallback(tmp_path):
    with ClosedViewer(load_closed("five_bar")) as viewer:
        png = tmp_path / "f.png"
        assert snapshot_closed(viewer, png, browser=False) == "matplotlib"
        assert png.stat().st_size > 5000
