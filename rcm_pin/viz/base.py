"""The Meshcat plumbing of :class:`rcm_pin.viz.viewer.Viewer`: opening, camera, export, closing.

:class:`MeshcatScene` opens a Meshcat visualizer on one Pinocchio model with the visual
geometry of its URDF (``package://`` meshes resolved in the given folders), aims the
camera, exports static HTML and stops a server it started. The scene lives in memory
(:class:`rcm_pin.viz.scene.SceneRecorder`) unless a local ``meshcat-server`` is asked for.
Meshcat 0.3.2 always aims its orbit camera at the world origin, so :meth:`set_camera`
shifts the whole scene (``/meshcat``, grid and axes) by the negated target.
"""

from __future__ import annotations

import contextlib
import io
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
import pinocchio as pin

with warnings.catch_warnings():  # meshcat imports pyzmq's deprecated zmq.eventloop.ioloop
    warnings.simplefilter("ignore", DeprecationWarning)
    import meshcat
    import meshcat.geometry as mg
    from meshcat.animation import Animation
    from pinocchio.visualize import MeshcatVisualizer

from rcm_pin.errors import InvalidInputError
from rcm_pin.model.meshes import drawable_urdf
from rcm_pin.viz.camera import FOV_DEG, meshcat_position
from rcm_pin.viz.palette import check_mode, mesh_arrays, paint, repainted_meshes
from rcm_pin.viz.scene import SceneRecorder, hex_color
from rcm_pin.viz.server import LOCAL_HOST, start_server, stop_server

_Scene = TypeVar("_Scene", bound="MeshcatScene")

#: Meshcat path of the overlays (markers, axes, point sets).
OVERLAYS = "overlays"


def check_zmq_url(zmq_url: str) -> None:
    """Refuse a Meshcat server that is not on this machine.

    Raises:
        InvalidInputError: not ``tcp://127.0.0.1:PORT`` or ``tcp://localhost:PORT``.
    """
    host = zmq_url.removeprefix("tcp://").rsplit(":", 1)[0]
    if not zmq_url.startswith("tcp://") or host not in {"127.0.0.1", "localhost"}:
        raise InvalidInputError(
            f"zmq_url {zmq_url!r} is not on this machine; valid: tcp://127.0.0.1:PORT"
        )


class MeshcatScene:
    """Base class: a Meshcat visualizer with Pinocchio's visual geometry of one model.

    Attributes:
        vis: the ``meshcat.Visualizer`` (root path ``/meshcat``).
        viz: Pinocchio's ``MeshcatVisualizer``.
        camera: (eye, target) world positions set by :meth:`set_camera` [m].
    """

    vis: Any
    viz: Any
    camera: tuple[np.ndarray, np.ndarray]

    def _open(self, model: pin.Model, urdf: str, *, package_dirs: Sequence[str] = (),
              server: bool, zmq_url: str | None, snapshot_style: bool,
              host: str = LOCAL_HOST, colors: str = "urdf") -> None:  # fmt: skip
        """Create the visualizer and load the model's visual geometry (parsed from ``urdf``).

        Args:
            model: the Pinocchio model the bodies follow (mimic joints included).
            urdf: URDF text with the visual geometry.
            package_dirs: folders that resolve ``package://`` mesh paths.
            server: start a local Meshcat server (:func:`rcm_pin.viz.server.start_server`:
                it dies with this process).
            zmq_url: connect to a running local server instead.
            snapshot_style: white background, no grid or axes.
            host: the address the started server's web viewer listens on (127.0.0.1).
            colors: body colours (:func:`rcm_pin.viz.palette.paint`).
        """
        check_mode(colors)
        if zmq_url is not None:
            check_zmq_url(zmq_url)
        proc = None
        if zmq_url is None and server:
            proc, zmq_url, _ = start_server(host)
        if zmq_url is not None:
            with contextlib.redirect_stdout(io.StringIO()):  # meshcat prints the URL
                self.vis = meshcat.Visualizer(zmq_url=zmq_url)
            self.vis.window.server_proc = proc  # close() stops it
        else:
            self.vis = meshcat.Visualizer(window=SceneRecorder())
        visual = pin.buildGeomFromUrdfString(  # meshes it cannot draw: warned, left out
            model, drawable_urdf(urdf), pin.GeometryType.VISUAL, package_dirs=list(package_dirs)
        )
        paint(visual, colors)
        # No collision model: with the visual one as collision model Pinocchio loaded every
        # mesh a second time under .../collisions (hidden, but sent and exported: an arm's
        # page was twice as large).
        self.viz = MeshcatVisualizer(model, None, visual)
        self.viz.initViewer(viewer=self.vis)
        self.viz.loadViewerModel(rootNodeName="pinocchio")
        for i in repainted_meshes(visual, colors):  # mesh files in the body colour
            obj = visual.geometryObjects[i]
            node = self.vis[self.viz.getViewerNodeName(obj, pin.GeometryType.VISUAL)]
            material = mg.MeshPhongMaterial(color=hex_color(obj.meshColor))
            node.set_object(mg.TriangularMeshGeometry(*mesh_arrays(obj)), material)
        if snapshot_style:  # white background, no grid or axes (for pictures)
            self.vis["/Background"].set_property("top_color", [1.0, 1.0, 1.0])
            self.vis["/Background"].set_property("bottom_color", [1.0, 1.0, 1.0])
            self.vis["/Grid"].set_property("visible", False)
            self.vis["/Axes"].set_property("visible", False)

    @property
    def url(self) -> str | None:
        """Web address of the live viewer (None for an in-memory scene)."""
        return None if isinstance(self.vis.window, SceneRecorder) else self.vis.url()

    # ---------------------------------------------------------------- motion
    def placements(self, q: np.ndarray) -> dict[str, np.ndarray]:
        """World placement (4x4) of each visual node at ``q`` (defined by subclasses)."""
        raise NotImplementedError

    def _record_animation(
        self, configs: np.ndarray, dt: float, overlays: Callable[[np.ndarray], dict[str, Any]]
    ) -> Animation:
        """One animation frame per configuration: every body, plus the overlay transforms.

        Args:
            configs: (N, n) configurations, in the form :meth:`placements` takes.
            dt: time between frames [s].
            overlays: q -> {overlay name: 4x4 transform} for the nodes under ``OVERLAYS``.

        Raises:
            InvalidInputError: ``dt`` not positive.
        """
        if not dt > 0.0:
            raise InvalidInputError(f"dt = {dt}; valid: a positive time step [s]")
        anim = Animation(default_framerate=max(1, round(1.0 / dt)))
        for i, q in enumerate(configs):
            frame = anim.at_frame(self.vis, i)
            for node, T in self.placements(q).items():
                frame[node].set_transform(T)
            for name, T in overlays(q).items():
                frame[f"{OVERLAYS}/{name}"].set_transform(T)
        return anim

    # ---------------------------------------------------------------- camera
    def set_camera(self, eye: np.ndarray, target: np.ndarray) -> None:
        """Place the camera at ``eye`` looking at ``target`` (world coordinates [m])."""
        eye, target = np.asarray(eye, dtype=float), np.asarray(target, dtype=float)
        self.camera = (eye, target)
        shift = pin.SE3(np.eye(3), -target).homogeneous
        for path in ("/meshcat", "/Grid", "/Axes"):
            self.vis[path].set_transform(shift)
        camera = self.vis["/Cameras/default/rotated/<object>"]
        camera.set_property("fov", FOV_DEG)
        camera.set_property("position", meshcat_position(eye, target))

    # ---------------------------------------------------------------- export
    def static_html(self, controls: bool = True) -> str:
        """The scene (and animation) as one self-contained HTML page.

        Args:
            controls: keep Meshcat's "Open Controls" panel (False hides it, for pictures).
        """
        html = str(self.vis.static_html())
        if not controls:
            html = html.replace("</body>", "<style>.dg {display: none !important;}</style></body>")
        return html

    def scene_commands(self) -> list[bytes]:
        """The packed Meshcat commands of an in-memory scene (and animation), for pages of
        several viewers (:func:`rcm_pin.viz.scene.panes_html`).

        Raises:
            InvalidInputError: the scene lives in a ``meshcat-server`` (use
                :meth:`static_html`).
        """
        window = self.vis.window
        if not isinstance(window, SceneRecorder):
            raise InvalidInputError(
                "scene_commands needs an in-memory scene; valid: Viewer(mech, server=False)"
            )
        return window.commands()

    def save_html(self, path: str | Path, controls: bool = True) -> Path:
        """Write :meth:`static_html` to ``path``; returns the path."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(self.static_html(controls))
        return path

    def close(self) -> None:
        """Stop the server process this viewer started (no-op for in-memory scenes)."""
        window = self.vis.window
        proc = getattr(window, "server_proc", None)
        if proc is not None:
            stop_server(proc)
        socket = getattr(window, "zmq_socket", None)
        if socket is not None:
            socket.close(linger=0)

    def __enter__(self: _Scene) -> _Scene:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
