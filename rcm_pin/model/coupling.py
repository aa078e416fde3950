"""The mimic coupling of a URDF: every joint as an affine function of the independent ones.

A transmission (gear train, belt, parallelogram written as a crank and its mimic) is a
URDF ``<mimic>`` joint. Pinocchio parsed with ``mimic=True`` gives it no coordinate; the
same URDF parsed without mimic has every joint. They are linked by

    q_full = G·q_pin + offset,   v_full = G_v·v_pin,

read here from the ``<mimic>`` tags, independently of Pinocchio's own mimic support, so
that everything Pinocchio computes on a mimic model can be checked on the no-mimic model
projected through G (virtual work: M = G_vᵀ M_full G_v, τ = G_vᵀ τ_full).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass

import numpy as np
import pinocchio as pin


@dataclass(frozen=True)
class Coupling:
    """Affine map from independent Pinocchio coordinates to every URDF joint.

    Attributes:
        G: (nq_full, nq) matrix; column j holds the multipliers of the joints that
            follow independent coordinate j (1 for the coordinate's own joint).
        Gv: (nv_full, nv) the same map on velocities (equals G unless the model has
            continuous joints, whose q has two entries and v one).
        offset: (nq_full,) mimic offsets.
        full_names: joint names of the no-mimic model in its q order.
    """

    G: np.ndarray
    Gv: np.ndarray
    offset: np.ndarray
    full_names: tuple[str, ...]

    def q_full(self, q_pin: np.ndarray) -> np.ndarray:
        """Configuration of the no-mimic model: G·q + offset."""
        return np.asarray(q_pin) @ self.G.T + self.offset

    def v_full(self, v_pin: np.ndarray) -> np.ndarray:
        """Velocity (or acceleration) of the no-mimic model: G·v."""
        return np.asarray(v_pin) @ self.Gv.T

    @property
    def has_mimic(self) -> bool:
        """Whether some joint follows another one."""
        return self.G.shape[0] != self.G.shape[1]


def mimic_tags(urdf: str) -> dict[str, tuple[str, float, float]]:
    """``{joint: (primary joint, multiplier, offset)}`` of every ``<mimic>`` tag."""
    out: dict[str, tuple[str, float, float]] = {}
    for joint in ET.fromstring(urdf).iter("joint"):
        tag = joint.find("mimic")
        if tag is not None:
            out[joint.attrib["name"]] = (
                tag.attrib["joint"],
                float(tag.attrib.get("multiplier", 1.0)),
                float(tag.attrib.get("offset", 0.0)),
            )
    return out


def coupling_from_urdf(urdf: str, model: pin.Model, model_full: pin.Model) -> Coupling:
    """Read ``<mimic>`` tags and build the coupling q_full = G·q_pin + offset.

    Only one-DOF joints (revolute, prismatic) may mimic or be mimicked, as in URDF.
    """
    mimic = mimic_tags(urdf)
    G = np.zeros((model_full.nq, model.nq))
    Gv = np.zeros((model_full.nv, model.nv))
    offset = np.zeros(model_full.nq)
    for jid in range(1, model_full.njoints):
        jname = model_full.names[jid]
        jf = model_full.joints[jid]
        if jname in mimic:
            primary, multiplier, off = mimic[jname]
            jp = model.joints[model.getJointId(primary)]
            G[jf.idx_q, jp.idx_q] = multiplier
            Gv[jf.idx_v, jp.idx_v] = multiplier
            offset[jf.idx_q] = off
        else:
            jm = model.joints[model.getJointId(jname)]
            for k in range(jm.nq):
                G[jf.idx_q + k, jm.idx_q + k] = 1.0
            for k in range(jm.nv):
                Gv[jf.idx_v + k, jm.idx_v + k] = 1.0
    full_names = tuple(
        model_full.names[j] for j in range(1, model_full.njoints) if model_full.joints[j].nq
    )
    return Coupling(G=G, Gv=Gv, offset=offset, full_names=full_names)
