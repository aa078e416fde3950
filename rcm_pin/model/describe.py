"""The one-line description of a :class:`~rcm_pin.model.mechanism.Mechanism` (its repr).

Name, family, the joints of the coordinates, xacro arguments, the tool and RCM frames
(serial) or the output frame, closures and drives (closed); never the URDF text.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from rcm_pin.model.mechanism import Mechanism


def describe(mech: Mechanism) -> str:
    """``Mechanism(name=..., family=..., coordinates=..., ...)`` on one line."""
    parts = [f"name={mech.name!r}", f"family={mech.family.name!r}"]
    parts += [f"coordinates={' '.join(mech.joint_names)!r}"]
    parts += [f"args={dict(mech.args)!r}"] if mech.args else []
    if mech.loops is None:
        rcm = "" if mech.rcm is None else mech.model.frames[mech.rcm.point_frame_id].name
        parts += [f"tool_frame={mech.output.frame!r}"] + [f"rcm_frame={rcm!r}"] * bool(rcm)
        return f"Mechanism({', '.join([*parts, 'closures=None'])})"
    kinds = [c.kind for c in mech.loops.closures]
    closures = " + ".join(f"{kinds.count(k)} × {k}" for k in dict.fromkeys(kinds))
    parts += [f"output_frame={mech.output.frame!r}", f"closures={closures!r}"]
    return f"Mechanism({', '.join(parts)}, drives={' '.join(mech.loops.drives)!r})"


__all__ = ["describe"]
