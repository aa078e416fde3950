"""Meshcat visualisation of any :class:`~rcm_pin.model.mechanism.Mechanism`.

One :class:`Viewer` for serial and closed mechanisms. It wraps Pinocchio's
``MeshcatVisualizer`` on the *mimic* model (visual geometry parsed with
``pin.buildGeomFromUrdfString(mech.model, ...)``, ``package://`` meshes found in
the folders of :func:`rcm_pin.viz.assets.assets`), so transmission bodies follow their
primary joints and the arms of example-robot-data show their meshes. It shows a
configuration (Mechanism coordinates; for a closed mechanism a full closed configuration),
or the configuration of an input vector (:meth:`Viewer.display_inputs`: coordinates of a
serial mechanism, drive values of a closed one, whose loops are closed by
:func:`rcm_pin.forward`), animates trajectories, draws the markers of
:mod:`rcm_pin.viz.overlays` and coloured point sets, and exports a self-contained static
HTML page.

By default the scene lives in memory (:class:`rcm_pin.viz.scene.SceneRecorder`): no
process, no port, no browser, same HTML as ``meshcat-server`` writes. With
``server=True`` a local ``meshcat-server`` is started (zmq and web server on 127.0.0.1
only); open :attr:`Viewer.url` in a browser. The camera looks at the bodies' centre,
from above the plane for a planar mechanism (:func:`rcm_pin.model.loops.plane_normal`).
"""

from __future__ import annotations

import time
import warnings

import numpy as np
import pinocchio as pin

with warnings.catch_warnings():  # meshcat imports pyzmq's deprecated zmq.eventloop.ioloop
    warnings.simplefilter("ignore", DeprecationWarning)
    from meshcat.animation import Animation

from rcm_pin.errors import InvalidInputError
from rcm_pin.model.constraints import plane_normal
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.viz import overlays as ov
from rcm_pin.viz.assets import assets
from rcm_pin.viz.base import OVERLAYS, MeshcatScene
from rcm_pin.viz.camera import box_corners, frame_points, plane_basis, project
from rcm_pin.viz.explain import PLAIN, ExplainMixin, SceneStyle
from rcm_pin.viz.server import LOCAL_HOST

#: Camera direction for planar mechanisms in (u, w, n) of the plane (mostly from above).
PLANAR_VIEW = np.array([0.2, -0.7, 1.0])


def view_direction(mech: Mechanism) -> np.ndarray | None:
    """Camera direction from above the plane of a planar mechanism (None: not planar)."""
    n = plane_normal(mech.model)
    return None if n is None else plane_basis(n) @ PLANAR_VIEW


class Viewer(ExplainMixin, ov.OverlaysMixin, MeshcatScene):
    """A Meshcat scene of one mechanism (module docstring).

    Args:
        mech: any mechanism (serial, closed, with or without an RCM).
        server: start a local ``meshcat-server`` (True) or record in memory (False).
        zmq_url: connect to an already running local server instead (127.0.0.1 only).
        host: with ``server``: the address its web viewer listens on (default 127.0.0.1,
            this machine only).
        snapshot_style: white background and no grid (for screenshots).
        markers: draw the default markers (:func:`rcm_pin.viz.overlays.point_markers`,
            and the insertion axis where there is an RCM).
        style: body colours and what else to draw (:class:`rcm_pin.viz.explain.SceneStyle`:
            by default the URDF's materials, each body without one its own colour, and no
            base plate, triads or drive markers; ``EXPLAINED`` draws them all).

    Attributes:
        mech: the mechanism.
        vis: the ``meshcat.Visualizer`` (root path ``/meshcat``).
        viz: Pinocchio's ``MeshcatVisualizer`` on the mimic model.
        q: the configuration shown last (Mechanism coordinates).
        assembly: label of the configuration shown (``home``, an assembly-mode label, ...).
        camera: (eye, target) world positions set by :meth:`set_camera` [m].

    Raises:
        InvalidInputError: ``zmq_url`` not on 127.0.0.1.
    """

    def __init__(self, mech: Mechanism, *, server: bool = False, zmq_url: str | None = None,
                 snapshot_style: bool = False, markers: bool = True,
                 host: str = LOCAL_HOST, style: SceneStyle = PLAIN) -> None:  # fmt: skip
        self.mech = mech
        self._open(mech.model, mech.urdf, package_dirs=list(assets(mech).mesh_dirs(mech)),
                   server=server, zmq_url=zmq_url, snapshot_style=snapshot_style,
                   host=host, colors=style.colors)  # fmt: skip
        self._data = mech.model.createData()
        self._points: dict[str, int] = {}
        self._decor = {}
        self._span: tuple[float, float] | None = None
        self.q, self.assembly = mech.home, "home"  # the one rule: rcm_pin.model.configurations
        if markers:
            self.show_markers()
            if mech.rcm is not None:
                self.show_tool_axis()
        self.display(self.q)
        self.show_style(style)
        self.fit_camera()

    # ------------------------------------------------------------------ state
    @property
    def inputs(self) -> np.ndarray:
        """Input vector of the configuration shown: drives (closed) or coordinates."""
        loops = self.mech.loops
        return self.q[loops.drive_q].copy() if loops is not None else self.q.copy()

    def display(self, q: np.ndarray) -> None:
        """Place every body (mimic bodies included) at coordinates ``q`` (no closure solve).

        Raises:
            InvalidInputError: wrong shape or non-finite entries.
        """
        self.q = self.mech.check_q(q).copy()
        self.viz.display(self.mech.to_pin(self.q))
        for name, T in self._overlay_transforms(self.q).items():
            self.vis[f"{OVERLAYS}/{name}"].set_transform(T)

    def display_inputs(self, inputs: np.ndarray, assembly: int = 0) -> np.ndarray:
        """Show the configuration of an input vector: assembly mode ``assembly`` of
        ``rcm_pin.forward(mech, inputs, all_modes=True)``.

        Args:
            inputs: drive values (closed) or coordinates (serial) [rad, m].
            assembly: index into the assembly modes found (0: the first).

        Returns:
            The coordinates shown (n,).

        Raises:
            InvalidInputError: bad inputs, or ``assembly`` out of range (the message
                gives the valid range).
            UnreachablePoseError: closed: the drives admit no assembly.
        """
        from rcm_pin.analysis.position import forward

        result = forward(self.mech, inputs, all_modes=True)
        if self.mech.loops is None and assembly != 0:
            raise InvalidInputError(
                f"assembly {assembly}: {self.mech.name} has no loop closures (its inputs "
                "give one configuration); valid: 0"
            )
        if not 0 <= assembly < result.count:
            raise InvalidInputError(
                f"assembly {assembly} out of range; valid: 0..{result.count - 1} "
                f"({result.count} assembly modes for these drives)"
            )
        sol = result.solutions[assembly]
        self.display(sol.q)
        self.assembly = sol.mode
        return sol.q

    def _kinematics(self, q: np.ndarray) -> tuple[pin.Data, pin.GeometryData]:
        """Fresh joint and geometry data at coordinates q (the displayed data untouched)."""
        viz = self.viz
        data, gdata = viz.model.createData(), viz.visual_model.createData()
        pin.forwardKinematics(viz.model, data, self.mech.to_pin(self.mech.check_q(q)))
        pin.updateGeometryPlacements(viz.model, data, viz.visual_model, gdata)
        return data, gdata

    def placements(self, q: np.ndarray) -> dict[str, np.ndarray]:
        """World placement (4x4) of each visual geometry node at ``q``, by node name."""
        viz, gdata = self.viz, self._kinematics(q)[1]
        return {
            viz.getViewerNodeName(obj, pin.GeometryType.VISUAL): gdata.oMg[i].homogeneous
            for i, obj in enumerate(viz.visual_model.geometryObjects)
        }

    def cut_frames(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """World positions (frame a, frame b) of each closure, as displayed.

        Read from the data Pinocchio's visualizer filled when it displayed :attr:`q`
        (``viz.data.oMi`` times each cut frame's placement); empty without loops.
        """
        closures = self.mech.loops.closures if self.mech.loops is not None else ()
        model, data = self.viz.model, self.viz.data
        return [
            (ov.frame_point(model, data, c.frame_a_id)[:3, 3],
             ov.frame_point(model, data, c.frame_b_id)[:3, 3])
            for c in closures
        ]  # fmt: skip

    def closure_gap(self) -> float:
        """Largest distance between the two cut frames of a closure, as displayed [m]
        (0 without loops)."""
        return max((float(np.linalg.norm(a - b)) for a, b in self.cut_frames()), default=0.0)

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
            qs: (N, n) configurations (closed mechanisms: closed ones, e.g. from
                :meth:`input_path`), one per frame.
            dt: time between frames [s].
            repetitions: times the clip plays.
            play: start playing when the page opens.

        Returns:
            The ``meshcat.animation.Animation`` sent to the scene.

        Raises:
            InvalidInputError: wrong shape, non-finite entries or ``dt`` not positive.
        """
        traj = self._trajectory(qs)
        anim = self._record_animation(traj, dt, self._overlay_transforms)
        self.display(traj[0])
        self.vis.set_animation(anim, play=play, repetitions=repetitions)
        return anim

    def input_path(self, inputs: np.ndarray) -> np.ndarray:
        """Configurations (N, n) of rows of inputs: the rows themselves (serial), or the
        closed configurations followed by continuation from :attr:`q` (closed;
        :func:`rcm_pin.analysis.closed_position.direct_position_path`)."""
        if self.mech.loops is None:
            return self._trajectory(inputs)
        from rcm_pin.analysis.closed_position import direct_position_path

        return direct_position_path(self.mech, inputs, self.q)

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
        """Aim the camera at the centre of the bounding box of the bodies and markers at the
        current q (:meth:`scene_points`; not the base plate) and fit them.

        Args:
            direction: from the centre towards the camera (default: from above the plane
                of a planar mechanism, else ``VIEW_DIRECTION``).
            margin: distance factor (> 1 leaves more room around the bodies).
            extra: (N, 3) further world points to keep in view (e.g. workspace samples).
        """
        corners = [np.reshape(extra, (-1, 3))] if extra is not None else []
        corners.append(self.scene_points(self.q, ground=True))
        view = direction if direction is not None else view_direction(self.mech)
        self.set_camera(*frame_points(np.vstack(corners), view, margin))

    def scene_points(self, q: np.ndarray, ground: bool = False) -> np.ndarray:
        """World points (N, 3) [m] that bound the scene at q: joint origins, the corners of
        every visual object's box, the markers (both ends of the insertion-axis rod), the
        decorations' origins, and with ``ground`` the base plate's corners."""
        data, gdata = self._kinematics(q)
        corners = [np.array([M.translation for M in data.oMi])]
        overlays = self._overlay_transforms(q)
        for name, T in overlays.items():
            if name != "ground":
                corners.append(T[None, :3, 3])
            elif ground:
                corners.append(self._decor[name].mesh.placed(T).vertices)
        if self._span is not None:  # both ends of the insertion-axis rod
            T, (lo, hi) = overlays["tool_axis"], self._span
            corners.append(T[:3, 3] + np.outer([-0.5, 0.5], (hi - lo) * T[:3, 1]))
        for i, obj in enumerate(self.viz.visual_model.geometryObjects):
            obj.geometry.computeLocalAABB()
            box = obj.geometry.aabb_local
            corners.append(box_corners(box.min_, box.max_, gdata.oMg[i].homogeneous))
        return np.vstack(corners)

    def project(self, points: np.ndarray, size: tuple[int, int] = (800, 600)) -> np.ndarray:
        """Pixel coordinates (N, 2) (column, row) of world points in a picture of ``size``."""
        return project(*self.camera, points, size)
