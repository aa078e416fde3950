"""Mobility (degrees of freedom) by the Somov–Malyshev formula from a model's joints.

    W = 6n − 5·P5 − 4·P4 − 3·P3 − 2·P2 − P1

n: moving links; P_k: pairs of class k (a class-k pair removes k freedoms). Counted on
the no-mimic parse of a URDF: every moving body is a link, every revolute or prismatic
joint a class-5 pair, and every mimic joint a gear mesh or belt, i.e. a class-1 pair
(it removes one freedom: the transmission equation q_m = k·q_p + c).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass

from rcm_pin.mechanism import Mechanism


@dataclass(frozen=True)
class MobilityCount:
    """The inventory and the resulting mobility.

    Attributes:
        n: moving links.
        pairs: class -> count (5: one-DOF pairs, 4: cylindrical, ..., 1: gear meshes).
        W: the Somov–Malyshev mobility.
    """

    n: int
    pairs: dict[int, int]
    W: int

    def formula(self) -> str:
        """The formula with the numbers in it."""
        terms = " − ".join(
            f"{k}·{self.pairs[k]}" if k != 1 else f"{self.pairs[k]}"
            for k in sorted(self.pairs, reverse=True)
            if self.pairs[k]
        )
        return f"W = 6·{self.n} − {terms} = {self.W}"


def somov_malyshev(n: int, pairs: dict[int, int]) -> int:
    """W = 6n − Σ_k k·P_k: a pair of class k imposes k constraints.

    Args:
        n: moving links.
        pairs: pair class (5 = one freedom left, 1 = five freedoms left) -> count.
    """
    return 6 * n - sum(k * count for k, count in pairs.items())


def mobility(mech: Mechanism) -> MobilityCount:
    """Count links and pairs of a mechanism's URDF and apply Somov–Malyshev."""
    root = ET.fromstring(mech.urdf)
    p5 = p1 = 0
    for joint in root.iter("joint"):
        kind = joint.attrib["type"]
        if kind in {"revolute", "prismatic", "continuous"}:
            p5 += 1
            if joint.find("mimic") is not None:
                p1 += 1
        elif kind not in {"fixed"}:
            raise ValueError(f"joint type {kind} not counted")  # pragma: no cover
    n = p5  # a tree: each one-DOF joint adds one moving link (fixed joints merge links)
    pairs = {5: p5, 1: p1}
    return MobilityCount(n=n, pairs=pairs, W=somov_malyshev(n, pairs))
