"""Joint descriptions read from a ``pin.Model``: the only place that talks to Pinocchio's
joint classes.

Every supported joint has one scalar joint variable ``theta``:

* ``revolute`` / ``prismatic`` (aligned RX..PZ or unaligned axes): ``theta = q[idx_q]``;
* ``revolute_unbounded`` (URDF ``continuous``, nq = 2, nv = 1): ``q[idx_q:idx_q+2] =
  (cos theta, sin theta)``, used as given, exactly as Pinocchio does;
* mimic joints (``JointModelMimic``, nq = nv = 0): ``theta = scaling * theta_primary +
  offset``, with the primary's ``idx_q`` / ``idx_v``.

The joint type and axis are identified from Pinocchio itself (motion subspace ``S`` and
placement ``M`` of the joint data), not from class names, and checked: ``M(theta)`` must
equal ``exp6(theta * S)`` at a probe value, so a joint that is not a pure revolute or
prismatic joint (helical, spherical, free-flyer, planar, universal, composite) raises
:class:`~rcm_pin.errors.InvalidInputError` instead of being modelled wrongly.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError

JointKind = Literal["revolute", "prismatic", "revolute_unbounded"]

_PROBE = 0.7  # joint value used to check M(theta) == exp6(theta S)


@dataclass(frozen=True)
class JointSpec:
    """One moving joint of the tree, in the form the symbolic algorithms need."""

    index: int  # Pinocchio joint id
    name: str
    parent: int  # Pinocchio id of the parent joint (0 = universe)
    kind: JointKind
    axis: np.ndarray  # unit axis in the joint frame
    rotation: np.ndarray  # jointPlacement rotation (3x3)
    translation: np.ndarray  # jointPlacement translation (3,)
    idx_q: int  # first configuration index (of the primary for a mimic joint)
    idx_v: int  # velocity index (of the primary for a mimic joint)
    scaling: float  # 1.0 unless mimic
    offset: float  # 0.0 unless mimic
    mimic: bool
    mass: float
    lever: np.ndarray  # centre of mass in the joint frame
    inertia: np.ndarray  # rotational inertia about the centre of mass (3x3)


@dataclass(frozen=True)
class FrameSpec:
    """A frame fixed to a joint: ``oMf = oMi[parent] * placement``."""

    index: int
    name: str
    parent: int
    rotation: np.ndarray
    translation: np.ndarray


def _primary_of(model: pin.Model, joint_id: int) -> int:
    mimicking = list(model.mimicking_joints)
    if joint_id not in mimicking:
        raise InvalidInputError(f"joint {model.names[joint_id]!r} is a mimic joint without primary")
    return int(list(model.mimicked_joints)[mimicking.index(joint_id)])


def _probe(model: pin.Model, jmodel: pin.JointModel, q: np.ndarray) -> tuple[np.ndarray, pin.SE3]:
    jdata = jmodel.createData()
    jmodel.calc(jdata, q)
    return np.array(jdata.S).reshape(6).copy(), pin.SE3(jdata.M)


def _identify(
    model: pin.Model, jid: int, primary: pin.JointModel, scaling: float, offset: float
) -> tuple[JointKind, np.ndarray]:
    """Joint kind and unit axis, checked against Pinocchio's own joint placement."""
    name = model.names[jid]
    unbounded = primary.nq == 2 and primary.nv == 1
    if scaling == 0.0:
        raise InvalidInputError(f"mimic joint {name!r} has multiplier 0; use a fixed joint")
    if unbounded and jid != primary.id:
        raise InvalidInputError(f"mimic joint {name!r} follows a continuous joint: unsupported")
    q = pin.neutral(model)
    if unbounded:
        q[primary.idx_q : primary.idx_q + 2] = np.cos(_PROBE), np.sin(_PROBE)
    else:
        q[primary.idx_q] = (_PROBE - offset) / scaling
    s, placement = _probe(model, model.joints[jid], q)
    s = s / scaling
    lin, ang = s[:3], s[3:]
    kind: JointKind
    if np.linalg.norm(lin) < 1e-12 and abs(np.linalg.norm(ang) - 1.0) < 1e-12:
        kind, axis = ("revolute_unbounded" if unbounded else "revolute"), ang
    elif np.linalg.norm(ang) < 1e-12 and abs(np.linalg.norm(lin) - 1.0) < 1e-12 and not unbounded:
        kind, axis = "prismatic", lin
    else:
        raise InvalidInputError(
            f"joint {name!r} ({model.joints[jid].shortname()}) is not a revolute or prismatic "
            "joint with a unit axis; supported: revolute, prismatic, continuous, mimic"
        )
    expected = pin.exp6(pin.Motion(_PROBE * s))
    if not expected.isApprox(placement, 1e-12):
        raise InvalidInputError(f"joint {name!r}: placement is not exp6(theta * S); unsupported")
    return kind, axis.copy()


def joint_specs(model: pin.Model) -> tuple[JointSpec, ...]:
    """Describe every moving joint of ``model`` (joint 0, the universe, excluded)."""
    specs = []
    for jid in range(1, model.njoints):
        jmodel = model.joints[jid]
        if jmodel.shortname() == "JointModelMimic":
            mimic = jmodel.extract()
            scaling, offset = float(mimic.scaling), float(mimic.offset)
            primary = model.joints[_primary_of(model, jid)]
        elif jmodel.nv == 1 and jmodel.nq in (1, 2):
            scaling, offset, primary = 1.0, 0.0, jmodel
        else:
            raise InvalidInputError(
                f"joint {model.names[jid]!r} ({jmodel.shortname()}, nq={jmodel.nq}, "
                f"nv={jmodel.nv}) is unsupported; supported: revolute, prismatic, continuous, "
                "mimic (free-flyer, spherical, planar joints are not)"
            )
        kind, axis = _identify(model, jid, primary, scaling, offset)
        placement = model.jointPlacements[jid]
        inertia = model.inertias[jid]
        specs.append(
            JointSpec(
                index=jid,
                name=str(model.names[jid]),
                parent=int(model.parents[jid]),
                kind=kind,
                axis=axis,
                rotation=np.array(placement.rotation),
                translation=np.array(placement.translation),
                idx_q=int(primary.idx_q),
                idx_v=int(primary.idx_v),
                scaling=scaling,
                offset=offset,
                mimic=primary.id != jid,
                mass=float(inertia.mass),
                lever=np.array(inertia.lever),
                inertia=np.array(inertia.inertia),
            )
        )
    return tuple(specs)


def frame_specs(model: pin.Model) -> tuple[FrameSpec, ...]:
    """Every frame of ``model`` (operational, body, joint and fixed-joint frames)."""
    return tuple(
        FrameSpec(
            index=i,
            name=str(f.name),
            parent=int(f.parentJoint),
            rotation=np.array(f.placement.rotation),
            translation=np.array(f.placement.translation),
        )
        for i, f in enumerate(model.frames)
    )


def coupling_matrix(model: pin.Model, specs: tuple[JointSpec, ...]) -> np.ndarray:
    """``G`` (n_joints x nv) with ``theta_dot = G v``: the mimic coupling of velocities."""
    g = np.zeros((len(specs), model.nv))
    for k, s in enumerate(specs):
        g[k, s.idx_v] = s.scaling
    return g


__all__ = ["FrameSpec", "JointKind", "JointSpec", "coupling_matrix", "frame_specs", "joint_specs"]
