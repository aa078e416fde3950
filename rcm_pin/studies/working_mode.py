"""The closed configuration of a working mode at an output pose (for the paper-004 studies
and ``rcm-pin vibrations``): the inverse position problem, one of its labelled solutions."""

from __future__ import annotations

from typing import Any

import numpy as np

from rcm_pin.analysis.position import inverse
from rcm_pin.errors import InvalidInputError
from rcm_pin.model.mechanism import Mechanism


def configuration_at(
    mech: Mechanism, pose: np.ndarray, mode: str | None = None, coords: Any = None
) -> tuple[np.ndarray, str]:
    """(closed configuration, working-mode label) at an output pose; default: the mode the
    inverse problem lists first (as ``rcm-pin ik`` prints them).

    Raises:
        InvalidInputError: ``mode`` is not a working mode at that pose (lists the valid ones).
        UnreachablePoseError: the pose is outside the workspace.
    """
    sols = inverse(mech, pose, coords).solutions
    if mode is None:
        return sols[0].q, sols[0].mode
    found = {s.mode: s.q for s in sols}
    if mode not in found:
        raise InvalidInputError(
            f"mode {mode!r} is not a working mode of {mech.name} at this pose; valid: "
            + ", ".join(found)
        )
    return found[mode], mode


__all__ = ["configuration_at"]
