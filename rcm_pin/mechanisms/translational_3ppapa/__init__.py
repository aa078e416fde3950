"""The translational 3-PPaPa parallel mechanism of paper 004 (Fig. 4): the family.

Two models of the same geometry (``xacro/translational_3ppapa.urdf.xacro``): the crank +
mimic parallelograms (``translational_3ppapa``) and the 4R-loop parallelograms
(``translational_3ppapa_loops``, over-constrained). The paper's equations are in
:mod:`.closed_form`, the linear accuracy theory in :mod:`.accuracy`.
"""

from __future__ import annotations

import numpy as np

from rcm_pin.errors import UnreachablePoseError
from rcm_pin.mechanisms.translational_3ppapa.closed_form import (
    LEG_SIGNS,
    MODES,
    POSITIVE_ARGS,
    SIGN_PATTERNS,
    Geometry3PPaPa,
    a_from_angles,
    a_matrix,
    direct_position,
    inverse_position,
    label,
    leg_angles,
    local,
    platform_point,
    residual,
)
from rcm_pin.model.family import Branch, Family
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output


def geometry(mech: Mechanism) -> Geometry3PPaPa:
    """The closed-form geometry of a loaded 3-PPaPa (from its sidecar parameters)."""
    return Geometry3PPaPa.from_params(mech._require_loops().params)


def joint_values(q: np.ndarray, angles: np.ndarray) -> dict[str, float]:
    """Every tree joint [m, rad]: drives P<i>, cranks c<i><k>, couplers k<i><k> = −crank,
    second cranks d<i><k> = crank (the parallelogram branch)."""
    out: dict[str, float] = {}
    for i in range(3):
        out[f"P{i + 1}"] = float(q[i])
        for k in range(2):
            t = float(angles[i, k])
            out[f"c{i + 1}{k + 1}"], out[f"k{i + 1}{k + 1}"], out[f"d{i + 1}{k + 1}"] = t, -t, t
    return out


def mech_q(mech: Mechanism, q: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """Mechanism coordinates of drives q and crank angles (3, 2) (either model)."""
    values = joint_values(q, angles)
    return np.array([values[n] for n in mech.joint_names])


def crank_angles(mech: Mechanism, q: np.ndarray) -> np.ndarray:
    """(3, 2) crank angles θ_i, φ_i read from Mechanism coordinates q."""
    names = list(mech.joint_names)
    return np.array([[q[names.index(f"c{i}{k}")] for k in (1, 2)] for i in (1, 2, 3)])


class Translational3PPaPaFamily(Family):
    """Hooks of the 3-PPaPa: 64 working modes, assembly modes, A (paper) and B = I."""

    name = "translational_3ppapa"
    description = "translational 3-PPaPa parallel mechanism (paper 004 Fig. 4)"
    closed = True

    def inverse_position(
        self, mech: Mechanism, target: np.ndarray, output: Output
    ) -> list[Branch] | None:
        """Every working mode reaching P (the paper's explicit solution)."""
        if output.coords != ("x", "y", "z"):
            return None
        g, p = geometry(mech), np.asarray(target, dtype=float)
        sols = inverse_position(g, p)
        if not sols:
            r = min(g.l1, g.l2)
            raise UnreachablePoseError(
                f"{mech.name}: platform point {p.tolist()} m is out of reach (a crank "
                f"cannot span it); valid: |x|, |y|, |z| <= min(l1, l2) = {r:.6g} m"
            )
        return [Branch(mech_q(mech, q, ang), lab) for lab, q, ang in sols]

    def direct_position(self, mech: Mechanism, drives: np.ndarray) -> list[np.ndarray] | None:
        """Every assembly mode the seeded Newton finds (``++/++/++`` first)."""
        g = geometry(mech)
        out = []
        for lab, p in direct_position(g, np.asarray(drives, dtype=float)):
            pattern = SIGN_PATTERNS[MODES.index(lab)]
            legs = [leg_angles(g, p, i, pattern[i]) for i in range(3)]
            ang = np.array([x[1:] for x in legs if x is not None])
            out.append(mech_q(mech, np.asarray(drives, dtype=float), ang))
        return out

    def mode_labels(self, mech: Mechanism) -> tuple[str, ...]:
        """The 64 sign patterns ``s11s12/s21s22/s31s32``."""
        return MODES

    def configurations(self, mech: Mechanism) -> dict[str, np.ndarray]:
        """``home``: P = 0, every crank along its drive axis (mode ``++/++/++``)."""
        _, q, ang = inverse_position(geometry(mech), np.zeros(3))[0]
        return {"home": mech_q(mech, q, ang)}

    def ab_matrices(self, mech: Mechanism, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """A = ∂F/∂p from the crank angles and B = I (both dimensionless)."""
        return a_from_angles(crank_angles(mech, q)), np.eye(3)


FAMILY = Translational3PPaPaFamily()

__all__ = [
    "FAMILY",
    "LEG_SIGNS",
    "MODES",
    "POSITIVE_ARGS",
    "SIGN_PATTERNS",
    "Geometry3PPaPa",
    "Translational3PPaPaFamily",
    "a_from_angles",
    "a_matrix",
    "crank_angles",
    "direct_position",
    "geometry",
    "inverse_position",
    "joint_values",
    "label",
    "leg_angles",
    "local",
    "mech_q",
    "platform_point",
    "residual",
]
