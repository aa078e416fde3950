"""Distinct assembly modes of a closed mechanism's direct problem.

Two solutions of the same drive values are the same assembly mode when they place the
mechanism the same way: their outputs agree and the origin of every frame (bodies,
joints, closure and operational frames) sits at the same world point, each within
:data:`MODE_TOL` [m, rad]. Configurations that differ only by a self-motion (passive
joints moving while drives, output and frame origins stay, e.g. a link spinning about the
axis through its two joints, or two coaxial joints of a ``6d`` closure turning against
each other, as LAAS's files write revolute closures) are one mode, the first found kept.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from rcm_pin.analysis.results import PositionSolution
from rcm_pin.model.mechanism import Mechanism

#: Two assembly modes are the same below this difference of output and frame origins.
MODE_TOL = 1e-7


def placement_key(mech: Mechanism, q: np.ndarray) -> np.ndarray:
    """Output value and world positions of every frame origin at configuration q."""
    q_pin = mech.q_pin(q)
    pin.framesForwardKinematics(mech.model, mech.data, q_pin)
    origins = np.concatenate([m.translation for m in mech.data.oMf])
    return np.concatenate([mech.output.value(mech.data.oMf[mech.output.frame_id]), origins])


def distinct_modes(
    mech: Mechanism, sols: Sequence[PositionSolution], tol: float = MODE_TOL
) -> list[PositionSolution]:
    """The solutions with distinct placements (module docstring), first occurrence kept."""
    out: list[PositionSolution] = []
    keys: list[np.ndarray] = []
    for s in sols:
        key = placement_key(mech, s.q)
        if not any(float(np.max(np.abs(key - k), initial=0.0)) < tol for k in keys):
            out.append(s)
            keys.append(key)
    return out


def self_motion(mech: Mechanism, q: np.ndarray) -> int:
    """Freedoms left with the drives held at a closed configuration q: nv − rank J_c − k
    (0 for a mechanism whose drives fix every joint)."""
    from rcm_pin.model.newton import constraint_rank

    jac = mech.constraint_jacobian(mech.q_pin(q))
    return mech.nv - constraint_rank(jac) - mech.require_loops().dof


def note(mech: Mechanism, sols: Sequence[PositionSolution]) -> str:
    """``""``, or the method note of a direct problem whose modes lie on a self-motion that
    moves frames (those modes are not merged)."""
    extra = self_motion(mech, sols[0].q) if sols else 0
    if extra <= 0:
        return ""
    return (
        f"; self-motion: nv − rank J_c exceeds the {mech.require_loops().dof} drives by "
        f"{extra}, modes along it that move frames are listed apart"
    )


__all__ = ["MODE_TOL", "distinct_modes", "note", "placement_key", "self_motion"]
