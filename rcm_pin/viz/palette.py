"""Colours of the bodies of a scene: the URDF's materials, or one colour per body.

A *body* is everything one Pinocchio joint moves (the visual geometry objects with that
``parentJoint``; links joined by fixed joints are one body, a mimic joint's transmission
body is a body of its own); the *ground* is what the world joint holds. :func:`paint`
sets the colour of each visual geometry object of a ``GeometryModel`` before the scene is
built, so the Meshcat picture and the matplotlib picture (which both read
``GeometryObject.meshColor``) show the same colours:

* ``"urdf"``: the URDF's materials only (an object without one keeps Pinocchio's light grey;
  a mesh file keeps its own materials in Meshcat);
* ``"auto"`` (the default): the URDF's material where it sets one, else the body's
  colour of :data:`PALETTE` (:data:`GROUND` for the ground); mesh files without a URDF
  material keep their own;
* ``"bodies"``: every object its body's colour, URDF materials and mesh materials
  replaced.

Colours of :data:`PALETTE` go to the moving bodies in joint order, so neighbouring bodies
differ; none is the red or green of the markers (:mod:`rcm_pin.viz.overlays`).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError

#: The colour modes of :func:`paint`.
COLOR_MODES = ("auto", "urdf", "bodies")
#: Colour of the ground (bodies fixed to the world) and of the base plate (RGBA in [0, 1]).
GROUND = (0.6, 0.6, 0.62, 1.0)
#: Colours of the moving bodies, in joint order (RGBA in [0, 1]).
PALETTE: tuple[tuple[float, float, float, float], ...] = (
    (0.2, 0.45, 0.85, 1.0),  # blue
    (0.95, 0.55, 0.15, 1.0),  # orange
    (0.55, 0.35, 0.75, 1.0),  # purple
    (0.1, 0.62, 0.62, 1.0),  # teal
    (0.88, 0.72, 0.18, 1.0),  # gold
    (0.6, 0.4, 0.25, 1.0),  # brown
    (0.5, 0.72, 0.92, 1.0),  # sky blue
    (0.55, 0.6, 0.2, 1.0),  # olive
    (0.85, 0.5, 0.6, 1.0),  # rose
    (0.25, 0.3, 0.6, 1.0),  # navy
    (0.95, 0.68, 0.5, 1.0),  # salmon
    (0.72, 0.62, 0.9, 1.0),  # lavender
)


def check_mode(colors: str) -> str:
    """``colors`` if it is a colour mode.

    Raises:
        InvalidInputError: not one of :data:`COLOR_MODES`.
    """
    if colors not in COLOR_MODES:
        raise InvalidInputError(f"colors {colors!r} is unknown; valid: {', '.join(COLOR_MODES)}")
    return colors


def body_colors(geom: pin.GeometryModel) -> dict[int, tuple[float, float, float, float]]:
    """The colour of each body that carries visual geometry, by joint id: :data:`GROUND` for
    joint 0, :data:`PALETTE` in turn (joint order) for the others."""
    joints = sorted({int(obj.parentJoint) for obj in geom.geometryObjects})
    moving = [j for j in joints if j != 0]
    out = {j: PALETTE[k % len(PALETTE)] for k, j in enumerate(moving)}
    if 0 in joints:
        out[0] = GROUND
    return out


def _is_mesh(obj: pin.GeometryObject) -> bool:
    """A triangle mesh read from a file (coal's BVH models), not a primitive shape."""
    return type(obj.geometry).__name__.startswith("BVH") and obj.geometry.num_tris > 0


def _has_own_material(obj: pin.GeometryObject) -> bool:
    """The URDF gave the object a material, or it is a mesh file with its own materials."""
    return bool(obj.overrideMaterial) or _is_mesh(obj)


def paint(geom: pin.GeometryModel, colors: str = "auto") -> pin.GeometryModel:
    """Set the colour of every visual object of ``geom`` for mode ``colors`` (module
    docstring); returns ``geom`` (changed in place).

    Raises:
        InvalidInputError: ``colors`` is not one of :data:`COLOR_MODES`.
    """
    check_mode(colors)
    if colors == "urdf":
        return geom
    by_body = body_colors(geom)
    for obj in geom.geometryObjects:
        if colors == "auto" and _has_own_material(obj):
            continue
        obj.meshColor[:] = by_body[int(obj.parentJoint)]
        obj.overrideMaterial = True  # a mesh file shows the colour, not its own materials
    return geom


def repainted_meshes(geom: pin.GeometryModel, colors: str) -> list[int]:
    """Indices of the mesh-file objects :func:`paint` gave a body colour (mode ``bodies``):
    Meshcat draws a mesh file in its own materials, so the viewer sends these as
    triangles (:func:`mesh_arrays`) in that colour instead."""
    if colors != "bodies":
        return []
    return [i for i, o in enumerate(geom.geometryObjects) if _is_mesh(o)]


def mesh_arrays(obj: pin.GeometryObject) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (n, 3) in the mesh file's own units (the URDF's scale undone: Pinocchio's
    viewer applies it to the placement) and triangles (m, 3) of a mesh object."""
    g = obj.geometry
    faces = np.array([[t[0], t[1], t[2]] for t in map(g.tri_indices, range(g.num_tris))])
    vertices = np.asarray(g.vertices(), dtype=float) / np.asarray(obj.meshScale, dtype=float)
    return vertices, faces.astype(np.uint32)


def legend(model: pin.Model, geom: pin.GeometryModel) -> list[tuple[tuple[float, ...], list[str]]]:
    """The colours shown and the links that carry each, in first-seen order.

    Returns:
        (RGBA, link names) pairs, one per distinct colour (rounded to 1e-3).
    """
    out: dict[tuple[float, ...], list[str]] = {}
    for obj in geom.geometryObjects:
        rgba = tuple(round(float(c), 3) for c in obj.meshColor)
        link = model.frames[obj.parentFrame].name
        names = out.setdefault(rgba, [])
        if link not in names:
            names.append(link)
    return list(out.items())


__all__ = [
    "COLOR_MODES",
    "GROUND",
    "PALETTE",
    "body_colors",
    "check_mode",
    "legend",
    "mesh_arrays",
    "paint",
    "repainted_meshes",
]
