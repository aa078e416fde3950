"""Joint position limits as the URDF writes them, not as urdfdom reads them.

urdfdom reads a revolute or prismatic joint whose ``<limit>`` has neither ``lower`` nor
``upper`` (``<limit effort="1" velocity="20"/>``, as every file of LAAS's
*example-parallel-robots* writes it) as the range [0, 0]: a joint that cannot move (it
refuses such a joint with no ``<limit>`` at all; the rule covers that case too). The rule
here: such a joint is **unbounded**, (−inf, inf). A joint with one bound given keeps
URDF's default 0 for the other (the file said something about its range). The rule is
read from the URDF text, since Pinocchio's model cannot tell a missing limit from
``lower="0" upper="0"``.

Consumers treat a non-finite bound as no bound: ``home`` puts an unbounded joint at 0
(:mod:`rcm_pin.model.configurations`), samplers draw angles in [−π, π].
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin

#: URDF joint types whose range urdfdom reads from ``<limit lower upper>``.
BOUNDED_TYPES = ("revolute", "prismatic")


def unbounded_joints(urdf: str) -> frozenset[str]:
    """Names of the revolute / prismatic joints whose URDF gives no range (module docstring).

    Args:
        urdf: URDF XML text (well-formed; the caller has parsed it already).
    """
    out = set()
    for joint in ET.fromstring(urdf).findall("joint"):
        if joint.attrib.get("type") not in BOUNDED_TYPES:
            continue
        limit = joint.find("limit")
        if limit is None or not {"lower", "upper"} & set(limit.attrib):
            out.add(joint.attrib.get("name", ""))
    return frozenset(out)


def free_missing_limits(urdf: str, *models: pin.Model) -> frozenset[str]:
    """Set the range of every joint without one (:func:`unbounded_joints`) to (−inf, inf)
    in each model, in place; returns the names of those joints."""
    names = unbounded_joints(urdf)
    for model in models:
        lower = np.array(model.lowerPositionLimit, dtype=float)
        upper = np.array(model.upperPositionLimit, dtype=float)
        for name in names:
            if not model.existJointName(name):
                continue
            joint = model.joints[model.getJointId(name)]
            if "Mimic" in joint.shortname():
                continue  # the mimic model's mimic joint: its q is its primary's
            lower[joint.idx_q : joint.idx_q + joint.nq] = -np.inf
            upper[joint.idx_q : joint.idx_q + joint.nq] = np.inf
        model.lowerPositionLimit = lower
        model.upperPositionLimit = upper
    return names


__all__ = ["BOUNDED_TYPES", "free_missing_limits", "unbounded_joints"]
