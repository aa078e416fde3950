"""Do the joint axes pass through the bodies they join? The miss of every axis, numerically.

A real joint is a shaft in bearings: its axis runs through both bodies it joins. For a
mechanism at a configuration (default ``mech.home``, closed mechanisms at their assembled
home), :func:`axis_misses` gives, for every moving joint and each of its two bodies, the
distance [m] from the joint's line to that body's visual geometry (0 where the line passes
through it):

* tree joints of the URDF (revolute, continuous, prismatic; mimic joints included): the
  line through the joint origin along its axis (a prismatic joint's line of travel); the
  bodies are its parent and child links;
* cut joints of the loop closures (a ``3d`` closure joins the bodies of its two frames at
  one point): the line through frame a's origin along the bodies' relative rotation axis,
  the one direction of their relative angular velocity over the closed loop's velocity
  space (null space of the closure Jacobian). A closure whose bodies turn about two or
  more axes (a ball joint) gets three lines through the point, along the world axes; one
  about which they do not turn relative to each other (or a ``6d`` closure: a weld) none.

A body is the rigid union of the links fixed together (Pinocchio's joint, the link's
fixed children merged), so a hub on a gear wheel fixed to a link counts for that link.
Its visual geometry is the URDF's (Pinocchio's visual ``GeometryModel``): boxes, cylinders
and spheres exactly, meshes by their triangles (:mod:`rcm_pin.model.line_distance`). A
body without visual geometry misses by ``inf``.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin
from scipy.linalg import null_space

from rcm_pin.errors import InvalidInputError
from rcm_pin.model import line_distance as ld
from rcm_pin.model.loops import residual_and_jacobian
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.meshes import drawable_urdf

#: URDF joint types that move (their axis is checked).
MOVING = ("revolute", "continuous", "prismatic")
#: Relative angular speed below which a cut joint's bodies count as not turning about a
#: direction, per unit speed of the loop's velocity space [rad/s] (well above round-off).
ROTATION_TOL = 1e-9


@dataclass(frozen=True)
class AxisMiss:
    """How far one joint's line passes from one of its bodies.

    Attributes:
        joint: URDF joint name, or ``frame_a~frame_b`` for a loop closure's cut joint.
        side: ``parent`` or ``child`` (a cut joint: the bodies of frame a and frame b).
        link: the URDF link on that side.
        miss: distance from the line to the body's visual geometry [m]; 0 through it.
    """

    joint: str
    side: str
    link: str
    miss: float


def triangles(geometry: Any) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (n, 3) [m] and faces (m, 3) of a coal triangle mesh (BVH model)."""
    tris = (geometry.tri_indices(i) for i in range(geometry.num_tris))
    faces = np.array([[t[0], t[1], t[2]] for t in tris], dtype=int).reshape(-1, 3)
    return np.asarray(geometry.vertices(), dtype=float), faces


def shape_miss(
    geometry: Any, p: np.ndarray, d: np.ndarray, mesh: tuple[np.ndarray, np.ndarray] | None = None
) -> float:
    """Miss [m] of the line p + t d (in the shape's frame) and one coal shape (``mesh``:
    its :func:`triangles`, when already extracted).

    Raises:
        InvalidInputError: a shape that is no URDF primitive or triangle mesh.
    """
    kind = type(geometry).__name__
    if kind == "Box":
        return ld.line_box(p, d, np.asarray(geometry.halfSide))
    if kind == "Cylinder":
        return ld.line_cylinder(p, d, geometry.radius, geometry.halfLength)
    if kind == "Sphere":
        return ld.line_sphere(p, d, geometry.radius)
    if hasattr(geometry, "tri_indices") and geometry.num_tris > 0:
        return ld.line_triangles(p, d, *(triangles(geometry) if mesh is None else mesh))
    raise InvalidInputError(
        f"visual shape {kind} cannot be measured; valid: box, cylinder, sphere, mesh"
    )


class _Scene:
    """The visual geometry of a mechanism placed at one Pinocchio configuration."""

    def __init__(self, mech: Mechanism, q_pin: np.ndarray) -> None:
        self.model = mech.model
        self.data = self.model.createData()
        self.geom = pin.buildGeomFromUrdfString(
            self.model, drawable_urdf(mech.urdf), pin.GeometryType.VISUAL
        )
        gdata = self.geom.createData()
        pin.forwardKinematics(self.model, self.data, q_pin)
        pin.updateFramePlacements(self.model, self.data)
        pin.updateGeometryPlacements(self.model, self.data, self.geom, gdata)
        self.placed = list(gdata.oMg)
        self.meshes: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        self.group = list(range(self.model.njoints))  # welded bodies share a group
        for c in mech.loops.closures if mech.loops is not None else ():
            if c.kind == "6d":
                a, b = (self._root(self.body_of(f)) for f in (c.frame_a_id, c.frame_b_id))
                self.group[max(a, b)] = min(a, b)

    def _root(self, joint: int) -> int:
        while self.group[joint] != joint:
            joint = self.group[joint]
        return joint

    def body_of(self, frame_id: int) -> int:
        """The Pinocchio joint (rigid body) that carries a frame."""
        return int(self.model.frames[frame_id].parentJoint)

    def body(self, link: str) -> int:
        """The Pinocchio joint (rigid body) that carries a link."""
        return self.body_of(self.model.getFrameId(link))

    def miss(self, body: int, point: np.ndarray, direction: np.ndarray) -> float:
        """Smallest miss [m] of the world line and the body's visual objects (inf: none)."""
        best = math.inf
        for i, (obj, oMg) in enumerate(zip(self.geom.geometryObjects, self.placed, strict=True)):
            if self._root(obj.parentJoint) == self._root(body):
                rot = oMg.rotation.T
                p, d = rot @ (point - oMg.translation), rot @ direction
                shape = obj.geometry
                if hasattr(shape, "tri_indices") and i not in self.meshes:
                    self.meshes[i] = triangles(shape)
                best = min(best, shape_miss(shape, p, d, self.meshes.get(i)))
        return best


def _tree_rows(mech: Mechanism, scene: _Scene) -> Iterator[AxisMiss]:
    root = ET.fromstring(mech.urdf)
    for joint in root.iter("joint"):
        if joint.get("type") not in MOVING:
            continue
        name = str(joint.get("name"))
        parent = str(joint.find("parent").get("link"))  # type: ignore[union-attr]
        child = str(joint.find("child").get("link"))  # type: ignore[union-attr]
        axis_el = joint.find("axis")
        axis = np.array([1.0, 0.0, 0.0])
        if axis_el is not None and axis_el.get("xyz"):
            axis = np.array([float(x) for x in str(axis_el.get("xyz")).split()])
        jid = scene.model.getJointId(name)
        if jid >= scene.model.njoints:
            continue  # not a joint of the model (replaced on load): nothing placed
        oMi = scene.data.oMi[jid]
        point, direction = oMi.translation, oMi.rotation @ axis
        for side, link in (("parent", parent), ("child", child)):
            miss = scene.miss(scene.body(link), point, direction)
            yield AxisMiss(name, side, link, miss)


def _link_of(mech: Mechanism, frame_id: int) -> str:
    """The link (body frame) of the rigid body that carries a frame."""
    model = mech.model
    joint = model.frames[frame_id].parentJoint
    for f in model.frames:
        if f.parentJoint == joint and f.type == pin.FrameType.BODY:
            return str(f.name)
    return str(model.frames[frame_id].name)


def _directions(omega: np.ndarray) -> list[np.ndarray]:
    """The directions an angular-velocity matrix (3, k) spans (SVD, ROTATION_TOL)."""
    u, sv, _ = np.linalg.svd(np.c_[omega, np.zeros(3)])
    return [u[:, i] for i in range(len(sv)) if sv[i] > ROTATION_TOL]


def _cut_axes(closed: np.ndarray, tree: np.ndarray) -> list[np.ndarray]:
    """Lines of a cut joint from the bodies' relative angular velocity over the closed
    loop's velocity space (``closed``) and over the cut-open tree's (``tree``): one
    direction, that axis; two or three, a ball joint (the world axes); none, the axis the
    tree allows when it allows one (a planar loop at a configuration where its bodies turn
    alike), else a weld (no line)."""
    axes = _directions(closed)
    if len(axes) > 1:
        return list(np.eye(3))
    if axes:
        return axes
    axes = _directions(tree)
    return axes if len(axes) == 1 else []


def _cut_rows(mech: Mechanism, scene: _Scene, q_pin: np.ndarray) -> Iterator[AxisMiss]:
    loops = mech.loops
    if loops is None:
        return
    model = scene.model
    data = model.createData()
    _, jac = residual_and_jacobian(model, data, loops, q_pin)
    basis = null_space(jac) if jac.shape[0] else np.eye(model.nv)
    pin.updateFramePlacements(model, data)
    for c in loops.closures:
        if c.kind != "3d":
            continue  # the frames coincide: a weld, one body
        ja = pin.getFrameJacobian(model, data, c.frame_a_id, pin.WORLD)[3:]
        jb = pin.getFrameJacobian(model, data, c.frame_b_id, pin.WORLD)[3:]
        lines = _cut_axes((jb - ja) @ basis, jb - ja)
        if not lines:
            continue
        point = data.oMf[c.frame_a_id].translation
        name = f"{c.frame_a}~{c.frame_b}"
        for side, fid in (("parent", c.frame_a_id), ("child", c.frame_b_id)):
            body = int(model.frames[fid].parentJoint)
            miss = max(scene.miss(body, point, d) for d in lines)
            yield AxisMiss(name, side, _link_of(mech, fid), miss)


def axis_misses(mech: Mechanism, q: np.ndarray | None = None) -> tuple[AxisMiss, ...]:
    """For every moving joint (tree and cut joints) and each of its two bodies, the miss
    of the joint's line and the body's visual geometry (module docstring).

    Args:
        mech: the mechanism.
        q: coordinates (n,) [rad, m]; default ``mech.home`` (closed: its assembled home).

    Returns:
        One :class:`AxisMiss` per joint and side: tree joints in URDF order, then the cut
        joints in closure order; parent side first.

    Raises:
        InvalidInputError: bad coordinates, or a visual shape that cannot be measured.
        MeshLocationError: a mesh outside every allowed folder.
    """
    q_pin = mech.to_pin(mech.check_q(mech.home if q is None else q))
    scene = _Scene(mech, q_pin)
    return (*_tree_rows(mech, scene), *_cut_rows(mech, scene, q_pin))


__all__ = ["MOVING", "ROTATION_TOL", "AxisMiss", "axis_misses", "shape_miss", "triangles"]
