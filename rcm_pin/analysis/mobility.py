"""Mobility (degrees of freedom): the structural formulas beside the rank of the closures.

Somov–Malyshev (spatial):

    W = 6n − 5·P5 − 4·P4 − 3·P3 − 2·P2 − P1

n: moving links; P_k: pairs of class k (a class-k pair removes k freedoms). Counted on
the no-mimic parse of a URDF: every moving body is a link, every revolute or prismatic
joint a class-5 pair, every mimic joint a gear mesh or belt, i.e. a class-1 pair (it
removes one freedom: the transmission equation q_m = k·q_p + c), and every loop closure a
cut pair: ``3d`` (points coincide) a spherical pair, class 3; ``6d`` a rigid joint, 6.
Planar mechanisms (every joint about one axis) are also counted by Chebyshev,
W = 3n − 2p₁ − 3p₀ (a point closure in the plane is a revolute pair, p₁; a ``6d`` closure
a rigid joint, p₀).

The formulas ignore the geometry; the rank does not: at a closed configuration the loops
leave nv − rank J_c freedoms (:func:`rcm_pin.model.newton.constraint_rank`). Where the
formula is below the rank count, that many closure equations are redundant (the
mechanism is over-constrained: a planar loop counted in space, a parallelogram).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass

import numpy as np

from rcm_pin.errors import InvalidInputError
from rcm_pin.model.constraints import plane_normal
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.newton import constraint_rank

#: URDF joint type -> class of the pair (freedoms it removes; 0: a free body).
PAIR_CLASS = {
    "revolute": 5,
    "continuous": 5,
    "prismatic": 5,
    "planar": 3,
    "floating": 0,
    "fixed": 0,
}


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
    rank_mobility: int | None = None
    chebyshev: int | None = None

    @property
    def redundant(self) -> int:
        """Closure equations the formula counts that the rank shows to be redundant."""
        return 0 if self.rank_mobility is None else self.rank_mobility - self.W

    def formula(self) -> str:
        """The formula with the numbers in it."""
        terms = " − ".join(
            f"{k}·{self.pairs[k]}" if k != 1 else f"{self.pairs[k]}"
            for k in sorted(self.pairs, reverse=True)
            if self.pairs[k]
        )
        return f"W = 6·{self.n} − {terms} = {self.W}"

    def describe(self) -> str:
        """The formula, Chebyshev's count (planar) and the rank count on one line."""
        text = f"{self.formula()} (Somov–Malyshev)"
        if self.chebyshev is not None:
            text += f"; Chebyshev W = {self.chebyshev}"
        if self.rank_mobility is not None:
            text += f"; from the rank: {self.rank_mobility}"
            if self.redundant:
                text += f" ({self.redundant} redundant closure equations)"
        return text


def somov_malyshev(n: int, pairs: dict[int, int]) -> int:
    """W = 6n − Σ_k k·P_k: a pair of class k imposes k constraints.

    Args:
        n: moving links.
        pairs: pair class (5 = one freedom left, 1 = five freedoms left) -> count.
    """
    return 6 * n - sum(k * count for k, count in pairs.items())


def mobility(mech: Mechanism, q: np.ndarray | None = None) -> MobilityCount:
    """Count links and pairs of a mechanism's URDF (and closures) and apply the formulas.

    Args:
        mech: the mechanism.
        q: a closed configuration for the rank count (default: the family's ``home``, or
            the first assembly of its drives where ``home`` is left open);
            serial mechanisms: the rank count is the number of coordinates.
    """
    root = ET.fromstring(mech.urdf)
    p5 = p1 = n = 0
    pairs: dict[int, int] = {}
    for joint in root.findall("joint"):  # not the <joint> of <transmission>
        kind = joint.attrib.get("type", "")
        if kind not in PAIR_CLASS:
            raise InvalidInputError(
                f"joint {joint.attrib.get('name', '?')!r} has type {kind!r}; valid: "
                + ", ".join(sorted(PAIR_CLASS))
            )
        if kind == "fixed":
            continue
        n += 1  # a tree: each moving joint adds one moving link (fixed joints merge links)
        if PAIR_CLASS[kind]:
            pairs[PAIR_CLASS[kind]] = pairs.get(PAIR_CLASS[kind], 0) + 1
        p5 += PAIR_CLASS[kind] == 5
        if joint.find("mimic") is not None:
            p1 += 1
    pairs = {**pairs, 1: pairs.get(1, 0) + p1}
    if mech.loops is None:
        return MobilityCount(n=n, pairs=pairs, W=somov_malyshev(n, pairs), rank_mobility=mech.nv)
    for c in mech.loops.closures:
        k = 3 if c.kind == "3d" else 6
        pairs[k] = pairs.get(k, 0) + 1
    if q is None:
        q = _assembled(mech)
    rank = mech.nv - constraint_rank(mech.residual_and_jacobian(q)[1])
    cheb = None
    if plane_normal(mech.model) is not None and not mech.coupling.has_mimic:
        six = sum(c.kind == "6d" for c in mech.loops.closures)  # a weld in the plane: 3
        cheb = 3 * n - 2 * (p5 + len(mech.loops.closures) - six) - 3 * six
    return MobilityCount(
        n=n, pairs=pairs, W=somov_malyshev(n, pairs), rank_mobility=rank, chebyshev=cheb
    )


def _assembled(mech: Mechanism) -> np.ndarray:
    """``home``, or where its loops are left open, the first assembly of its drives."""
    from rcm_pin.analysis.position import forward
    from rcm_pin.errors import RcmPinError

    q = mech.home
    if float(np.max(np.abs(mech.closure_residual(mech.q_pin(q))), initial=0.0)) < 1e-9:
        return q
    try:
        return forward(mech, q[mech.require_loops().drive_q]).solutions[0].q
    except RcmPinError:
        return q  # no assembly: the rank count at the open home (the message of describe)


__all__ = ["MobilityCount", "mobility", "somov_malyshev"]
