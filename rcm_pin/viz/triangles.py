"""Triangle meshes of a mechanism's scene at a configuration, for the no-browser picture.

:func:`body_meshes` triangulates the URDF's visual geometry (Pinocchio's visual
``GeometryModel`` on the mimic model, ``package://`` meshes found in the folders of
:func:`rcm_pin.viz.assets.assets`): boxes, cylinders, spheres, capsules, cones and
ellipsoids from their coal shapes, meshes from coal's vertices and triangles, any other
shape as its local bounding box. Each is placed by ``pin.updateGeometryPlacements`` and
coloured by its URDF material. A mechanism without visual geometry gets grey rods between
its joint origins instead (:func:`rod_meshes`). :func:`marker_meshes` gives the markers
:class:`rcm_pin.viz.viewer.Viewer` draws (:mod:`rcm_pin.viz.overlays`): a red sphere at
the RCM point and a green rod along the insertion axis, red spheres at the cut frames of
each closure, a green sphere at the output where there is no insertion axis.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.meshes import drawable_urdf
from rcm_pin.viz import overlays as ov
from rcm_pin.viz.assets import assets

#: Segments around a circle of a cylinder, cone or sphere.
SEGMENTS = 24
#: Colour of the rods drawn for a mechanism without visual geometry (RGB in [0, 1]).
ROD_COLOR = (0.85, 0.55, 0.2)
#: Radius of the insertion-axis rod and of the links' rods, as in the viewer [m].
AXIS_RADIUS = 0.0015


@dataclass(frozen=True)
class Mesh:
    """Triangles in world coordinates.

    Attributes:
        vertices: (n, 3) world positions [m].
        faces: (m, 3) vertex indices, counter-clockwise seen from outside.
        rgba: colour and opacity in [0, 1].
        closed: a closed surface whose back faces may be culled.
    """

    vertices: np.ndarray
    faces: np.ndarray
    rgba: tuple[float, float, float, float]
    closed: bool = True

    def placed(self, T: np.ndarray) -> Mesh:
        """The mesh moved by the 4x4 transform T."""
        v = self.vertices @ T[:3, :3].T + T[:3, 3]
        return Mesh(v, self.faces, self.rgba, self.closed)


def _revolve(profile: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Surface of revolution about z of a (k, 2) profile (radius, z), poles allowed."""
    k, s = len(profile), SEGMENTS
    phi = 2 * np.pi * np.arange(s) / s
    r, z = profile[:, :1], np.repeat(profile[:, 1:], s, axis=1)
    v = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(k - 1), np.arange(s), indexing="ij")
    a, b = i * s + j, i * s + (j + 1) % s
    c, d = a + s, b + s
    f = np.concatenate([np.stack([a, b, d], -1), np.stack([a, d, c], -1)]).reshape(-1, 3)
    keep = np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]), axis=1)
    return v, f[keep > 0]


def _sphere_profile(radius: float, z0: float = 0.0, z1: float = 0.0) -> np.ndarray:
    """Profile of a sphere of ``radius`` split at the equator, the halves at z1 and z0."""
    t = np.linspace(-np.pi / 2, np.pi / 2, SEGMENTS // 2 + 1)
    z = radius * np.sin(t) + np.where(t < 0, z0, z1)
    return np.c_[radius * np.cos(t), z]


def box(half: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and outward triangles of a box of half sides ``half`` [m]."""
    v = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    f = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))])
    return v * np.asarray(half), f


def shape_triangles(geometry: Any) -> tuple[np.ndarray, np.ndarray]:
    """Local vertices (n, 3) [m] and triangles (m, 3) of one coal shape."""
    kind = type(geometry).__name__
    if kind == "Box":
        return box(geometry.halfSide)
    if kind == "Sphere":
        return _revolve(_sphere_profile(geometry.radius))
    if kind == "Ellipsoid":
        v, f = _revolve(_sphere_profile(1.0))
        return v * np.asarray(geometry.radii), f
    if kind in ("Cylinder", "Cone", "Capsule"):
        r, h = geometry.radius, geometry.halfLength
        if kind == "Capsule":
            return _revolve(_sphere_profile(r, -h, h))
        top = r if kind == "Cylinder" else 0.0
        return _revolve(np.array([[0.0, -h], [r, -h], [top, h], [0.0, h]]))
    if hasattr(geometry, "tri_indices") and geometry.num_tris > 0:
        tris = map(geometry.tri_indices, range(geometry.num_tris))
        f = np.array([[t[0], t[1], t[2]] for t in tris])
        return np.asarray(geometry.vertices(), dtype=float), f.astype(int)
    geometry.computeLocalAABB()  # anything else: its bounding box
    lo, hi = np.asarray(geometry.aabb_local.min_), np.asarray(geometry.aabb_local.max_)
    v, f = box((hi - lo) / 2)
    return v + (hi + lo) / 2, f


def visual_model(mech: Mechanism) -> pin.GeometryModel:
    """The visual GeometryModel of the mechanism's URDF on its (mimic) model (meshes that
    cannot be drawn left out, each with a warning: :func:`rcm_pin.model.meshes.drawable_urdf`)."""
    dirs = list(assets(mech).mesh_dirs(mech))
    return pin.buildGeomFromUrdfString(
        mech.model, drawable_urdf(mech.urdf), pin.GeometryType.VISUAL, package_dirs=dirs
    )


def placements(mech: Mechanism, q: np.ndarray) -> pin.Data:
    """Joint and frame placements at coordinates q."""
    data = mech.model.createData()
    pin.forwardKinematics(mech.model, data, mech.to_pin(mech.check_q(q)))
    pin.updateFramePlacements(mech.model, data)
    return data


def body_meshes(
    mech: Mechanism,
    q: np.ndarray,
    geom: pin.GeometryModel | None = None,
    local: dict[int, tuple[np.ndarray, np.ndarray]] | None = None,
) -> list[Mesh]:
    """World triangles of every visual geometry object at q (rods when there is none).

    Args:
        mech: the mechanism.
        q: coordinates (n,) [rad, m].
        geom: its visual model (default :func:`visual_model`).
        local: cache of the local triangles by object index (filled on the way).
    """
    geom = visual_model(mech) if geom is None else geom
    if geom.ngeoms == 0:
        return rod_meshes(mech, q)
    local = {} if local is None else local
    data, gdata = mech.model.createData(), geom.createData()
    pin.forwardKinematics(mech.model, data, mech.to_pin(mech.check_q(q)))
    pin.updateGeometryPlacements(mech.model, data, geom, gdata)
    out = []
    for i, obj in enumerate(geom.geometryObjects):
        if i not in local:
            local[i] = shape_triangles(obj.geometry)
        v, f = local[i]
        rgba = tuple(float(c) for c in np.clip(obj.meshColor, 0.0, 1.0))
        mesh = Mesh(v, f, rgba)  # type: ignore[arg-type]
        out.append(mesh.placed(gdata.oMg[i].homogeneous))
    return out


def rod(a: np.ndarray, b: np.ndarray, radius: float, rgba: tuple[float, ...]) -> Mesh | None:
    """A cylinder of ``radius`` [m] from a to b (None when they coincide)."""
    d = np.asarray(b, float) - np.asarray(a, float)
    length = float(np.linalg.norm(d))
    if length < 1e-12:
        return None
    z = d / length
    x = np.cross(z, [1.0, 0.0, 0.0] if abs(z[0]) < 0.9 else [0.0, 1.0, 0.0])
    x /= np.linalg.norm(x)
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = np.column_stack([x, np.cross(z, x), z]), (np.asarray(a) + b) / 2
    h = length / 2
    v, f = _revolve(np.array([[0.0, -h], [radius, -h], [radius, h], [0.0, h]]))
    return Mesh(v, f, tuple(rgba)).placed(T)  # type: ignore[arg-type]


def ball(p: np.ndarray, radius: float, rgba: tuple[float, ...]) -> Mesh:
    """A sphere of ``radius`` [m] centred at p."""
    v, f = _revolve(_sphere_profile(radius))
    return Mesh(v + np.asarray(p), f, tuple(rgba))  # type: ignore[arg-type]


def arrow(length: float, radius: float, rgba: tuple[float, ...], *, both: bool = False) -> Mesh:
    """An arrow along local z from 0 to ``length`` [m] (``both``: from −length, two heads)."""
    head, r = 0.24 * length, radius
    z0 = -length if both else 0.0
    profile = [[0.0, z0], [2.4 * r, z0 + head], [r, z0 + head]] if both else [[0.0, 0.0], [r, 0.0]]
    profile += [[r, length - head], [2.4 * r, length - head], [0.0, length]]
    v, f = _revolve(np.array(profile))
    return Mesh(v, f, tuple(rgba))  # type: ignore[arg-type]


def torus(radius: float, tube: float, rgba: tuple[float, ...]) -> Mesh:
    """A ring of ``radius`` [m] about local z, tube radius ``tube`` [m]."""
    s = np.linspace(0.0, 2 * np.pi, 17)
    v, f = _revolve(np.c_[radius + tube * np.cos(s), tube * np.sin(s)])
    return Mesh(v, f, tuple(rgba))  # type: ignore[arg-type]


def slab(half: np.ndarray, rgba: tuple[float, ...]) -> Mesh:
    """A box of half sides ``half`` [m] with a vertex triple per face (flat shading)."""
    v, f = box(np.asarray(half, float))
    tri = v[f].reshape(-1, 3)
    return Mesh(tri, np.arange(len(tri)).reshape(-1, 3), tuple(rgba))  # type: ignore[arg-type]


def rod_meshes(mech: Mechanism, q: np.ndarray) -> list[Mesh]:
    """Rods from each joint origin to its parent's (and to the cut frames), for a
    mechanism without visual geometry."""
    model, data = mech.model, placements(mech, q)
    pairs = [(data.oMi[model.parents[j]].translation, data.oMi[j].translation)
             for j in range(1, model.njoints)]  # fmt: skip
    pairs.append((data.oMi[model.frames[mech.output.frame_id].parentJoint].translation,
                  data.oMf[mech.output.frame_id].translation))  # fmt: skip
    for c in mech.loops.closures if mech.loops is not None else ():
        for fid in (c.frame_a_id, c.frame_b_id):
            pairs.append((data.oMi[model.frames[fid].parentJoint].translation,
                          data.oMf[fid].translation))  # fmt: skip
    size = float(np.linalg.norm(np.ptp(np.array([p for ab in pairs for p in ab]), axis=0)))
    radius = max(0.02 * size, 2 * AXIS_RADIUS)  # wider than the insertion-axis rod
    out = [rod(a, b, radius, (*ROD_COLOR, 1.0)) for a, b in pairs]
    out += [ball(b, 1.5 * radius, (*ROD_COLOR, 1.0)) for _, b in pairs[: model.njoints - 1]]
    return [m for m in out if m is not None]


def marker_meshes(mech: Mechanism, q: np.ndarray, radius: float | None = None) -> list[Mesh]:
    """The viewer's markers at q (module docstring): spheres of ``radius`` [m] (default
    :func:`rcm_pin.viz.overlays.marker_radius`) and the insertion-axis rod."""
    radius = ov.marker_radius(mech, q) if radius is None else radius
    model, data = mech.model, placements(mech, q)
    out: list[Mesh] = []
    if mech.rcm is not None:
        T = ov.axis_transform(mech, data, span := ov.axis_span(mech))
        half = 0.5 * (span[1] - span[0]) * T[:3, 1]
        axis = rod(T[:3, 3] - half, T[:3, 3] + half, AXIS_RADIUS, (*ov.GREEN, 1.0))
        out += [axis] if axis is not None else []
    for name, fid in ov.point_markers(mech).items():
        color, opacity = ov.MARKER_STYLE.get(name, (ov.RED, 0.6))
        p = ov.frame_point(model, data, fid)[:3, 3]
        out.append(ball(p, radius, (*color, max(opacity, 0.8))))
    return out
