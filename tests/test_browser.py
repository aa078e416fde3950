"""Real-browser check: a static Meshcat page rendered by headless Chromium.

Skipped only when Chromium is absent outside CI; under CI (``CI`` set) it must run.
"""

from __future__ import annotations

import os

import numpy as np
import pytest
from PIL import Image

import rcm_pin
from rcm_pin.viz.snapshot import find_chromium, picture, screenshot_html
from rcm_pin.viz.viewer import Viewer

pytestmark = pytest.mark.browser

SIZE = (800, 600)

if find_chromium() is None and not os.environ.get("CI"):
    pytest.skip("headless Chromium not installed (CI installs it)", allow_module_level=True)


def _render(viewer: Viewer, tmp_path, name: str) -> np.ndarray:
    page = viewer.save_html(tmp_path / f"{name}.html", controls=False)
    png = screenshot_html(page, tmp_path / f"{name}.png", SIZE)
    return np.asarray(Image.open(png).convert("RGB"), dtype=int)


def _reddish(img: np.ndarray) -> np.ndarray:
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    return (r > 120) & (r - g > 60) & (r - b > 60)


def test_mechanism_drawn_where_the_camera_looks(tmp_path):
    mech = rcm_pin.load("rcm_bevel")
    viewer = Viewer(mech, snapshot_style=True)  # RCM marker and tool axis by default
    q1 = np.array([0.3, -0.4, 0.09, 0.5, 0.6, 0.2])
    viewer.display(q1)
    viewer.fit_camera()
    first = _render(viewer, tmp_path, "first")
    assert first.shape == (SIZE[1], SIZE[0], 3)
    drawn = (first < 235).any(axis=2)  # white background elsewhere
    h, w = drawn.shape
    centre = drawn[h // 5 : 4 * h // 5, w // 5 : 4 * w // 5]
    assert centre.mean() > 0.10, f"only {centre.mean():.1%} of the centre drawn"
    assert drawn[: h // 10].mean() < 0.05 and drawn[-h // 10 :].mean() < 0.05  # margins clear
    # the RCM marker (red) is where the camera model projects point A
    col, row = np.round(viewer.project(np.zeros(3), SIZE)[0]).astype(int)
    window = _reddish(first[row - 12 : row + 13, col - 12 : col + 13])
    assert window.sum() >= 20, f"no red RCM marker near pixel ({col}, {row})"
    # the orange links are visible
    orange = (first[..., 0] > 180) & (first[..., 1] > 70) & (first[..., 1] < 170)
    assert (orange & (first[..., 2] < 90)).sum() > 500

    viewer.display(np.array([-0.5, 0.5, 0.06, 0.0, 0.0, 0.0]))  # same camera
    second = _render(viewer, tmp_path, "second")
    changed = (np.abs(second - first).sum(axis=2) > 60).mean()
    assert changed > 0.02, f"only {changed:.1%} of the pixels changed"
    assert _reddish(second[row - 12 : row + 13, col - 12 : col + 13]).sum() >= 20  # A is fixed


@pytest.mark.parametrize("name", ["planar_3rrr", "four_bar", "panda"])
def test_closed_and_arm_scenes_drawn(name, tmp_path):
    """A closed mechanism seen from above (cut-point markers where the camera projects
    them) and an arm with its meshes, through the one picture helper."""
    mech = rcm_pin.load(name)
    viewer = Viewer(mech, snapshot_style=True)
    png = tmp_path / f"{name}.png"
    assert picture(viewer, png, size=SIZE) == "chromium"
    img = np.asarray(Image.open(png).convert("RGB"), dtype=int)
    drawn = (img < 235).any(axis=2)
    h, w = drawn.shape
    assert drawn[h // 5 : 4 * h // 5, w // 5 : 4 * w // 5].mean() > 0.02
    assert drawn[: h // 20].mean() < 0.05 and drawn[-h // 20 :].mean() < 0.05  # margins clear
    for a, _ in viewer.cut_frames():  # red cut markers (none for the arm)
        col, row = np.round(viewer.project(a, SIZE)[0]).astype(int)
        window = _reddish(img[row - 10 : row + 11, col - 10 : col + 11])
        assert window.sum() >= 10, f"no red cut marker near pixel ({col}, {row})"


def test_side_by_side_page_draws_every_pane(tmp_path):
    """The report's page of several Meshcat viewers (one JavaScript copy, gzip-compressed
    commands inflated by the browser): every pane gets its blue Meshcat background and a
    robot drawn over it (a pane that failed shows the white page and an error text)."""
    from rcm_pin.report.programmable_rcm import side_by_side
    from rcm_pin.studies.rcm_comparison import make_setup, run

    tracks = [run(make_setup(name), "circle", duration=0.2) for name in ("rcm_bevel", "ur5")]
    page = side_by_side(tracks, tmp_path / "side_by_side.html")
    png = screenshot_html(page, tmp_path / "side_by_side.png", (1200, 500))
    img = np.asarray(Image.open(png).convert("RGB"), dtype=int)
    for pane in (img[40:, 10:590], img[40:, 610:1190]):
        r, b = pane[..., 0], pane[..., 2]
        assert (b - r > 40).mean() > 0.3, "no Meshcat background: the pane did not load"
        assert (r > b - 10).mean() > 0.01, "no robot drawn over the background"
