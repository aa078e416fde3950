"""Every joint a URDF can hold, as Mechanism coordinates (``docs/joints.md``).

The rule: one coordinate per independent joint, named after it.

* ``revolute`` [rad] and ``prismatic`` [m]: Pinocchio's own q entry, limits of the URDF.
* ``continuous``: one angle θ [rad], unbounded (limits −inf, inf). Pinocchio stores it as
  (cos θ, sin θ) in two q entries and one v entry; that pair stays inside the Mechanism
  (:func:`to_pin` writes it, :func:`from_pin` reads ``atan2``); velocities, Jacobian
  columns and forces use the joint's one v index.
* ``<mimic>`` joints: no coordinate (they follow their primary through the coupling,
  :mod:`rcm_pin.model.coupling`). Pinocchio refuses a mimic pair whose configuration
  spaces differ (a ``continuous`` follower of a ``revolute`` primary, as in dVRK-like
  double parallelograms) and its (cos, sin) pair is not affine in θ, so every
  ``continuous`` joint in a mimic pair is parsed as an unbounded ``revolute`` joint
  (:func:`revolute_mimics`): the same axis, origin and kinematics, one q entry.
* ``fixed``: a frame, no coordinate.
* ``floating`` and ``planar``: refused (:class:`~rcm_pin.errors.UnsupportedJointError`
  naming the joint).

Closed mechanisms keep Pinocchio's q of the cut-open tree as coordinates (their loop
solvers work on it), so a ``continuous`` joint there contributes its (cos, sin) pair.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError, UnsupportedJointError
from rcm_pin.model.indices import joint_index
from rcm_pin.model.loops import REVOLUTE

#: Limit written for a continuous joint parsed as revolute (urdfdom rejects ``inf``);
#: the Mechanism and the parsed models then carry −inf, inf [rad].
_WIDE = "1e300"


def is_continuous(jmodel: pin.JointModel) -> bool:
    """Whether a Pinocchio joint is a URDF ``continuous`` one: q = (cos θ, sin θ), v = θ̇."""
    return bool(jmodel.nq == 2 and jmodel.nv == 1)


def revolute_mimics(
    urdf: str, name: str = "URDF", every_continuous: bool = False
) -> tuple[str, frozenset[str]]:
    """URDF text whose ``continuous`` joints of mimic pairs (``every_continuous``: all of
    them, for a closed mechanism, whose loop solvers work on Pinocchio's q) are unbounded
    ``revolute``: the same kinematics with one angle each.

    Returns:
        The text (unchanged when no such joint) and the names of the rewritten joints.

    Raises:
        InvalidInputError: the text is not XML, or not a ``<robot name=...>`` with links
            (e.g. a xacro macro file rendered without a robot, as example-robot-data's
            ``ur3.urdf``).
    """
    try:
        root = ET.fromstring(urdf)
    except ET.ParseError as exc:
        raise InvalidInputError(
            f"{name}: the URDF is not XML ({exc}); valid: a <robot> document"
        ) from None
    if root.tag != "robot" or not root.get("name") or root.find("link") is None:
        raise InvalidInputError(
            f"{name}: the document is <{root.tag}> with name={root.get('name')!r} and "
            f"{len(root.findall('link'))} links (a macro file without a robot?); valid: "
            "<robot name=...> with at least one <link>"
        )
    joints = {j.attrib.get("name", ""): j for j in root.iter("joint")}
    paired: set[str] = set()
    for jname, joint in joints.items():
        tag = joint.find("mimic")
        if tag is not None:
            paired |= {jname, tag.attrib.get("joint", "")}
    chosen = joints if every_continuous else paired
    names = frozenset(n for n in chosen if n in joints and joints[n].get("type") == "continuous")
    if not names:
        return urdf, names
    for n in names:
        joint = joints[n]
        joint.set("type", "revolute")
        limit = joint.find("limit")
        if limit is None:
            limit = ET.SubElement(joint, "limit", {"effort": _WIDE, "velocity": _WIDE})
        limit.set("lower", "-" + _WIDE)
        limit.set("upper", _WIDE)
    return ET.tostring(root, encoding="unicode"), names


def unbound(model: pin.Model, names: frozenset[str]) -> None:
    """Give the rewritten joints of :func:`revolute_mimics` the limits of a continuous
    joint in the parsed model: position −inf, inf; effort and velocity inf when the URDF
    gave none (the wide placeholder)."""
    wide = float(_WIDE)
    for n in names:
        if not model.existJointName(n) or model.joints[model.getJointId(n)].nq != 1:
            continue  # a mimic follower of the mimic model has no q entry of its own
        jm = model.joints[model.getJointId(n)]
        lo, hi = model.lowerPositionLimit.copy(), model.upperPositionLimit.copy()
        lo[jm.idx_q], hi[jm.idx_q] = -np.inf, np.inf
        model.lowerPositionLimit, model.upperPositionLimit = lo, hi
        for attr in ("effortLimit", "velocityLimit"):
            lim = getattr(model, attr).copy()
            lim[jm.idx_v] = np.inf if lim[jm.idx_v] >= wide else lim[jm.idx_v]
            setattr(model, attr, lim)


def check_joints(model: pin.Model) -> None:
    """Refuse the joints a Mechanism has no coordinates for.

    Raises:
        UnsupportedJointError: a ``floating`` or ``planar`` joint (named).
    """
    for j in range(1, model.njoints):
        jm = model.joints[j]
        if jm.nq > 1 and not is_continuous(jm):
            kind = {"JointModelFreeFlyer": "floating", "JointModelPlanar": "planar"}.get(
                jm.shortname(), jm.shortname()
            )
            raise UnsupportedJointError(
                f"{model.name}: joint {model.names[j]!r} is {kind} (nq={jm.nq}, nv={jm.nv}); "
                "valid: revolute, continuous, prismatic, fixed or mimic joints (write a "
                "floating or planar base as a chain of prismatic and revolute joints)"
            )


@dataclass(frozen=True)
class Coordinates:
    """The Mechanism coordinates of a model.

    Attributes:
        joints: joint of each coordinate.
        q_index: Pinocchio q index of each (the cos entry of a continuous joint).
        v_index: Pinocchio v index of each velocity coordinate.
        revolute: (n,) bool, the angles [rad].
        continuous: indices of the coordinates that are continuous joints' angles.
        lower: (n,) lower limits [rad or m] (−inf for continuous joints).
        upper: (n,) upper limits [rad or m] (inf for continuous joints).
    """

    joints: tuple[str, ...]
    q_index: np.ndarray
    v_index: np.ndarray
    revolute: np.ndarray
    continuous: np.ndarray
    lower: np.ndarray
    upper: np.ndarray


def coordinates(model: pin.Model, joints: Sequence[str] = ()) -> Coordinates:
    """One coordinate per independent joint, in Pinocchio order or the order of ``joints``
    (the papers'); a continuous joint one unbounded angle (a closed mechanism's arrive
    here as unbounded revolute joints: :func:`revolute_mimics`).

    Raises:
        UnsupportedJointError: a floating or planar joint, or no moving joint at all.
        UnknownFrameError: a named joint the model does not have.
        InvalidInputError: a named joint twice, or one without a coordinate (fixed, mimic).
    """
    check_joints(model)
    if joints:
        ids = [joint_index(model, j, "coordinate joint") for j in joints]
        twice = sorted({j for j in joints if list(joints).count(j) > 1})
        none = [model.names[j] for j in ids if model.joints[j].nq == 0]
        if twice or none:
            raise InvalidInputError(
                f"{model.name}: coordinate joints {', '.join(twice or none)} "
                + ("named twice" if twice else "have no coordinate (mimic or fixed)")
                + "; valid: each independent joint once"
            )
    else:
        ids = [j for j in range(1, model.njoints) if model.joints[j].nq > 0]
    if not ids:
        raise UnsupportedJointError(
            f"{model.name}: no moving joint (every joint is fixed or a mimic follower); "
            "valid: a URDF with at least one revolute, continuous or prismatic joint"
        )
    cont = [k for k, j in enumerate(ids) if is_continuous(model.joints[j])]
    q_index = np.array([model.joints[j].idx_q for j in ids], dtype=int)
    lower = np.asarray(model.lowerPositionLimit)[q_index].copy()
    upper = np.asarray(model.upperPositionLimit)[q_index].copy()
    lower[cont], upper[cont] = -np.inf, np.inf
    shortnames = [model.joints[j].shortname() for j in ids]
    return Coordinates(
        joints=tuple(model.names[j] for j in ids),
        q_index=q_index,
        v_index=np.array([model.joints[j].idx_v for j in ids], dtype=int),
        revolute=np.array(
            [s in REVOLUTE or k in cont for k, s in enumerate(shortnames)], dtype=bool
        ),
        continuous=np.array(cont, dtype=int),
        lower=lower,
        upper=upper,
    )


def to_pin(
    q: np.ndarray, neutral: np.ndarray, q_index: np.ndarray, continuous: np.ndarray
) -> np.ndarray:
    """Coordinates (..., n) -> Pinocchio q (..., nq_pin): θ -> (cos θ, sin θ) for the
    continuous coordinates, the neutral configuration for joints without a coordinate."""
    out = np.broadcast_to(neutral, q.shape[:-1] + neutral.shape).copy()
    out[..., q_index] = q
    if continuous.size:
        i, a = q_index[continuous], q[..., continuous]
        out[..., i], out[..., i + 1] = np.cos(a), np.sin(a)
    return out


def from_pin(q_pin: np.ndarray, q_index: np.ndarray, continuous: np.ndarray) -> np.ndarray:
    """Pinocchio q (..., nq_pin) -> coordinates: θ = atan2(sin, cos) ∈ (−π, π] for the
    continuous coordinates."""
    q = q_pin[..., q_index]
    if continuous.size:
        i = q_index[continuous]
        q[..., continuous] = np.arctan2(q_pin[..., i + 1], q_pin[..., i])
    return q


def parse_failure(urdf: str, name: str, exc: Exception) -> str:
    """The message for URDF text Pinocchio refused: a name used twice, or the mimic joint at
    fault (a primary missing from the file, or one Pinocchio meets after its follower in
    its depth-first walk, so the mimic model cannot be built), else Pinocchio's text."""
    root = ET.fromstring(urdf)
    names = [j.get("name", "") for j in root.findall("joint")]  # not <transmission>'s
    for kind, used in (
        ("joint", names),
        ("link", [k.get("name", "") for k in root.findall("link")]),
    ):
        twice = sorted({n for n in used if used.count(n) > 1})
        if twice:
            return f"{name}: {kind} name {twice[0]!r} is used twice; valid: unique {kind} names"
    try:
        order = list(pin.buildModelFromXML(urdf).names)
    except (RuntimeError, ValueError):
        order = []
    for joint in root.findall("joint"):
        tag, follower = joint.find("mimic"), joint.get("name", "")
        primary = "" if tag is None else tag.get("joint", "")
        if tag is not None and primary not in names:
            return (
                f"{name}: joint {follower!r} mimics {primary!r}, which the URDF does not have; "
                "valid: a <mimic joint=...> naming one of its joints"
            )
        later = primary in order and follower in order
        if tag is not None and later and order.index(primary) > order.index(follower):
            return (
                f"{name}: joint {follower!r} mimics {primary!r}, which Pinocchio meets "
                "after it in its depth-first walk of the tree; valid: a primary on the "
                "follower's path from the root or on an earlier branch"
            )
    return f"{name}: Pinocchio cannot parse the URDF: {exc}"


__all__ = [
    "Coordinates",
    "check_joints",
    "coordinates",
    "from_pin",
    "is_continuous",
    "parse_failure",
    "revolute_mimics",
    "to_pin",
    "unbound",
]
