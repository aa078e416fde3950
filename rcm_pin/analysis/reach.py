"""A proven bound on how far a frame can get from the base: what makes a target provably
unreachable (as opposed to not found by a numeric search).

Along the chain from the world to a frame, the frame's world position is the sum of each
joint placement's translation and each joint's own translation, every one rotated by the
joints before it; rotations keep lengths, so by the triangle inequality

    |p| ≤ Σ |t_placement| + Σ max |travel of a prismatic joint| + |t_frame|

over the joints of the chain (the no-mimic model: a follower's travel is bounded through
the mimic coupling q_full = G·q + offset from the coordinates' limits). A joint whose
translation has no such bound (a free-flyer, a planar or helical joint, a prismatic joint
without finite limits) makes the bound infinite: nothing is proved.
"""

from __future__ import annotations

import numpy as np

from rcm_pin.model.indices import frame_index
from rcm_pin.model.mechanism import Mechanism

#: Joints that only rotate about their origin (revolute, continuous, spherical, universal).
_ROTATING = ("JointModelR", "JointModelSpherical", "JointModelUniversal")
#: One-coordinate joints that translate along their axis.
_PRISMATIC = ("JointModelP",)


def _travel(mech: Mechanism, idx_q_full: int) -> float:
    """max |q_full[i]| of a one-coordinate joint of the no-mimic model over the joint box
    of the independent coordinates [m] (inf where a limit is infinite)."""
    lo = np.asarray(mech.model.lowerPositionLimit, dtype=float)
    hi = np.asarray(mech.model.upperPositionLimit, dtype=float)
    row = mech.coupling.G[idx_q_full]
    used = row != 0.0
    if not np.all(np.isfinite(lo[used]) & np.isfinite(hi[used])):
        return float("inf")
    bound = np.abs(row[used]) @ np.maximum(np.abs(lo[used]), np.abs(hi[used]))
    return float(bound + abs(mech.coupling.offset[idx_q_full]))


def reach_bound(mech: Mechanism, frame: str, extra: float = 0.0) -> float:
    """Upper bound of the distance of ``frame``'s origin from the world origin [m], over
    every configuration within the joint limits (module docstring), plus ``extra`` [m]
    (e.g. a tool beyond the frame); ``inf`` when no finite bound follows from the model.

    Raises:
        UnknownFrameError: no such frame (lists the frames).
    """
    model = mech.model_full
    f = model.frames[frame_index(model, frame, "frame")]
    total = float(np.linalg.norm(f.placement.translation)) + extra
    j = f.parentJoint
    while j > 0:
        joint = model.joints[j]
        kind = joint.shortname()
        total += float(np.linalg.norm(model.jointPlacements[j].translation))
        if kind.startswith(_PRISMATIC) and joint.nq == 1:
            total += _travel(mech, joint.idx_q)
        elif not kind.startswith(_ROTATING):
            return float("inf")
        j = model.parents[j]
    return total


__all__ = ["reach_bound"]
