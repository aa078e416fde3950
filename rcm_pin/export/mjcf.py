"""Any mechanism as a MuJoCo MJCF file (plain XML; writing needs no MuJoCo).

The mapping (``docs/mujoco.md``):

* one ``<body>`` per joint of the no-mimic Pinocchio model (fixed links merged into it), at
  the joint placement, with the joint's inertia (``<inertial fullinertia>``), one
  ``hinge`` or ``slide`` joint named as in the URDF (range, damping, frictionloss,
  armature from the URDF);
* every ``<mimic>`` transmission: a joint equality q_m = offset + multiplier · q_p
  (``polycoef``);
* every loop closure: ``connect`` (3d) or ``weld`` (6d) between sites at its two frames;
* drives (a closed mechanism's drives; a serial one's independent joints): ``motor``
  actuators, force-limited by the URDF effort;
* sites at the tool or output frame, the RCM point and axis frames, the closure frames;
* visual geometry: URDF boxes, cylinders, spheres and STL / OBJ meshes (absolute paths) as
  ``contype=0`` geoms (no contacts, no mass);
* the solver settings of :mod:`rcm_pin.export.settings`, explained in an XML comment.
"""

from __future__ import annotations

import os
import warnings
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError
from rcm_pin.export import settings as st
from rcm_pin.export.geometry import MESH_FORMATS, geoms
from rcm_pin.export.geometry import floats as _f
from rcm_pin.export.geometry import pose as _pose
from rcm_pin.model.coupling import mimic_tags
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.processes import atomic_write


@dataclass(frozen=True)
class MjcfExport:
    """What :func:`to_mjcf` wrote.

    Attributes:
        path: the MJCF file.
        mechanism: the mechanism as exported (inertia floor applied): rcm-pin on this
            computes the dynamics the file describes.
        settings: the solver settings written.
        floored: joints whose bodies got the inertia floor.
        inexact: what the file cannot express exactly (one sentence each).
        skipped_meshes: mesh files left out (format MuJoCo does not read).
    """

    path: Path
    mechanism: Mechanism
    settings: st.SolverSettings
    floored: tuple[str, ...]
    inexact: tuple[str, ...]
    skipped_meshes: tuple[str, ...]

    def summary(self) -> dict[str, object]:
        """JSON-able summary (the CLI's ``--json`` document)."""
        s = self.settings
        return {
            "mechanism": self.mechanism.name,
            "mjcf": str(self.path),
            "timestep": s.timestep,
            "solref": list(s.solref),
            "solimp": list(s.solimp),
            "predicted_drift": s.predicted_drift,
            "drift_tol": s.drift_tol,
            "floored_bodies": list(self.floored),
            "inexact": list(self.inexact),
            "skipped_meshes": list(self.skipped_meshes),
        }


def _axis(model: pin.Model, j: int) -> tuple[str, np.ndarray]:
    """MuJoCo joint type and axis of Pinocchio joint j (from its motion subspace)."""
    jm = model.joints[j]
    if jm.nv != 1:
        raise InvalidInputError(
            f"joint {model.names[j]!r} has {jm.nv} DOF; valid for MJCF export: one-DOF joints"
        )
    jd = jm.createData()
    jm.calc(jd, pin.neutral(model))
    s = np.asarray(jd.S).ravel()
    return ("hinge", s[3:]) if np.linalg.norm(s[3:]) > 0.5 else ("slide", s[:3])


def _body(model: pin.Model, j: int, parent: ET.Element) -> ET.Element:
    """The body, inertial and joint of Pinocchio joint j under ``parent``."""
    name = model.names[j]
    body = ET.SubElement(parent, "body", name=name)
    _pose(body, model.jointPlacements[j])
    inertia = model.inertias[j]
    if inertia.mass > 0:
        I = inertia.inertia
        ET.SubElement(
            body,
            "inertial",
            pos=_f(inertia.lever),
            mass=repr(float(inertia.mass)),
            fullinertia=_f([I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]]),
        )
    kind, axis = _axis(model, j)
    joint = ET.SubElement(body, "joint", name=name, type=kind, axis=_f(axis))
    jm = model.joints[j]
    lo, hi = model.lowerPositionLimit[jm.idx_q], model.upperPositionLimit[jm.idx_q]
    if jm.nq == 1 and np.isfinite(lo) and np.isfinite(hi) and hi - lo < 1e6:
        joint.set("limited", "true")
        joint.set("range", _f([lo, hi]))
    for attr, values in (
        ("damping", model.damping),
        ("frictionloss", model.friction),
        ("armature", model.armature),
    ):
        if values[jm.idx_v] > 0:
            joint.set(attr, repr(float(values[jm.idx_v])))
    return body


def _sites(mech: Mechanism) -> dict[str, str]:
    """Frame name -> role of every frame that gets a site."""
    roles: dict[str, str] = {}
    if mech.output.frame_id >= 0:
        roles[mech.output.frame] = "output" if mech.is_closed else "tool"
    if mech.rcm is not None:
        roles.setdefault(mech.model.frames[mech.rcm.point_frame_id].name, "rcm point")
        roles.setdefault(mech.model.frames[mech.rcm.axis_frame_id].name, "rcm axis")
    for c in mech.loops.closures if mech.loops is not None else ():
        roles.setdefault(c.frame_a, "closure")
        roles.setdefault(c.frame_b, "closure")
    return roles


def build(mech: Mechanism, s: st.SolverSettings) -> tuple[ET.Element, list[str], list[str]]:
    """The MJCF tree of a (floored) mechanism; (root, inexact notes, skipped meshes)."""
    full = mech.model_full
    root = ET.Element("mujoco", model=mech.name)
    ET.SubElement(root, "compiler", angle="radian", inertiafromgeom="false", autolimits="true")
    option = ET.SubElement(root, "option", timestep=repr(s.timestep))
    option.set("gravity", _f(full.gravity.linear))
    option.attrib.update(solver="Newton", iterations="200", tolerance="1e-12")
    world = ET.SubElement(root, "worldbody")
    bodies: dict[int, ET.Element] = {0: world}
    for j in range(1, full.njoints):
        bodies[j] = _body(full, j, bodies[full.parents[j]])
    for name, role in _sites(mech).items():
        frame = full.frames[full.getFrameId(name)]
        bodies[frame.parentJoint].append(ET.Comment(f" {role} frame "))
        site = ET.SubElement(bodies[frame.parentJoint], "site", name=name, size="0.002")
        site.set("group", "2")
        _pose(site, frame.placement)
    skipped: list[str] = []
    geoms(mech, bodies, skipped)
    assets = ET.Element("asset")
    for geom in root.iter("geom"):
        if geom.get("type") == "mesh":
            file, _, scale = geom.attrib["mesh"].partition("|")
            name = f"mesh{len(assets)}"
            ET.SubElement(assets, "mesh", name=name, file=file, scale=scale)
            geom.set("mesh", name)
    if len(assets):
        root.insert(2, assets)
    inexact = _equalities(mech, ET.SubElement(root, "equality"), s)
    actuators = ET.SubElement(root, "actuator")
    drives = mech.loops.drives if mech.loops is not None else mech.joint_names
    for name in drives:
        motor = ET.SubElement(actuators, "motor", name=name, joint=name, gear="1")
        effort = full.effortLimit[full.joints[full.getJointId(name)].idx_v]
        if np.isfinite(effort) and 0 < effort < 1e6:
            motor.attrib.update(forcelimited="true", forcerange=_f([-effort, effort]))
    return root, inexact, skipped


def _equalities(mech: Mechanism, eq: ET.Element, s: st.SolverSettings) -> list[str]:
    """Mimic joint equalities and closure connects / welds; notes on what is inexact."""
    soft = {"solref": _f(s.solref), "solimp": _f(s.solimp)}
    for name, (primary, mult, off) in mimic_tags(mech.urdf).items():
        joint = ET.SubElement(eq, "joint", name=f"mimic_{name}", joint1=name, joint2=primary)
        joint.attrib.update(soft)
        joint.set("polycoef", _f([off, mult, 0, 0, 0]))
    inexact = []
    for c in mech.loops.closures if mech.loops is not None else ():
        tag = "connect" if c.kind == "3d" else "weld"
        ET.SubElement(eq, tag, name=f"{c.frame_a}-{c.frame_b}", site1=c.frame_a, site2=c.frame_b)
        eq[-1].attrib.update(soft)
        if len(c.world_rows) > len(c.rows):
            inexact.append(
                f"closure {c.frame_a}-{c.frame_b} keeps {len(c.rows)} of the {tag}'s rows in "
                f"its frame, but {len(c.world_rows)} world rows move: MuJoCo's {tag} "
                "constrains them all, as rcm-pin's constrained dynamics does (not the kinematic "
                "row subset)"
            )
    return inexact


def _comment(mech: Mechanism, s: st.SolverSettings) -> str:
    return (
        f" rcm-pin export of {mech.name}. Solver settings (docs/mujoco.md): every equality "
        f"has solimp {_f(s.solimp)} (MuJoCo's stiffest impedance) and solref {_f(s.solref)} "
        "(time constant 2*timestep, the smallest MuJoCo accepts; critically damped). The "
        f"timestep {s.timestep:g} s keeps the predicted equality drift "
        f"max({st.MIMIC_SAFETY:g}*(1-d)*a_m*(2*dt)^2, {st.LOOP_COEFF:g}*a_c*dt^2) = "
        f"{s.predicted_drift:.2g} m or rad (a_m = {s.mimic_acceleration:.3g}, a_c = "
        f"{s.loop_acceleration:.3g}: the free accelerations of the mimic and closure rows "
        f"under gravity) under the tolerance {s.drift_tol:g}. Geoms are visual only (no "
        "contact, no mass). "
    )


def to_mjcf(
    mech: Mechanism,
    path: str | os.PathLike[str],
    timestep: float | None = None,
    drift_tol: float = st.DRIFT_TOL,
) -> MjcfExport:
    """Write ``mech`` as an MJCF file (module docstring); needs no MuJoCo.

    Args:
        path: the file to write (atomically: a temporary file beside it, then renamed).
        timestep: dt [s] (default: chosen for ``drift_tol``, :mod:`rcm_pin.export.settings`).
        drift_tol: largest predicted closure drift [m or rad].

    Raises:
        InvalidInputError: an unwritable path (missing or read-only folder, a folder),
            a bad timestep or tolerance, a joint with more than one DOF.
        MeshLocationError: a mesh outside the description's folders (as ``view``).

    Warns:
        MissingMeshWarning: a mesh file that cannot be found (left out, as ``view``).
        InertiaFloorWarning: moving bodies without mass or inertia (raised to a floor).
        InexactExportWarning: closures whose kept rows MJCF cannot express, skipped meshes.
    """
    target = Path(path)
    folder = target.parent if str(target.parent) else Path(".")
    if target.is_dir() or not folder.is_dir() or not os.access(folder, os.W_OK):
        raise InvalidInputError(
            f"cannot write {str(target)!r} (a folder, or its folder is missing or not "
            "writable); valid: a file path in an existing writable folder"
        )
    s = st.choose(mech, timestep, drift_tol)
    exported, raised = st.floored(mech)
    root, inexact, skipped = build(exported, s)
    root.insert(0, ET.Comment(_comment(mech, s)))
    for note in inexact + [f"mesh {m} left out (MuJoCo reads STL, OBJ, MSH)" for m in skipped]:
        warnings.warn(f"{mech.name}: {note}", st.InexactExportWarning, stacklevel=2)
    ET.indent(root)
    text = ET.tostring(root, encoding="unicode") + "\n"
    try:
        atomic_write(target, text.encode("utf-8"))
    except OSError as exc:
        raise InvalidInputError(f"cannot write {str(target)!r} ({exc.strerror})") from None
    return MjcfExport(target, exported, s, raised, tuple(inexact), tuple(skipped))


__all__ = ["MESH_FORMATS", "MjcfExport", "build", "to_mjcf"]
