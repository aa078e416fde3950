"""Decorations that explain a scene: a base plate, frame triads, drive rings, joint axes.

Each is a :class:`Decoration`: a triangle mesh (:class:`rcm_pin.viz.triangles.Mesh`, in
a local frame) fixed to one Pinocchio joint, so the Meshcat scene (a
``TriangularMeshGeometry`` under ``overlays/``) and the matplotlib picture draw the very
same triangles, and both follow the configuration shown:

* the *base plate* (:func:`ground_plate`): a thin grey slab under the bodies, normal to
  "up" (world z; the plane's normal for a planar mechanism, seen from above), sized from
  the bodies' bounding box at the configuration it is made at;
* *frame triads* (:func:`triads`): x, y, z arrows (red, green, blue) at the output (tool)
  frame and at the remote centre A where there is one;
* *drive rings* (:func:`drive_rings`): a magenta ring around the axis of every driven
  joint (:func:`drives`: the loops' drives, else every coordinate's joint), where the
  axis meets the driven body, with a double arrow along a prismatic one's;
* *joint axes* (:func:`joint_axes`): a thin dark rod along every joint's axis, through
  the places where its two bodies meet it (:func:`joint_sites`).

Sizes are fractions of the bodies' bounding-box diagonal (:func:`extent`).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pinocchio as pin

with warnings.catch_warnings():  # meshcat imports pyzmq's deprecated zmq.eventloop.ioloop
    warnings.simplefilter("ignore", DeprecationWarning)
    import meshcat.geometry as mg

from rcm_pin.model.constraints import plane_normal
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.viz.camera import plane_basis
from rcm_pin.viz.palette import GROUND
from rcm_pin.viz.scene import hex_color
from rcm_pin.viz.triangles import Mesh, arrow, body_meshes, rod, slab, torus, visual_model

#: Colour of the drive markers (RGB in [0, 1]).
DRIVE_COLOR = (0.85, 0.1, 0.7)
#: Colours of the triads' x, y and z arrows (RGB in [0, 1]).
AXIS_COLORS = ((0.9, 0.1, 0.1), (0.1, 0.7, 0.2), (0.15, 0.3, 0.95))
#: Colour of the joint-axis rods (RGBA in [0, 1]).
AXIS_ROD = (0.25, 0.25, 0.28, 1.0)
#: Sizes as fractions of the bodies' extent: triad arrow length, drive ring radius, base
#: plate thickness, gap under the bodies and margin around them.
TRIAD, RING, PLATE, GAP, MARGIN = 0.1, 0.055, 0.012, 0.03, 0.08
#: Radius of the joint-axis rods and their reach beyond the bodies, fractions of the extent.
AXIS_RADIUS, AXIS_REACH = 0.003, 0.03


@dataclass(frozen=True, eq=False)
class Decoration:
    """One mesh fixed to a joint (module docstring).

    Attributes:
        name: scene node name under ``overlays/``.
        kind: ``ground``, ``triad``, ``drive`` or ``axis``.
        mesh: triangles in the local frame, and colour.
        joint: the Pinocchio joint it moves with (0: fixed to the world).
        placement: 4x4 of the local frame in the joint's frame [m].
        label: text for its origin in a labelled picture (empty: none).
    """

    name: str
    kind: str
    mesh: Mesh
    joint: int
    placement: np.ndarray = field(repr=False)
    label: str = ""

    def transform(self, data: pin.Data) -> np.ndarray:
        """World placement (4x4) of the local frame, from the joint placements in data."""
        return np.asarray(data.oMi[self.joint].homogeneous) @ self.placement

    def meshcat(self) -> tuple[Any, Any]:
        """The Meshcat geometry and material."""
        rgba = self.mesh.rgba
        geometry = mg.TriangularMeshGeometry(self.mesh.vertices, self.mesh.faces)
        return geometry, mg.MeshPhongMaterial(color=hex_color(rgba), opacity=rgba[3])


def _frame_z(axis: np.ndarray, at: np.ndarray | None = None) -> np.ndarray:
    """4x4 whose z axis is ``axis`` (normalised) and origin ``at``."""
    z = np.asarray(axis, float) / np.linalg.norm(axis)
    x = np.cross(z, [1.0, 0.0, 0.0] if abs(z[0]) < 0.9 else [0.0, 1.0, 0.0])
    x /= np.linalg.norm(x)
    T = np.eye(4)
    T[:3, :3] = np.column_stack([x, np.cross(z, x), z])
    if at is not None:
        T[:3, 3] = at
    return T


def extent(points: np.ndarray) -> float:
    """Diagonal of the bounding box of (N, 3) points [m] (1 mm at least)."""
    p = np.reshape(points, (-1, 3))
    return max(float(np.linalg.norm(p.max(0) - p.min(0))), 1e-3)


def up_direction(mech: Mechanism) -> np.ndarray:
    """World z, or the plane's normal turned to z ≥ 0 for a planar mechanism."""
    n = plane_normal(mech.model)
    return np.array([0.0, 0.0, 1.0]) if n is None else plane_basis(n)[:, 2]


def ground_plate(mech: Mechanism, points: np.ndarray) -> Decoration:
    """The base plate under ``points`` (N, 3) [m], the bodies at some configuration."""
    size, basis = extent(points), plane_basis(up_direction(mech))
    local = np.reshape(points, (-1, 3)) @ basis  # (u, w, up) coordinates
    lo, hi = local.min(0), local.max(0)
    margin = MARGIN * size
    half = np.array([(hi[0] - lo[0]) / 2 + margin, (hi[1] - lo[1]) / 2 + margin, PLATE * size / 2])
    centre = np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, lo[2] - GAP * size - half[2]])
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = basis, basis @ centre
    return Decoration("ground", "ground", slab(half, GROUND), 0, T)


def triad(
    name: str, joint: int, placement: np.ndarray, length: float, label: str
) -> list[Decoration]:
    """x, y, z arrows (:data:`AXIS_COLORS`) of the frame at ``placement`` in ``joint``."""
    out = []
    for k, axis in enumerate(np.eye(3)):
        mesh = arrow(length, 0.045 * length, (*AXIS_COLORS[k], 1.0))
        T = placement @ _frame_z(axis)
        out.append(
            Decoration(f"{name}/{'xyz'[k]}", "triad", mesh, joint, T, label if k == 0 else "")
        )
    return out


def enclosing(point: np.ndarray, meshes: list[Mesh]) -> float:
    """How far a triad at ``point`` must reach to be seen out of a body centred on it [m]:
    the largest half side of the bounding box of a mesh whose centre is nearer to the
    point than its smallest half side (a sphere or box around the frame); 0 for none."""
    out = 0.0
    for m in meshes:
        lo, hi = m.vertices.min(0), m.vertices.max(0)
        half = (hi - lo) / 2
        if np.linalg.norm(point - (lo + hi) / 2) < half.min():
            out = max(out, float(half.max()))
    return out


def triads(mech: Mechanism, length: float, meshes: list[Mesh] | None = None,
           q: np.ndarray | None = None) -> list[Decoration]:  # fmt: skip
    """Triads at the output frame (``tool`` of a serial mechanism, ``output`` of a closed
    one) and at the remote centre A where there is one; arrows ``length`` long [m], longer
    (up to 2.5 ``length``) to reach out of a body that holds the frame (:func:`enclosing`
    of the world ``meshes`` at ``q``)."""
    model = mech.model
    frames = {"tool" if mech.loops is None else "output": mech.output.frame_id}
    if mech.rcm is not None:
        frames["A"] = mech.rcm.point_frame_id
    data = model.createData()
    pin.forwardKinematics(model, data, mech.to_pin(mech.home if q is None else q))
    out = []
    for label, fid in frames.items():
        f = model.frames[fid]
        p = (data.oMi[f.parentJoint] * f.placement).translation
        reach = min(max(length, enclosing(p, meshes or []) + 0.6 * length), 2.5 * length)
        out += triad(f"triad_{label}", f.parentJoint, f.placement.homogeneous, reach, label)
    return out


def drives(mech: Mechanism) -> dict[str, str]:
    """The driven joints: label (the input's name: ``q1``, ... or the drive) -> URDF joint."""
    if mech.loops is not None:
        return {name: name for name in mech.loops.drives}
    return dict(zip(mech.coordinate_names, mech.joint_names, strict=True))


def joint_axis(model: pin.Model, joint: int, q_pin: np.ndarray) -> tuple[np.ndarray, bool]:
    """Unit axis of a one-DOF joint in its own frame, and whether it is prismatic."""
    data = model.createData()
    jac = np.asarray(pin.computeJointJacobian(model, data, q_pin, joint)).reshape(6, model.nv)
    col = jac[:, model.joints[joint].idx_v]
    prismatic = bool(np.linalg.norm(col[3:]) < 1e-12)
    axis = col[:3] if prismatic else col[3:]
    return axis / np.linalg.norm(axis), prismatic


def ring_site(local: np.ndarray, radius: float) -> float | None:
    """Where a body meets a joint axis (local z) [m], from the body's vertices ``local``
    (N, 3) in the axis frame: the foot of the vertices nearest the axis (of those within
    ``radius / 2`` of the nearest, the one nearest the joint origin); None when no vertex
    comes within ``radius`` of the axis (the body does not meet it) or there is none."""
    if not len(local):
        return None
    r, s = np.hypot(local[:, 0], local[:, 1]), local[:, 2]
    if r.min() > radius:
        return None
    near = r <= r.min() + 0.5 * radius
    return float(s[near][np.argmin(np.abs(s[near]))])


@dataclass(frozen=True, eq=False)
class JointSite:
    """A one-DOF joint's axis in the scene.

    Attributes:
        joint: Pinocchio joint id.
        parent: its parent joint id (the body the axis frame is fixed to).
        placement: 4x4 of the axis frame (z along the axis, origin at the joint) in the
            parent joint's frame.
        prismatic: a slide (else a revolute pair).
        child: where the child body meets the axis, along it [m] (None: no visual).
        parent_at: where the parent body meets the axis [m] (None: no visual).
        world: 4x4 world placement of the axis frame at the configuration of the sites.
    """

    joint: int
    parent: int
    placement: np.ndarray
    prismatic: bool
    child: float | None
    parent_at: float | None
    world: np.ndarray


def joint_sites(mech: Mechanism, q: np.ndarray, radius: float,
                geom: pin.GeometryModel | None = None) -> dict[int, JointSite]:  # fmt: skip
    """The :class:`JointSite` of every one-DOF joint at q, by joint id (:func:`ring_site`
    of the visual objects of ``geom``, default the URDF's, with ``radius`` [m])."""
    model, q_pin = mech.model, mech.to_pin(mech.check_q(q))
    geom = visual_model(mech) if geom is None else geom
    meshes = body_meshes(mech, q, geom) if geom.ngeoms else []
    data = model.createData()
    pin.forwardKinematics(model, data, q_pin)
    by_body: dict[int, list[np.ndarray]] = {}
    for m, obj in zip(meshes, geom.geometryObjects, strict=True):
        by_body.setdefault(int(obj.parentJoint), []).append(m.vertices)
    out = {}
    for j in range(1, model.njoints):
        if model.joints[j].nv != 1:
            continue
        axis, prismatic = joint_axis(model, j, q_pin)
        parent = int(model.parents[j])
        T = model.jointPlacements[j].homogeneous @ _frame_z(axis)
        world = np.asarray(data.oMi[parent].homogeneous) @ T
        at = []
        for body in (j, parent):
            v = np.vstack(by_body[body]) if body in by_body else np.zeros((0, 3))
            at.append(ring_site((v - world[:3, 3]) @ world[:3, :3], radius))
        out[j] = JointSite(j, parent, T, prismatic, at[0], at[1], world)
    return out


def _shifted(T: np.ndarray, s: float) -> np.ndarray:
    return T @ _frame_z(np.array([0.0, 0.0, 1.0]), np.array([0.0, 0.0, s]))


def drive_rings(mech: Mechanism, sites: dict[int, JointSite], radius: float) -> list[Decoration]:
    """A ring around each driven joint's axis (:func:`drives`), on the parent body, where
    the axis meets the child body (else at the joint) moved up to ``radius`` towards the
    parent body (so that a body starting on the axis does not hide it), and a double arrow
    along a prismatic one's. Rings are ``radius`` [m] wide, narrower (down to 0.4
    ``radius``) where drives sit close together: at most 0.45 times the distance to the
    nearest other ring."""
    rgba, out = (*DRIVE_COLOR, 1.0), []
    placed = {}
    for label, joint_name in drives(mech).items():
        site = sites[mech.model.getJointId(joint_name)]
        s0, back = site.child or 0.0, site.parent_at or 0.0  # a step towards the parent
        s0 -= float(np.clip(s0 - back, -radius, radius))
        placed[label] = (site, _shifted(site.placement, s0), (site.world @ [0, 0, s0, 1])[:3])
    for label, (site, T, centre) in placed.items():
        gaps = [np.linalg.norm(centre - c) for k, (_, _, c) in placed.items() if k != label]
        r = float(np.clip(0.45 * min(gaps, default=np.inf), 0.4 * radius, radius))
        ring = torus(r, 0.2 * r, rgba)
        out.append(Decoration(f"drive_{label}", "drive", ring, site.parent, T, label))
        if site.prismatic:
            mesh = arrow(2.2 * r, 0.12 * r, rgba, both=True)
            out.append(Decoration(f"drive_{label}_slide", "drive", mesh, site.parent, T))
    return out


def joint_axes(mech: Mechanism, sites: dict[int, JointSite], radius: float,
               reach: float) -> list[Decoration]:  # fmt: skip
    """A thin dark rod of ``radius`` [m] along every joint's axis, from the joint origin
    to where the parent and child bodies meet the axis, ``reach`` [m] beyond (so the axes
    of a spherical mechanism meet at its centre)."""
    out = []
    for j, site in sites.items():
        ends = [0.0, *(s for s in (site.child, site.parent_at) if s is not None)]
        lo, hi = min(ends) - reach, max(ends) + reach
        mesh = rod(np.array([0.0, 0.0, lo]), np.array([0.0, 0.0, hi]), radius, AXIS_ROD)
        if mesh is not None:
            name = mech.model.names[j]
            out.append(Decoration(f"axis_{name}", "axis", mesh, site.parent, site.placement))
    return out
