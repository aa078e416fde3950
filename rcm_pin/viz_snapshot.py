"""PNG pictures of mechanism scenes: headless Chromium, or a matplotlib fallback.

:func:`screenshot_html` renders a static Meshcat page (:meth:`rcm_pin.viz.Viewer.save_html`)
in headless Chromium with software WebGL (SwiftShader) and a fresh profile directory.
:func:`frames_png` draws the joint frames and the links between them with matplotlib
(no browser needed). :func:`snapshot` tries the first and falls back to the second.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import pinocchio as pin

from rcm_pin.errors import SnapshotError
from rcm_pin.mechanism import Mechanism

#: Command-line flags for a headless, offline, software-rendered Chromium.
CHROMIUM_FLAGS: tuple[str, ...] = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--enable-unsafe-swiftshader",
    "--use-angle=swiftshader",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
    "--disable-quic",
    "--hide-scrollbars",
)


def find_chromium() -> str | None:
    """Path of a Chromium / Chrome executable (``RCM_PIN_CHROMIUM`` first), or None."""
    env = os.environ.get("RCM_PIN_CHROMIUM")
    if env:
        return env if shutil.which(env) else None
    for name in ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable"):
        path = shutil.which(name)
        if path:
            return path
    return None


def screenshot_html(html: str | Path, png: str | Path, size: tuple[int, int] = (800, 600),
                    budget_ms: int = 2000, timeout: float = 120.0) -> Path:  # fmt: skip
    """Render a local HTML file in headless Chromium and save a PNG screenshot.

    Args:
        html: path of a local, self-contained HTML file.
        png: output PNG path.
        size: window width and height [px].
        budget_ms: virtual time the page may run before the picture is taken [ms].
        timeout: wall-clock limit for the Chromium process [s].

    Returns:
        The PNG path.

    Raises:
        SnapshotError: no Chromium, or it exited without writing the PNG.
    """
    exe = find_chromium()
    if exe is None:
        raise SnapshotError("no Chromium found; valid: install chromium or set RCM_PIN_CHROMIUM")
    html, png = Path(html).resolve(), Path(png).resolve()
    png.parent.mkdir(parents=True, exist_ok=True)
    png.unlink(missing_ok=True)
    with tempfile.TemporaryDirectory(prefix="rcm_pin_chromium_") as profile:
        cmd = [
            exe,
            *CHROMIUM_FLAGS,
            f"--user-data-dir={profile}",
            f"--window-size={size[0]},{size[1]}",
            f"--virtual-time-budget={int(budget_ms)}",
            f"--screenshot={png}",
            html.as_uri(),
        ]
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            raise SnapshotError(f"Chromium took longer than {timeout} s on {html}") from None
    if not png.exists():
        tail = proc.stderr.strip().splitlines()[-3:]
        raise SnapshotError(f"Chromium wrote no screenshot (exit {proc.returncode}): {tail}")
    return png


def frames_png(mech: Mechanism, q: np.ndarray, png: str | Path, title: str = "") -> Path:
    """Matplotlib line drawing of the joint frames at ``q`` (the no-browser fallback).

    Lines join each joint origin to its parent's; short red/green/blue segments show
    each joint frame's x/y/z axes; a red dot marks the RCM point and a black square the
    tool centre.
    """
    from matplotlib.figure import Figure

    q = mech.check_q(q)
    model, data = mech.model, mech.model.createData()
    pin.forwardKinematics(model, data, mech.to_pin(q))
    pin.updateFramePlacements(model, data)
    fig = Figure(figsize=(6.4, 4.8), dpi=100)
    ax = fig.add_subplot(projection="3d")
    origins = np.array([data.oMi[j].translation for j in range(model.njoints)])
    for j in range(1, model.njoints):
        seg = origins[[model.parents[j], j]]
        ax.plot(*seg.T, color="tab:orange", lw=2)
    scale = 0.25 * float(np.ptp(origins, axis=0).max() or 0.1)
    for j in range(1, model.njoints):
        o, R = data.oMi[j].translation, data.oMi[j].rotation
        for k, c in enumerate("rgb"):
            ax.plot(*np.c_[o, o + scale * R[:, k]], color=c, lw=1)
    tool = data.oMf[mech.tool_frame_id].translation
    ax.scatter(*tool, color="k", marker="s", s=30, label="tool centre")
    if mech.rcm_frame_id >= 0:
        ax.scatter(*data.oMf[mech.rcm_frame_id].translation, color="r", s=40, label="RCM A")
        ax.plot(*np.c_[np.zeros(3), 1.3 * tool], color="tab:green", ls="--", lw=1)
    pts = np.vstack([origins, tool])
    centre, half = (pts.max(0) + pts.min(0)) / 2, float(np.ptp(pts, axis=0).max()) / 2 + scale
    ax.set(xlim=centre[0] + [-half, half], ylim=centre[1] + [-half, half])
    ax.set(zlim=centre[2] + [-half, half], xlabel="x [m]", ylabel="y [m]", zlabel="z [m]")
    ax.set_title(title or f"{mech.name}: joint frames (matplotlib fallback)")
    ax.legend(loc="upper left", fontsize=8)
    png = Path(png)
    png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(png)
    return png


def snapshot(mech: Mechanism, q: np.ndarray, png: str | Path, *, html: str | Path | None = None,
             size: tuple[int, int] = (800, 600), browser: bool = True) -> str:  # fmt: skip
    """Write a PNG of the mechanism at ``q``; returns the method used.

    Args:
        mech: the mechanism.
        q: configuration (Mechanism coordinates).
        png: output path.
        html: also keep the static Meshcat page here (default: a temporary file).
        size: picture size [px] (Chromium).
        browser: try headless Chromium first.

    Returns:
        ``"chromium"`` (Meshcat scene rendered by headless Chromium) or ``"matplotlib"``
        (line drawing of the joint frames, used when Chromium is absent or fails).
    """
    from rcm_pin.viz import Viewer

    with Viewer(mech, snapshot_style=True) as viewer:
        if mech.rcm_frame_id >= 0:
            viewer.show_rcm()
            viewer.show_tool_axis()
        viewer.display(q)
        viewer.fit_camera()
        with tempfile.TemporaryDirectory(prefix="rcm_pin_scene_") as tmp:
            page = viewer.save_html(html or Path(tmp) / "scene.html", controls=False)
            if browser and find_chromium() is not None:
                try:
                    screenshot_html(page, png, size)
                    return "chromium"
                except SnapshotError:
                    pass
    frames_png(mech, q, png)
    return "matplotlib"
