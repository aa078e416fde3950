"""The joint replacements of a LAAS sidecar (``joint_name`` / ``joint_type``), on URDF text.

LAAS's loader (*example-parallel-robots*, ``completeRobotLoader``) rebuilds some joints of
the URDF tree before closing the loops. The same replacement here, written back as URDF so
that every route (Pinocchio's parse, the no-mimic model, the mobility count) sees it:

* ``FIXED``: the joint becomes a fixed joint at its zero position (LAAS freezes it at
  the neutral configuration);
* ``UJOINT_AB`` (A, B in X, Y, Z): a universal joint, two revolute joints about the axes A
  then B of the joint frame, named ``<joint>_A`` and ``<joint>_B``, with a massless link
  ``<joint>_A_link`` between them (the original axis is ignored, as LAAS does; no range:
  unbounded, :mod:`rcm_pin.model.limits`);
* ``SPHERICAL``: refused (URDF has no ball joint and three revolute joints would add a
  representation singularity), with the valid types in the message.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from collections.abc import Mapping

from rcm_pin.errors import InvalidInputError, UnknownFrameError

_UJOINT = re.compile(r"^UJOINT_([XYZ])([XYZ])$")
_AXES = {"X": "1 0 0", "Y": "0 1 0", "Z": "0 0 1"}
VALID = "FIXED, UJOINT_XY, UJOINT_XZ, UJOINT_YX, UJOINT_YZ, UJOINT_ZX, UJOINT_ZY"


def replace_joints(urdf: str, joint_types: Mapping[str, str]) -> str:
    """URDF text with the LAAS joint replacements applied (module docstring).

    Args:
        urdf: URDF XML text.
        joint_types: joint name -> ``FIXED`` / ``UJOINT_AB`` / ``SPHERICAL``.

    Raises:
        UnknownFrameError: a joint the URDF does not have (lists its joints).
        InvalidInputError: malformed XML, or a type that is not supported (lists the valid).
    """
    if not joint_types:
        return urdf
    try:
        root = ET.fromstring(urdf)
    except ET.ParseError as exc:
        raise InvalidInputError(f"the URDF is not well-formed XML: {exc}") from None
    joints = {j.attrib.get("name", ""): j for j in root.findall("joint")}
    for name, kind in joint_types.items():
        if name not in joints:
            raise UnknownFrameError(
                f"sidecar joint_name {name!r} is not a joint of the URDF; valid: "
                + ", ".join(joints)
            )
        joint, kind = joints[name], str(kind).upper()
        match = _UJOINT.match(kind)
        if kind == "FIXED":
            joint.set("type", "fixed")
            for tag in ("axis", "limit", "mimic"):
                for child in joint.findall(tag):
                    joint.remove(child)
        elif match and match[1] != match[2]:
            _split(root, joint, name, match[1], match[2])
        else:
            raise InvalidInputError(
                f"sidecar joint_type {kind!r} of joint {name!r} is not supported; valid: {VALID}"
                " (SPHERICAL: write the ball joint into the URDF as the loop's 3d closure)"
            )
    return ET.tostring(root, encoding="unicode")


def _split(root: ET.Element, joint: ET.Element, name: str, a: str, b: str) -> None:
    """Replace ``joint`` by revolute joints about a then b with a massless link between."""
    parent, child = joint.find("parent"), joint.find("child")
    if parent is None or child is None:
        raise InvalidInputError(f"joint {name!r} has no parent or child link")
    middle = f"{name}_{a}_link"
    ET.SubElement(root, "link", name=middle)
    first = ET.SubElement(root, "joint", name=f"{name}_{a}", type="revolute")
    origin = joint.find("origin")
    if origin is not None:
        ET.SubElement(first, "origin", dict(origin.attrib))
    ET.SubElement(first, "parent", link=parent.attrib["link"])
    ET.SubElement(first, "child", link=middle)
    ET.SubElement(first, "axis", xyz=_AXES[a])
    second = ET.SubElement(root, "joint", name=f"{name}_{b}", type="revolute")
    ET.SubElement(second, "parent", link=middle)
    ET.SubElement(second, "child", link=child.attrib["link"])
    ET.SubElement(second, "axis", xyz=_AXES[b])
    old = joint.find("limit")  # urdfdom needs <limit>; no range: unbounded (model.limits)
    effort = {k: old.attrib.get(k, "0") for k in ("effort", "velocity")} if old is not None else {}
    for new in (first, second):
        ET.SubElement(
            new, "limit", effort=effort.get("effort", "0"), velocity=effort.get("velocity", "0")
        )
    root.remove(joint)


__all__ = ["VALID", "replace_joints"]
