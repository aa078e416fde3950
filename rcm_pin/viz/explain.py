"""What a viewer draws to explain a mechanism: :class:`SceneStyle` and the viewer's methods.

:class:`SceneStyle` says how the bodies are coloured (:mod:`rcm_pin.viz.palette`) and
which decorations of :mod:`rcm_pin.viz.decorations` a
:class:`rcm_pin.viz.viewer.Viewer` draws (base plate, frame triads, drive rings, joint
axes); :class:`ExplainMixin` holds the viewer's ``show_*`` methods for them and gives
their world meshes (for the matplotlib picture) and labels (for
:func:`rcm_pin.viz.caption.explained_png`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from rcm_pin.model.mechanism import Mechanism
from rcm_pin.viz.base import OVERLAYS
from rcm_pin.viz.decorations import (
    AXIS_RADIUS,
    AXIS_REACH,
    RING,
    TRIAD,
    Decoration,
    drive_rings,
    extent,
    ground_plate,
    joint_axes,
    joint_sites,
    triads,
)
from rcm_pin.viz.palette import check_mode
from rcm_pin.viz.triangles import Mesh, body_meshes


@dataclass(frozen=True)
class SceneStyle:
    """What a viewer draws besides the bodies and the default markers.

    Attributes:
        colors: body colours, one of :data:`rcm_pin.viz.palette.COLOR_MODES`.
        ground: a base plate under the bodies.
        triads: frame triads at the output (tool) frame and the remote centre.
        drives: a ring on the axis of every driven joint.
        axes: a thin rod along every joint's axis.

    Raises:
        InvalidInputError: ``colors`` is not a colour mode.
    """

    colors: str = "auto"
    ground: bool = False
    triads: bool = False
    drives: bool = False
    axes: bool = False

    def __post_init__(self) -> None:
        check_mode(self.colors)

    @classmethod
    def explained(cls, colors: str = "auto") -> SceneStyle:
        """Everything on (:data:`EXPLAINED`) with body colours ``colors``.

        Raises:
            InvalidInputError: ``colors`` is not a colour mode.
        """
        return cls(colors, ground=True, triads=True, drives=True, axes=True)


#: The default style: the URDF's materials, per-body colours where it sets none.
PLAIN = SceneStyle()
#: The gallery's style: per-body colours, base plate, triads, drive rings and joint axes.
EXPLAINED = SceneStyle.explained()


class ExplainMixin:
    """The viewer's methods for :class:`Decoration` s; they follow :meth:`display` and the
    animations (``_overlay_transforms``)."""

    mech: Mechanism
    vis: Any
    viz: Any
    q: np.ndarray
    _decor: dict[str, Decoration]

    def display(self, q: np.ndarray) -> None:  # defined by the viewer
        raise NotImplementedError

    def scene_points(self, q: np.ndarray, ground: bool = False) -> np.ndarray:  # the viewer's
        raise NotImplementedError

    def _add(self, decorations: list[Decoration]) -> None:
        for d in decorations:
            self.vis[f"{OVERLAYS}/{d.name}"].set_object(*d.meshcat())
            self._decor[d.name] = d
        self.display(self.q)

    def show_ground(self) -> None:
        """A base plate under the bodies as shown now (:func:`ground_plate`)."""
        self._add([ground_plate(self.mech, self.scene_points(self.q))])

    def show_triads(self, length: float | None = None) -> None:
        """Frame triads at the output (tool) frame and A (:func:`triads`).

        Args:
            length: arrow length [m] (default :data:`TRIAD` times :func:`extent`).
        """
        size = extent(self.scene_points(self.q))
        meshes = body_meshes(self.mech, self.q, self.viz.visual_model)
        length = TRIAD * size if length is None else length
        self._add(triads(self.mech, length, meshes, self.q))

    def show_drives(self, radius: float | None = None) -> None:
        """A ring on every driven joint's axis (:func:`drive_rings`).

        Args:
            radius: ring radius [m] (default :data:`RING` times :func:`extent`).
        """
        size = extent(self.scene_points(self.q))
        radius = RING * size if radius is None else radius
        sites = joint_sites(self.mech, self.q, radius, self.viz.visual_model)
        self._add(drive_rings(self.mech, sites, radius))

    def show_joint_axes(self, radius: float | None = None) -> None:
        """A thin rod along every joint's axis (:func:`joint_axes`).

        Args:
            radius: rod radius [m] (default :data:`AXIS_RADIUS` times :func:`extent`).
        """
        size = extent(self.scene_points(self.q))
        radius = AXIS_RADIUS * size if radius is None else radius
        sites = joint_sites(self.mech, self.q, RING * size, self.viz.visual_model)
        self._add(joint_axes(self.mech, sites, radius, AXIS_REACH * size))

    def show_style(self, style: SceneStyle) -> None:
        """Draw what ``style`` asks for (its colours are set when the viewer is built)."""
        if style.ground:
            self.show_ground()
        if style.triads:
            self.show_triads()
        if style.drives:
            self.show_drives()
        if style.axes:
            self.show_joint_axes()

    def decorations(self) -> list[Decoration]:
        """The decorations shown (:mod:`rcm_pin.viz.decorations`), in the order added."""
        return list(self._decor.values())

    def decoration_meshes(self, q: np.ndarray | None = None) -> tuple[list[Mesh], list[Mesh]]:
        """World meshes of the decorations at ``q`` (default: the one shown): the base
        plate, and the others."""
        data = self.mech.model.createData()
        pin.forwardKinematics(self.mech.model, data, self.mech.to_pin(self.q if q is None else q))
        under: list[Mesh] = []
        over: list[Mesh] = []
        for d in self._decor.values():
            (under if d.kind == "ground" else over).append(d.mesh.placed(d.transform(data)))
        return under, over

    def labels(self, q: np.ndarray | None = None) -> list[tuple[str, np.ndarray]]:
        """(text, world point [m]) of each labelled decoration at ``q`` (default: shown)."""
        data = self.mech.model.createData()
        pin.forwardKinematics(self.mech.model, data, self.mech.to_pin(self.q if q is None else q))
        return [(d.label, d.transform(data)[:3, 3]) for d in self._decor.values() if d.label]
