"""Visual geometry of a URDF as MJCF geoms: boxes, cylinders, spheres, STL / OBJ / MSH meshes
(absolute paths; a DAE visual falls back to the link's collision mesh), all ``contype=0``
(no contacts) and massless (the bodies carry the URDF inertias)."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pinocchio as pin

from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.meshes import drawable_urdf

#: Mesh formats MuJoCo reads.
MESH_FORMATS = (".stl", ".obj", ".msh")


def floats(values: object) -> str:
    """Space-separated floats (repr: round-trips exactly)."""
    return " ".join(repr(float(v)) for v in np.ravel(np.asarray(values, dtype=float)))


def pose(elem: ET.Element, placement: pin.SE3) -> None:
    """``pos`` and ``quat`` (w x y z) of a placement."""
    quat = pin.Quaternion(placement.rotation)
    elem.set("pos", floats(placement.translation))
    elem.set("quat", floats([quat.w, quat.x, quat.y, quat.z]))


def geoms(mech: Mechanism, bodies: dict[int, ET.Element], skipped: list[str]) -> None:
    """Visual geoms of the URDF's links (module docstring); meshes through the viewer's
    policy (:func:`rcm_pin.model.meshes.drawable_urdf`: a missing one left out with a
    warning, one outside the description's folders refused).

    Raises:
        MeshLocationError: a mesh outside the allowed folders (names ``--mesh-dir``).
    """
    full = mech.model_full
    for link in ET.fromstring(drawable_urdf(mech.urdf)).iter("link"):
        if not full.existFrame(link.attrib["name"]):
            continue
        frame = full.frames[full.getFrameId(link.attrib["name"])]
        collisions = link.findall("collision")
        for visual in link.findall("visual"):
            before = len(skipped)
            geom = _geom(visual, skipped)
            if geom is None and len(skipped) > before and collisions:
                geom = _geom(collisions[0], [])  # e.g. a DAE visual, an STL collision mesh
                if geom is not None:
                    visual = collisions[0]
                    del skipped[before:]
            if geom is None:
                continue
            origin = visual.find("origin")
            xyz = [
                float(v)
                for v in (origin.get("xyz", "0 0 0") if origin is not None else "0 0 0").split()
            ]
            rpy = [
                float(v)
                for v in (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split()
            ]
            placement = frame.placement * pin.SE3(pin.rpy.rpyToMatrix(*rpy), np.array(xyz))
            geom.attrib.update(contype="0", conaffinity="0", group="1", mass="0")
            pose(geom, placement)
            bodies[frame.parentJoint].append(geom)


def _geom(visual: ET.Element, skipped: list[str]) -> ET.Element | None:
    """One URDF ``<visual>`` as a geom element (None: nothing MuJoCo draws)."""
    shape = visual.find("geometry")
    if shape is None or not len(shape):
        return None
    g = shape[0]
    if g.tag == "box":
        sizes = np.array([float(v) for v in g.get("size", "0 0 0").split()]) / 2
        return ET.Element("geom", type="box", size=floats(sizes))
    if g.tag == "cylinder":
        size = [float(g.get("radius", 0)), float(g.get("length", 0)) / 2]
        return ET.Element("geom", type="cylinder", size=floats(size))
    if g.tag == "sphere":
        return ET.Element("geom", type="sphere", size=floats([float(g.get("radius", 0))]))
    if g.tag == "mesh":
        file = g.get("filename", "").removeprefix("file://")
        if not file.lower().endswith(MESH_FORMATS) or not Path(file).is_absolute():
            skipped.append(file)
            return None
        scale = g.get("scale", "1 1 1")
        return ET.Element("geom", type="mesh", mesh=f"{file}|{scale}")
    return None


__all__ = ["MESH_FORMATS", "floats", "geoms", "pose"]
