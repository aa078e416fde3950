"""Design checks of the eye linkage: interference of its links, Listing's-law roll.

Interference: a Pinocchio ``GeometryModel`` of the links' boxes (the URDF visuals) and coal
distances between every pair of *non-adjacent* links over a grid of the two gaze drives
(θ1, θ2): links are adjacent when a joint connects them (the frame counts as the parent of
the pairs O1, O2, O3 and the lid) or a cut pair does (B: coupler–rocker, P: link 5–eye 2,
K: finger–yaw crank), and link 5 is adjacent to the Assur group's links (slot and pin).
The result is the smallest clearance of every pair of links (over the visuals of each: a
link may have several, e.g. a hub besides its bar), where it occurs, and the clearance map
(the smallest clearance over all pairs at each grid point).

Listing's law: the eye turns from the primary (straight) direction about an axis in the
frontal plane (⊥ X). For the Helmholtz angles of this linkage, R = Ry(−e) Rz(α) Rx(ρ), the
quaternion's x component vanishes iff

    tan(ρ/2) = tan(e/2) tan(α/2),

the roll motor 4 must add; the second route builds the Listing rotation (axis X × d, angle
∠(X, d)) and reads its roll (:func:`listing_roll_from_rotation`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from rcm_pin.analysis.capabilities import position_solver
from rcm_pin.mechanisms.eye_4dof.closed_form import gaze_angles
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.rotations import rot_y, rot_z

#: Joints whose links touch through a cut pair (the closures B, P, K).
CUT_PAIRS = (("A", "O2"), ("D", "L"), ("U", "O3"))
#: Link 5 and the Assur group's links 7, 8, 9 slide inside each other (slot E, pin U): all
#: mutually adjacent.
GROUP = ("D", "E", "F", "U")


@dataclass(frozen=True)
class Clearance:
    """Interference over a drive grid.

    Attributes:
        pairs: the checked pairs (link names).
        minimum: smallest distance of each pair [m] (negative: penetration depth unknown, 0).
        where: the drives (θ1, θ2) [rad] of each pair's minimum.
        theta1, theta2: the grid; map: smallest distance over all pairs at each grid point.
    """

    pairs: tuple[tuple[str, str], ...]
    minimum: np.ndarray
    where: np.ndarray
    theta1: np.ndarray
    theta2: np.ndarray
    map: np.ndarray

    @property
    def worst(self) -> tuple[tuple[str, str], float, np.ndarray]:
        """(pair, clearance [m], drives) of the smallest clearance."""
        i = int(np.argmin(self.minimum))
        return self.pairs[i], float(self.minimum[i]), self.where[i]

    def colliding(self, tol: float = 0.0) -> list[tuple[str, str]]:
        """Pairs whose clearance is ≤ tol somewhere on the grid."""
        return [p for p, d in zip(self.pairs, self.minimum, strict=True) if d <= tol]


def geometry_model(mech: Mechanism) -> tuple[pin.GeometryModel, list[tuple[int, int]]]:
    """The link boxes and the non-adjacent pairs (indices into the geometry objects)."""
    gm = pin.buildGeomFromUrdfString(mech.model, mech.urdf, pin.GeometryType.VISUAL)
    model, adjacent = mech.model, set()
    for j in range(1, model.njoints):
        adjacent.add(frozenset((j, model.parents[j])))
    for a, b in CUT_PAIRS:
        adjacent.add(frozenset((model.getJointId(a), model.getJointId(b))))
    for i, a in enumerate(GROUP):
        for b in GROUP[i + 1 :]:
            adjacent.add(frozenset((model.getJointId(a), model.getJointId(b))))
    objects = gm.geometryObjects
    pairs = []
    for i in range(len(objects)):
        for k in range(i + 1, len(objects)):
            ji, jk = objects[i].parentJoint, objects[k].parentJoint
            if ji != jk and frozenset((ji, jk)) not in adjacent:
                gm.addCollisionPair(pin.CollisionPair(i, k))
                pairs.append((i, k))
    return gm, pairs


def _link(name: str) -> str:
    return name.rsplit("_", 1)[0]


def interference(mech: Mechanism, n: int = 13, lid: float = 0.0, roll: float = 0.0) -> Clearance:
    """Coal distances of every non-adjacent pair of links over an n × n grid of (θ1, θ2) ∈
    [−π, π)² (each pair's smallest over the visuals of its two links)."""
    gm, pairs = geometry_model(mech)
    gd = pin.GeometryData(gm)
    objects = gm.geometryObjects
    links = [(_link(objects[i].name), _link(objects[k].name)) for i, k in pairs]
    names = tuple(dict.fromkeys(links))  # the link pairs, in first-object order
    group = np.array([names.index(p) for p in links], dtype=int)
    theta = np.linspace(-np.pi, np.pi, n, endpoint=False)
    minimum = np.full(len(names), np.inf)
    where = np.zeros((len(names), 2))
    cmap = np.full((n, n), np.inf)
    for a, t1 in enumerate(theta):
        for b, t2 in enumerate(theta):
            sols = position_solver(mech).direct(mech, np.array([t1, t2, lid, roll])).seeds
            if not sols:
                continue
            pin.computeDistances(mech.model, mech.data, gm, gd, sols[0])
            d = np.full(len(names), np.inf)
            np.minimum.at(d, group, [r.min_distance for r in gd.distanceResults])
            cmap[a, b] = d.min()
            better = d < minimum
            minimum[better] = d[better]
            where[better] = (t1, t2)
    return Clearance(names, minimum, where, theta, theta, cmap)


def listing_roll(elevation: float, azimuth: float) -> float:
    """ρ [rad] with tan(ρ/2) = tan(e/2) tan(α/2) (module docstring)."""
    return 2.0 * math.atan(math.tan(elevation / 2) * math.tan(azimuth / 2))


def listing_roll_from_rotation(elevation: float, azimuth: float) -> float:
    """The same from the Listing rotation about X × d by ∠(X, d), d the gaze direction."""
    d = rot_y(-elevation) @ rot_z(azimuth) @ np.array([1.0, 0.0, 0.0])
    axis = np.cross([1.0, 0.0, 0.0], d)
    s = float(np.linalg.norm(axis))
    if s == 0.0:
        return 0.0
    rot = pin.exp3(axis / s * math.atan2(s, float(d[0])))
    return gaze_angles(rot)[2]


__all__ = [
    "CUT_PAIRS",
    "GROUP",
    "Clearance",
    "geometry_model",
    "interference",
    "listing_roll",
    "listing_roll_from_rotation",
]
