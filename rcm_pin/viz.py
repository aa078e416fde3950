"""Meshcat visualisation of a :class:`~rcm_pin.mechanism.Mechanism`.

A :class:`Viewer` wraps Pinocchio's ``MeshcatVisualizer`` built on the *mimic* model
(visual geometry parsed with ``pin.buildGeomFromUrdfString(mech.model, ...)``, so
transmission bodies follow their primary joints). It shows a configuration, animates a
trajectory, draws the RCM point, the tool axis and coloured point sets (workspace
samples, singularity measures), and exports a self-contained static HTML page.

By default the scene lives in memory (:class:`rcm_pin.viz_scene.SceneRecorder`): no
process, no port, no browser, same HTML as ``meshcat-server`` writes. With
``server=True`` a local ``meshcat-server`` is started (zmq and web server on 127.0.0.1
only); open :attr:`Viewer.url` in a browser.

The camera looks at the mechanism's centre: Meshcat 0.3.2 always aims its orbit camera
at the world origin, so the whole scene (``/meshcat``, grid and axes) is shifted by the
negated centre. Coordinates inside the scene are unaffected.
"""

from __future__ import annotations

import time
import warnings
from typing import Any

import numpy as np
import pinocchio as pin

with warnings.catch_warnings():  # meshcat imports pyzmq's deprecated zmq.eventloop.ioloop
    warnings.simplefilter("ignore", DeprecationWarning)
    import meshcat.geometry as mg
    from meshcat.animation import Animation

from rcm_pin.errors import InvalidInputError
from rcm_pin.kinematics import OUTPUT_LINK_FRAME
from rcm_pin.mechanism import Mechanism
from rcm_pin.viz_base import OVERLAYS, MeshcatScene
from rcm_pin.viz_camera import box_corners, frame_points, project
from rcm_pin.viz_scene import colormap, hex_color


class Viewer(MeshcatScene):
    """A Meshcat scene of one mechanism.

    Args:
        mech: the mechanism (RCM or any URDF-based :class:`Mechanism`).
        server: start a local ``meshcat-server`` (True) or record in memory (False).
        zmq_url: connect to an already running local server instead (127.0.0.1 only).
        snapshot_style: white background and no grid (for screenshots).

    Attributes:
        mech: the mechanism.
        vis: the ``meshcat.Visualizer`` (root path ``/meshcat``).
        viz: Pinocchio's ``MeshcatVisualizer`` on the mimic model.
        q: the configuration shown last (Mechanism coordinates).
        camera: (eye, target) world positions set by :meth:`set_camera` [m].

    Raises:
        InvalidInputError: ``zmq_url`` not on 127.0.0.1.
    """

    def __init__(self, mech: Mechanism, *, server: bool = False, zmq_url: str | None = None,
                 snapshot_style: bool = False) -> None:  # fmt: skip
        self.mech = mech
        self._open(mech.model, mech.urdf, server=server, zmq_url=zmq_url,
                   snapshot_style=snapshot_style)  # fmt: skip
        self._axis_frame = (
            mech.frame_id(OUTPUT_LINK_FRAME) if mech.model.existFrame(OUTPUT_LINK_FRAME) else -1
        )
        self._axis_shown = False
        self.q = np.clip(np.zeros(mech.nq), mech.lower, mech.upper)
        self.display(self.q)
        self.fit_camera()

    # ------------------------------------------------------------------ state
    def display(self, q: np.ndarray) -> None:
        """Place every body (mimic bodies included) at configuration ``q``."""
        self.q = self.mech.check_q(q).copy()
        self.viz.display(self.mech.to_pin(self.q))
        if self._axis_shown:
            self.vis[f"{OVERLAYS}/tool_axis"].set_transform(self._axis_transform())

    def placements(self, q: np.ndarray) -> dict[str, np.ndarray]:
        """World placement (4x4) of each visual geometry node at ``q``, by node name."""
        q_pin = self.mech.to_pin(self.mech.check_q(q))
        viz = self.viz
        pin.forwardKinematics(viz.model, viz.data, q_pin)
        pin.updateGeometryPlacements(viz.model, viz.data, viz.visual_model, viz.visual_data)
        return {
            viz.getViewerNodeName(obj, pin.GeometryType.VISUAL): viz.visual_data.oMg[i].homogeneous
            for i, obj in enumerate(viz.visual_model.geometryObjects)
        }

    # --------------------------------------------------------------- overlays
    def show_rcm(self, radius: float = 0.008, color: Any = (0.9, 0.1, 0.1)) -> None:
        """A translucent sphere at the remote centre A (the ``rcm`` frame)."""
        if self.mech.rcm_frame_id < 0:
            raise InvalidInputError(f"{self.mech.name} has no RCM frame; valid: rcm_* mechanisms")
        material = mg.MeshPhongMaterial(color=hex_color(color), transparent=True, opacity=0.5)
        node = self.vis[f"{OVERLAYS}/rcm"]
        node.set_object(mg.Sphere(radius), material)
        pin.forwardKinematics(self.mech.model, self.mech.data, self.mech.to_pin(self.q))
        oMa = pin.updateFramePlacement(self.mech.model, self.mech.data, self.mech.rcm_frame_id)
        node.set_transform(pin.SE3(np.eye(3), oMa.translation).homogeneous)

    def show_tool_axis(self, radius: float = 0.0015, color: Any = (0.1, 0.7, 0.2)) -> None:
        """The output axis e4 as a thin rod from behind A to beyond full insertion.

        It follows later :meth:`display` and :meth:`animate` calls.

        Raises:
            InvalidInputError: the mechanism has no ``output_link`` frame.
        """
        if self._axis_frame < 0:
            raise InvalidInputError(f"{self.mech.name} has no {OUTPUT_LINK_FRAME} frame")
        lo, hi = self._axis_span()
        self.vis[f"{OVERLAYS}/tool_axis"].set_object(
            mg.Cylinder(hi - lo, radius), mg.MeshPhongMaterial(color=hex_color(color))
        )
        self._axis_shown = True
        self.display(self.q)

    def _axis_span(self) -> tuple[float, float]:
        reach = float(self.mech.upper[2]) if self.mech.nq >= 3 else 0.1
        return -0.03, reach + 0.04

    def _axis_transform(self) -> np.ndarray:
        """Output-link frame placed so the rod's y axis (Meshcat) lies along e4."""
        m, d = self.mech.model, self.mech.data
        pin.forwardKinematics(m, d, self.mech.to_pin(self.q))
        oMo = pin.updateFramePlacement(m, d, self._axis_frame)
        a = oMo.actInv(pin.updateFramePlacement(m, d, max(self.mech.rcm_frame_id, 0)).translation)
        lo, hi = self._axis_span()
        local = pin.SE3(pin.rpy.rpyToMatrix(np.pi / 2, 0.0, 0.0), a + [0, 0, (lo + hi) / 2])
        return np.asarray((oMo * local).homogeneous)

    def show_points(self, name: str, points: np.ndarray, values: np.ndarray | None = None, *,
                    color: Any = (0.2, 0.4, 0.9), size: float = 0.004,
                    cmap: str = "viridis") -> None:  # fmt: skip
        """Draw a point set, coloured by ``values`` through ``cmap`` or in one ``color``.

        Args:
            name: scene node name under ``overlays/`` (re-using a name replaces the set).
            points: (N, 3) world positions [m] (e.g. tool-centre workspace samples).
            values: (N,) scalars (e.g. a singularity measure); None for one colour.
            color: RGB in [0, 1] used without ``values``.
            size: point size [m].
            cmap: matplotlib colormap name for ``values``.

        Raises:
            InvalidInputError: wrong shapes or non-finite positions.
        """
        p = np.asarray(points, dtype=float)
        if p.ndim != 2 or p.shape[1] != 3 or not np.all(np.isfinite(p)):
            raise InvalidInputError(f"points have shape {p.shape}; valid: (N, 3) finite values")
        if values is not None and np.asarray(values).shape != (len(p),):
            raise InvalidInputError(
                f"values have shape {np.asarray(values).shape}; valid: ({len(p)},)"
            )
        rgb = colormap(values, cmap) if values is not None else np.tile(color, (len(p), 1))
        geometry = mg.PointsGeometry(p.T.astype(np.float32), rgb.T.astype(np.float32))
        self.vis[f"{OVERLAYS}/{name}"].set_object(mg.Points(geometry, mg.PointsMaterial(size)))

    def show_tool_positions(self, name: str, qs: np.ndarray, values: np.ndarray | None = None,
                            **kwargs: Any) -> np.ndarray:  # fmt: skip
        """Draw the tool centres of configurations ``qs`` (N, n); returns them (N, 3)."""
        from rcm_pin.kinematics import tool_poses

        points = tool_poses(self.mech, qs)[:, :3, 3]
        self.show_points(name, points, values, **kwargs)
        return points

    # ---------------------------------------------------------------- motion
    def play(self, qs: np.ndarray, dt: float = 0.05) -> None:
        """Step through configurations (live viewers sleep ``dt`` between frames)."""
        live = self.url is not None
        for q in self._trajectory(qs):
            self.display(q)
            if live:
                time.sleep(dt)

    def animate(self, qs: np.ndarray, dt: float = 0.05, *, repetitions: int = 1,
                play: bool = True) -> Animation:  # fmt: skip
        """Record a Meshcat animation of a trajectory; it is part of :meth:`static_html`.

        Args:
            qs: (N, n) configurations, one per frame.
            dt: time between frames [s].
            repetitions: times the clip plays.
            play: start playing when the page opens.

        Returns:
            The ``meshcat.animation.Animation`` sent to the scene.
        """
        traj = self._trajectory(qs)

        def tool_axis(q: np.ndarray) -> dict[str, np.ndarray]:
            if not self._axis_shown:
                return {}
            self.q = q  # _axis_transform reads the configuration shown
            return {"tool_axis": self._axis_transform()}

        anim = self._record_animation(traj, dt, tool_axis)
        self.display(traj[0])
        self.vis.set_animation(anim, play=play, repetitions=repetitions)
        return anim

    def _trajectory(self, qs: np.ndarray) -> np.ndarray:
        arr = np.asarray(qs, dtype=float)
        if arr.ndim != 2 or arr.shape[1] != self.mech.nq or not np.all(np.isfinite(arr)):
            raise InvalidInputError(
                f"trajectory has shape {arr.shape}; valid: (N, {self.mech.nq}) finite values"
            )
        return arr

    # ---------------------------------------------------------------- camera
    def fit_camera(self, direction: np.ndarray | None = None, margin: float = 1.0,
                   extra: np.ndarray | None = None) -> None:  # fmt: skip
        """Aim the camera at the bodies' bounding-box centre at the current q and fit them.

        Args:
            direction: from the centre towards the camera (default ``VIEW_DIRECTION``).
            margin: distance factor (> 1 leaves more room around the bodies).
            extra: (N, 3) further world points to keep in view (e.g. workspace samples).
        """
        corners = [np.reshape(extra, (-1, 3))] if extra is not None else []
        placements = self.placements(self.q)  # also runs forward kinematics
        corners.append(np.array([M.translation for M in self.viz.data.oMi]))
        if self._axis_shown:  # both ends of the tool-axis rod
            T, (lo, hi) = self._axis_transform(), self._axis_span()
            corners.append(T[:3, 3] + np.outer([-0.5, 0.5], (hi - lo) * T[:3, 1]))
        for obj in self.viz.visual_model.geometryObjects:
            obj.geometry.computeLocalAABB()
            box = obj.geometry.aabb_local
            T = placements[self.viz.getViewerNodeName(obj, pin.GeometryType.VISUAL)]
            corners.append(box_corners(box.min_, box.max_, T))
        self.set_camera(*frame_points(np.vstack(corners), direction, margin))

    def project(self, points: np.ndarray, size: tuple[int, int] = (800, 600)) -> np.ndarray:
        """Pixel coordinates (N, 2) (column, row) of world points in a picture of ``size``."""
        return project(*self.camera, points, size)
