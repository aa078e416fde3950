"""PNG pictures of mechanism scenes: headless Chromium, or a matplotlib rendering.

:func:`screenshot_html` renders a static Meshcat page (:meth:`rcm_pin.viz.viewer.Viewer.save_html`)
in headless Chromium with software WebGL (SwiftShader) and a fresh profile directory.
:func:`rcm_pin.viz.drawing.fallback_png` draws the same scene (the URDF's visual geometry,
shaded, and the markers) with matplotlib from the same camera (no browser needed).
:func:`picture` (of a viewer) and :func:`snapshot` (of a mechanism at a configuration) are
the one helper that tries the first and falls back to
the second, for every mechanism.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import subprocess
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rcm_pin.errors import SnapshotError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.viz.drawing import fallback_png
from rcm_pin.viz.explain import PLAIN, SceneStyle

if TYPE_CHECKING:
    from rcm_pin.viz.viewer import Viewer

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


#: Virtual time a page may run before the picture [ms]. Short budgets (0.5–2 s) made this
#: Chromium (156) hang before writing any picture on a heavy page (the 29 MB panda scene:
#: 4 of 6 runs at 2 s, 0 of 13 at 10 s); virtual time costs almost no wall time.
BUDGET_MS = 10_000


def screenshot_html(html: str | Path, png: str | Path, size: tuple[int, int] = (800, 600),
                    budget_ms: int = BUDGET_MS, timeout: float = 120.0) -> Path:  # fmt: skip
    """Render a local HTML file in headless Chromium and save a PNG screenshot.

    Chromium runs in a session of its own, so a run past ``timeout`` is ended with every
    process it started (renderers, GPU process), not only the browser process.

    Args:
        html: path of a local, self-contained HTML file.
        png: output PNG path.
        size: window width and height [px].
        budget_ms: virtual time the page may run before the picture is taken [ms]
            (:data:`BUDGET_MS`).
        timeout: wall-clock limit for the Chromium process [s].

    Returns:
        The PNG path.

    Raises:
        SnapshotError: no Chromium, it ran past ``timeout``, or it exited without writing
            the PNG.
    """
    exe = find_chromium()
    if exe is None:
        raise SnapshotError("no Chromium found; valid: install chromium or set RCM_PIN_CHROMIUM")
    html, png = Path(html).resolve(), Path(png).resolve()
    png.parent.mkdir(parents=True, exist_ok=True)
    png.unlink(missing_ok=True)
    # a killed Chromium may leave files behind for a moment: never fail on the cleanup
    fresh = tempfile.TemporaryDirectory(prefix="rcm_pin_chromium_", ignore_cleanup_errors=True)
    with fresh as profile:
        cmd = [
            exe,
            *CHROMIUM_FLAGS,
            f"--user-data-dir={profile}",
            f"--window-size={size[0]},{size[1]}",
            f"--virtual-time-budget={int(budget_ms)}",
            f"--screenshot={png}",
            html.as_uri(),
        ]
        proc = subprocess.Popen(
            cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
            start_new_session=True,
        )  # fmt: skip
        try:
            _, stderr = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            _kill_session(proc)
            raise SnapshotError(f"Chromium took longer than {timeout} s on {html}") from None
    if not png.exists():
        tail = stderr.strip().splitlines()[-3:]
        raise SnapshotError(f"Chromium wrote no screenshot (exit {proc.returncode}): {tail}")
    return png


def _kill_session(proc: subprocess.Popen[str]) -> None:
    """End a process and every process of its session (it was started in a new one)."""
    with contextlib.suppress(ProcessLookupError):
        os.killpg(proc.pid, signal.SIGKILL)
    proc.communicate()


def picture(
    viewer: Viewer,
    png: str | Path,
    *,
    html: str | Path | None = None,
    size: tuple[int, int] = (800, 600),
    browser: bool = True,
) -> str:
    """The browser-else-fallback picture of a viewer's scene at its configuration.

    Args:
        viewer: the scene (best built with ``snapshot_style=True``; no animation, or
            the browser shows one of its frames).
        png: output path.
        html: also keep the static Meshcat page here (default: a temporary file).
        size: picture size [px].
        browser: try headless Chromium first.

    Returns:
        ``"chromium"`` (the Meshcat scene rendered by headless Chromium) or ``"matplotlib"``
        (:func:`rcm_pin.viz.drawing.fallback_png` of the mechanism at ``viewer.q``: its
        visual geometry shaded in the viewer's colours, with the default markers, the
        viewer's decorations and camera; used when Chromium is absent or fails).
    """
    with tempfile.TemporaryDirectory(prefix="rcm_pin_scene_") as tmp:
        page = viewer.save_html(html or Path(tmp) / "scene.html", controls=False)
        if browser and find_chromium() is not None:
            try:
                screenshot_html(page, png, size)
                return "chromium"
            except SnapshotError:
                pass
    fallback_png(viewer.mech, viewer.q, png, size=size, camera=viewer.camera,
                 geom=viewer.viz.visual_model,
                 decorations=viewer.decoration_meshes())  # fmt: skip
    return "matplotlib"


def snapshot(mech: Mechanism, q: np.ndarray | None, png: str | Path, *,
             html: str | Path | None = None, size: tuple[int, int] = (800, 600),
             browser: bool = True, style: SceneStyle = PLAIN) -> str:  # fmt: skip
    """Write a PNG of any mechanism at coordinates ``q``; returns the method used.

    Builds a :class:`~rcm_pin.viz.viewer.Viewer` (snapshot style, default markers),
    shows ``q`` (None: the default configuration), fits the camera and takes
    :func:`picture`.

    Args:
        mech: the mechanism.
        q: coordinates (n,) [rad, m] (closed mechanisms: a closed configuration).
        png: output path.
        html: also keep the static Meshcat page here.
        size: picture size [px].
        browser: try headless Chromium first.
        style: body colours and decorations (:class:`rcm_pin.viz.explain.SceneStyle`;
            the base plate is sized at ``q``).

    Returns:
        ``"chromium"`` or ``"matplotlib"`` (see :func:`picture`).
    """
    from rcm_pin.viz.viewer import Viewer

    with Viewer(mech, snapshot_style=True, style=SceneStyle(style.colors)) as viewer:
        if q is not None:
            viewer.display(q)
        viewer.show_style(style)  # decorations sized at q
        viewer.fit_camera()
        return picture(viewer, png, html=html, size=size, browser=browser)
