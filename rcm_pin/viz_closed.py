"""Meshcat scenes of closed-loop mechanisms, shown assembled.

A :class:`ClosedViewer` displays the cut-open tree of a
:class:`~rcm_pin.closed_loop.ClosedMechanism` (Pinocchio's ``MeshcatVisualizer`` on the
tree model, visual geometry from the same URDF) at a *closed* configuration: the drive
angles are given, the passive joints come from the direct position problem
(:func:`rcm_pin.closed_loop.direct_position`, closure residual < 1e-12 m), so every cut
pair lands on its partner and the loops look closed. Small spheres mark the cut points
(frame a and frame b of each closure; they coincide) and the output frame.

Scenes live in memory (:class:`rcm_pin.viz_scene.SceneRecorder`) unless ``server=True``,
and export to the same self-contained static HTML as :class:`rcm_pin.viz.Viewer`.
"""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin

with warnings.catch_warnings():  # meshcat imports pyzmq's deprecated zmq.eventloop.ioloop
    warnings.simplefilter("ignore", DeprecationWarning)
    import meshcat.geometry as mg
    from meshcat.animation import Animation

from rcm_pin.closed_loop.core import ClosedMechanism
from rcm_pin.closed_loop.position import direct_position
from rcm_pin.errors import InvalidInputError
from rcm_pin.viz_base import OVERLAYS, MeshcatScene
from rcm_pin.viz_camera import box_corners, frame_points
from rcm_pin.viz_scene import hex_color

#: Camera direction for planar mechanisms (mostly from above the xy plane).
PLANAR_VIEW = np.array([0.2, -0.7, 1.0])


class ClosedViewer(MeshcatScene):
    """A Meshcat scene of one closed mechanism, displayed assembled.

    Args:
        mech: the closed mechanism.
        urdf: its URDF text (default: re-rendered from the catalogue with ``xacro_args``).
        xacro_args: xacro arguments used to render the URDF when ``urdf`` is None.
        server: start a local ``meshcat-server`` (127.0.0.1) instead of an in-memory scene.
        snapshot_style: white background, no grid or axes.

    Attributes:
        q: full tree configuration (n,) shown last [rad] (closed: residual < 1e-12 m).
        q_drives: its drive angles (k,) [rad].
        assembly: label of the assembly mode shown.
    """

    def __init__(self, mech: ClosedMechanism, urdf: str | None = None, *,
                 xacro_args: dict[str, Any] | None = None, server: bool = False,
                 snapshot_style: bool = False) -> None:  # fmt: skip
        from rcm_pin.closed_loop.loader import render_closed

        self.mech = mech
        if urdf is None:
            urdf = render_closed(mech.name, **(xacro_args or {}))[0]
        self._open(mech.model, urdf, server=server, zmq_url=None, snapshot_style=snapshot_style)
        self._markers()
        first = direct_position_home(mech)
        self.q, self.q_drives, self.assembly = first, first[mech.idx_driven], "home"
        self.display_full(first)
        self.fit_camera()

    # ------------------------------------------------------------------ state
    def display(self, q_drives: np.ndarray, assembly: int = 0) -> np.ndarray:
        """Solve the direct position problem for the drives and show assembly mode ``assembly``.

        Args:
            q_drives: drive angles (k,) [rad].
            assembly: index into the assembly modes found (0: the first).

        Returns:
            The full configuration shown (n,) [rad].

        Raises:
            InvalidInputError: bad drives, or ``assembly`` out of range (message lists the count).
            UnreachablePoseError: the drives admit no assembly.
        """
        result = direct_position(self.mech, q_drives, all_modes=True)
        if not 0 <= assembly < result.count:
            raise InvalidInputError(
                f"assembly {assembly} out of range; valid: 0..{result.count - 1} "
                f"({result.count} assembly modes for these drives)"
            )
        sol = result.solutions[assembly]
        self.display_full(sol.q)
        self.assembly = sol.mode
        return sol.q

    def display_full(self, q: np.ndarray) -> None:
        """Show a full tree configuration (n,) as given (no closure solve)."""
        q = self.mech.check_q(q, self.mech.model.nq, "q")
        self.q, self.q_drives = q.copy(), q[self.mech.idx_driven].copy()
        self.viz.display(q)
        for name, T in self._marker_transforms().items():
            self.vis[f"{OVERLAYS}/{name}"].set_transform(T)

    def cut_frames(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """World positions (frame a, frame b) of each closure, from the displayed placements.

        Uses the data Pinocchio's visualizer filled when it displayed :attr:`q`
        (``viz.data.oMi`` times each cut frame's placement on its parent joint).
        """
        model, data = self.viz.model, self.viz.data
        out = []
        for c in self.mech.closures:
            pts = []
            for name in (c.frame_a, c.frame_b):
                f = model.frames[model.getFrameId(name)]
                pts.append((data.oMi[f.parentJoint] * f.placement).translation.copy())
            out.append((pts[0], pts[1]))
        return out

    def closure_gap(self) -> float:
        """Largest distance between the two cut frames of a closure, as displayed [m]."""
        return max(float(np.linalg.norm(a - b)) for a, b in self.cut_frames())

    def placements(self, q: np.ndarray) -> dict[str, np.ndarray]:
        """World placement (4x4) of each visual geometry node at full configuration ``q``."""
        viz = self.viz
        data, gdata = viz.model.createData(), viz.visual_model.createData()
        pin.forwardKinematics(viz.model, data, np.asarray(q, dtype=float))
        pin.updateGeometryPlacements(viz.model, data, viz.visual_model, gdata)
        return {
            viz.getViewerNodeName(obj, pin.GeometryType.VISUAL): gdata.oMg[i].homogeneous
            for i, obj in enumerate(viz.visual_model.geometryObjects)
        }

    # --------------------------------------------------------------- overlays
    def _marker_names(self) -> list[tuple[str, str]]:
        out = []
        for i, c in enumerate(self.mech.closures):
            out += [(f"cut_{i}_a", c.frame_a), (f"cut_{i}_b", c.frame_b)]
        return out + [("output", self.mech.output_frame)]

    def _markers(self, radius: float = 0.008) -> None:
        for name, _ in self._marker_names():
            colour = (0.1, 0.6, 0.2) if name == "output" else (0.9, 0.1, 0.1)
            material = mg.MeshPhongMaterial(color=hex_color(colour), transparent=True, opacity=0.6)
            self.vis[f"{OVERLAYS}/{name}"].set_object(mg.Sphere(radius), material)

    def _marker_transforms(self, q: np.ndarray | None = None) -> dict[str, np.ndarray]:
        model = self.mech.model
        data = model.createData()
        pin.forwardKinematics(model, data, self.q if q is None else q)
        out = {}
        for name, frame in self._marker_names():
            f = model.frames[model.getFrameId(frame)]
            p = (data.oMi[f.parentJoint] * f.placement).translation
            out[name] = pin.SE3(np.eye(3), p).homogeneous
        return out

    # ---------------------------------------------------------------- motion
    def animate(self, qs: np.ndarray, dt: float = 0.05, *, repetitions: int = 1,
                play: bool = True) -> Animation:  # fmt: skip
        """Record an animation of full closed configurations ``qs`` (N, n), e.g. from
        :func:`rcm_pin.closed_loop.direct_position_path`."""
        arr = np.asarray(qs, dtype=float)
        if arr.ndim != 2 or arr.shape[1] != self.mech.model.nq or not np.all(np.isfinite(arr)):
            raise InvalidInputError(
                f"trajectory has shape {arr.shape}; valid: (N, {self.mech.model.nq}) finite values"
            )
        anim = self._record_animation(arr, dt, self._marker_transforms)
        self.display_full(arr[0])
        self.vis.set_animation(anim, play=play, repetitions=repetitions)
        return anim

    # ---------------------------------------------------------------- camera
    def fit_camera(self, direction: np.ndarray | None = None, margin: float = 1.05) -> None:
        """Aim the camera at the bodies' bounding-box centre and fit them in view."""
        placements = self.placements(self.q)
        corners = [np.array([M.translation for M in self.viz.data.oMi])]
        for obj in self.viz.visual_model.geometryObjects:
            obj.geometry.computeLocalAABB()
            box = obj.geometry.aabb_local
            T = placements[self.viz.getViewerNodeName(obj, pin.GeometryType.VISUAL)]
            corners.append(box_corners(box.min_, box.max_, T))
        view = PLANAR_VIEW if self.mech.plane_normal is not None else None
        eye, target = frame_points(np.vstack(corners), direction if direction is not None else view,
                                   margin)  # fmt: skip
        self.set_camera(eye, target)


def direct_position_home(mech: ClosedMechanism) -> np.ndarray:
    """A closed configuration to start from: the first working mode at the home pose.

    3-RRR: platform at the origin, φ = 0; five-bar: P on the symmetry axis at 60 % of the
    reach (both in the middle of the workspace).
    """
    from rcm_pin.closed_loop.position import inverse_position

    if mech.name.startswith("planar_3rrr"):
        pose = np.zeros(3)
    else:
        reach = float(mech.params["proximal_1"] + mech.params["distal_1"])
        pose = np.array([0.0, 0.6 * reach])
    return inverse_position(mech, pose).solutions[0].q


def snapshot_closed(viewer: ClosedViewer, png: str | Path, size: tuple[int, int] = (800, 600),
                    browser: bool = True) -> str:  # fmt: skip
    """PNG of the scene: headless Chromium if present, else a matplotlib drawing of the links.

    Returns:
        ``"chromium"`` or ``"matplotlib"``.
    """
    import tempfile

    from rcm_pin.errors import SnapshotError
    from rcm_pin.viz_snapshot import find_chromium, screenshot_html

    if browser and find_chromium() is not None:
        with tempfile.TemporaryDirectory(prefix="rcm_pin_scene_") as tmp:
            page = viewer.save_html(Path(tmp) / "scene.html", controls=False)
            try:
                screenshot_html(page, png, size)
                return "chromium"
            except SnapshotError:
                pass
    _links_png(viewer, png)
    return "matplotlib"


def _links_png(viewer: ClosedViewer, png: str | Path) -> Path:
    """Matplotlib drawing (xy plane) of the joint origins, their links and the cut points."""
    from matplotlib.figure import Figure

    model, data = viewer.mech.model, viewer.viz.data
    fig = Figure(figsize=(6.4, 4.8), dpi=100)
    ax = fig.add_subplot()
    origins = np.array([data.oMi[j].translation for j in range(model.njoints)])
    for j in range(1, model.njoints):
        ax.plot(*origins[[model.parents[j], j], :2].T, "-o", color="tab:orange", lw=2, ms=4)
    for c, (a, b) in zip(viewer.mech.closures, viewer.cut_frames(), strict=True):
        for name, p in ((c.frame_a, a), (c.frame_b, b)):
            parent = model.frames[model.getFrameId(name)].parentJoint
            ax.plot(*np.c_[origins[parent, :2], p[:2]], "-", color="tab:orange", lw=2)
        ax.scatter(a[0], a[1], color="r", s=30, zorder=3)
    ax.set(aspect="equal", xlabel="x [m]", ylabel="y [m]")
    ax.set_title(f"{viewer.mech.name}: joints and cut points (matplotlib fallback)")
    png = Path(png)
    png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(png)
    return png
