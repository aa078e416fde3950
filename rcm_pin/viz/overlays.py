"""What :class:`rcm_pin.viz.viewer.Viewer` draws over the bodies, decided from the data.

* the remote centre A (a translucent red sphere) and the insertion axis (a thin green rod
  along axis ``mech.rcm.axis`` of frame ``mech.rcm.axis_frame_id``) where ``mech.rcm`` is
  not None;
* both cut frames of every loop closure (red spheres; they coincide on a closed
  configuration);
* the output / tool point (a green sphere) where there is no insertion axis to show it;
* point sets (workspace samples, singularity measures), coloured by value.

The functions take Pinocchio data already filled by forward kinematics at the
configuration shown; :class:`OverlaysMixin` holds the viewer's ``show_*`` methods. None
tests a mechanism's name.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np
import pinocchio as pin

with warnings.catch_warnings():  # meshcat imports pyzmq's deprecated zmq.eventloop.ioloop
    warnings.simplefilter("ignore", DeprecationWarning)
    import meshcat.geometry as mg

from rcm_pin.errors import InvalidInputError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.viz.base import OVERLAYS
from rcm_pin.viz.scene import colormap, hex_color

#: Marker colours (RGB in [0, 1]).
RED, GREEN = (0.9, 0.1, 0.1), (0.1, 0.7, 0.2)
#: Colour and opacity of the point markers by name (cut points: red, opacity 0.6).
MARKER_STYLE: dict[str, tuple[tuple[float, float, float], float]] = {
    "rcm": (RED, 0.5),
    "output": (GREEN, 0.6),
}
#: Room left on the insertion-axis rod behind A and beyond the deepest tool centre [m].
AXIS_BEHIND, AXIS_BEYOND = 0.03, 0.04


def point_markers(mech: Mechanism) -> dict[str, int]:
    """Default point markers of a mechanism: overlay name -> frame id.

    ``rcm`` at A (when there is one), ``cut_<i>_a`` / ``cut_<i>_b`` at both frames of
    closure i, and ``output`` at the output frame when there is no insertion axis.
    """
    out: dict[str, int] = {}
    if mech.rcm is not None:
        out["rcm"] = mech.rcm.point_frame_id
    for i, c in enumerate(mech.loops.closures if mech.loops is not None else ()):
        out[f"cut_{i}_a"], out[f"cut_{i}_b"] = c.frame_a_id, c.frame_b_id
    if mech.rcm is None:
        out["output"] = mech.output.frame_id
    return out


def marker_radius(mech: Mechanism, q: np.ndarray, largest: float = 0.008) -> float:
    """Default marker radius [m]: ``largest``, or 4 % of the size of a smaller mechanism
    (diagonal of the box around every frame origin at coordinates q; where every frame
    origin is one point, e.g. a spherical mechanism's centre, the closures' length scale)."""
    data = mech.model.createData()
    pin.forwardKinematics(mech.model, data, mech.to_pin(q))
    pin.updateFramePlacements(mech.model, data)
    p = np.array([M.translation for M in data.oMf])
    size = float(np.linalg.norm(np.ptp(p, axis=0)))
    if size < 1e-9:  # all origins at one point: the size comes from the loops (or none)
        size = mech.loops.length_scale if mech.loops is not None else largest / 0.04
    return min(largest, 0.04 * size)


def sphere(radius: float, color: Any, opacity: float) -> tuple[Any, Any]:
    """A Meshcat sphere of ``radius`` [m] and its translucent material."""
    material = mg.MeshPhongMaterial(color=hex_color(color), transparent=True, opacity=opacity)
    return mg.Sphere(radius), material


def frame_point(model: pin.Model, data: pin.Data, frame_id: int) -> np.ndarray:
    """4×4 translation to a frame's origin (no rotation) from the joint placements in data."""
    f = model.frames[frame_id]
    p = (data.oMi[f.parentJoint] * f.placement).translation
    return np.asarray(pin.SE3(np.eye(3), p).homogeneous)


def axis_span(mech: Mechanism) -> tuple[float, float]:
    """Extent (lo, hi) of the insertion-axis rod along the axis, measured from A [m].

    From :data:`AXIS_BEHIND` behind A (or behind the shallowest tool centre) to
    :data:`AXIS_BEYOND` beyond the deepest one, the tool centre taken at the limit box's
    corners and the middle (infinite limits replaced by ±π).

    Raises:
        InvalidInputError: the mechanism has no RCM axis.
    """
    rcm = require_rcm(mech)
    lo = np.where(np.isfinite(mech.lower), mech.lower, -np.pi)
    hi = np.where(np.isfinite(mech.upper), mech.upper, np.pi)
    depths = []
    model, data = mech.model, mech.model.createData()
    for q in (lo, hi, 0.5 * (lo + hi)):
        pin.forwardKinematics(model, data, mech.to_pin(q))
        axis = pin.updateFramePlacement(model, data, rcm.axis_frame_id)
        a = pin.updateFramePlacement(model, data, rcm.point_frame_id).translation
        tool = pin.updateFramePlacement(model, data, mech.output.frame_id).translation
        depths.append(float((tool - a) @ axis.rotation[:, rcm.axis]))
    return min(0.0, *depths) - AXIS_BEHIND, max(0.0, *depths) + AXIS_BEYOND


def axis_transform(mech: Mechanism, data: pin.Data, span: tuple[float, float]) -> np.ndarray:
    """Placement (4×4) of the rod: its y axis (Meshcat cylinders) along the insertion axis,
    its centre on that axis, ``span`` measured from the foot of A on the axis.

    ``data`` holds the frame placements at the configuration shown.
    """
    rcm = require_rcm(mech)
    model = mech.model
    axis = pin.updateFramePlacement(model, data, rcm.axis_frame_id)
    a = pin.updateFramePlacement(model, data, rcm.point_frame_id).translation
    e = axis.rotation[:, rcm.axis]
    foot = axis.translation + ((a - axis.translation) @ e) * e
    k = rcm.axis
    x = axis.rotation[:, (k + 1) % 3]
    rot = np.column_stack([x, e, np.cross(x, e)])
    return np.asarray(pin.SE3(rot, foot + 0.5 * (span[0] + span[1]) * e).homogeneous)


def axis_rod(span: tuple[float, float], radius: float, color: Any) -> tuple[Any, Any]:
    """The rod's Meshcat cylinder and material."""
    return mg.Cylinder(span[1] - span[0], radius), mg.MeshPhongMaterial(color=hex_color(color))


def points_object(points: np.ndarray, values: np.ndarray | None, color: Any, size: float,
                  cmap: str) -> Any:  # fmt: skip
    """A Meshcat point cloud, coloured by ``values`` through ``cmap`` or in one ``color``.

    Raises:
        InvalidInputError: points not (N, 3) finite, or values not (N,).
    """
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 3 or not np.all(np.isfinite(p)):
        raise InvalidInputError(f"points have shape {p.shape}; valid: (N, 3) finite values")
    if values is not None and np.asarray(values).shape != (len(p),):
        raise InvalidInputError(f"values have shape {np.asarray(values).shape}; valid: ({len(p)},)")
    rgb = colormap(values, cmap) if values is not None else np.tile(color, (len(p), 1))
    geometry = mg.PointsGeometry(p.T.astype(np.float32), rgb.T.astype(np.float32))
    return mg.Points(geometry, mg.PointsMaterial(size))


class OverlaysMixin:
    """The overlay methods of :class:`rcm_pin.viz.viewer.Viewer` (markers and point sets).

    Markers shown follow :meth:`display` and the animations: :meth:`_overlay_transforms`
    gives their placements at any configuration.
    """

    mech: Mechanism
    vis: Any
    q: np.ndarray
    _data: pin.Data
    _points: dict[str, int]
    _span: tuple[float, float] | None
    _decor: dict[str, Any]  # name -> rcm_pin.viz.explain.Decoration

    def display(self, q: np.ndarray) -> None:  # defined by the viewer
        raise NotImplementedError

    def show_markers(self, radius: float | None = None) -> None:
        """Spheres at the default marker frames (:func:`point_markers`);
        they follow later :meth:`display` and :meth:`animate` calls.

        Args:
            radius: sphere radius [m] (default :func:`marker_radius`).
        """
        if radius is None:
            radius = marker_radius(self.mech, self.q)
        for name, fid in point_markers(self.mech).items():
            self._show_point(name, fid, radius, *MARKER_STYLE.get(name, (RED, 0.6)))
        self.display(self.q)

    def show_rcm(self, radius: float = 0.008, color: Any = RED) -> None:
        """A translucent sphere at the remote centre A.

        Raises:
            InvalidInputError: the mechanism has no RCM.
        """
        self._show_point("rcm", require_rcm(self.mech).point_frame_id, radius, color, 0.5)
        self.display(self.q)

    def _show_point(self, name: str, fid: int, radius: float, color: Any, opacity: float) -> None:
        self.vis[f"{OVERLAYS}/{name}"].set_object(*sphere(radius, color, opacity))
        self._points[name] = fid

    def show_tool_axis(self, radius: float = 0.0015, color: Any = GREEN) -> None:
        """The insertion axis as a thin rod from behind A to beyond the deepest tool centre
        (:func:`axis_span`); it follows later :meth:`display` calls.

        Raises:
            InvalidInputError: the mechanism has no RCM.
        """
        self._span = axis_span(self.mech)
        self.vis[f"{OVERLAYS}/tool_axis"].set_object(*axis_rod(self._span, radius, color))
        self.display(self.q)

    def _overlay_transforms(self, q: np.ndarray) -> dict[str, np.ndarray]:
        """q -> {overlay name: 4x4} of every marker shown."""
        model, data = self.mech.model, self._data
        pin.forwardKinematics(model, data, self.mech.to_pin(q))
        out = {name: frame_point(model, data, fid) for name, fid in self._points.items()}
        if self._span is not None:
            out["tool_axis"] = axis_transform(self.mech, data, self._span)
        out.update({name: d.transform(data) for name, d in self._decor.items()})
        return out

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
        obj = points_object(points, values, color, size, cmap)
        self.vis[f"{OVERLAYS}/{name}"].set_object(obj)

    def show_tool_positions(self, name: str, qs: np.ndarray, values: np.ndarray | None = None,
                            **kwargs: Any) -> np.ndarray:  # fmt: skip
        """Draw the tool (output frame) origins of configurations ``qs`` (N, n); returns
        them (N, 3) [m]."""
        from rcm_pin.analysis.kinematics import tool_poses

        points = tool_poses(self.mech, qs)[:, :3, 3]
        self.show_points(name, points, values, **kwargs)
        return points


def require_rcm(mech: Mechanism) -> Any:
    """``mech.rcm``, or the error that says which mechanisms have one."""
    if mech.rcm is None:
        raise InvalidInputError(
            f"{mech.name} has no RCM frame; valid: a mechanism with a remote centre (rcm_*), "
            "or load(..., rcm_frame=...)"
        )
    return mech.rcm
