"""The output of a closed mechanism: from its sidecar, the caller, or none at all.

A LAAS ``robot.yaml`` names closures and motors only; the output (the frame whose pose
answers the position problems, and which of its coordinates) is optional. The rule:

1. ``output_frame`` given by the caller (``rcm_pin.load(..., output_frame=...)``,
   ``--output-frame``; ``tool_frame`` / ``--tool-frame`` mean the same) replaces the
   sidecar's frame; ``output_coords`` the sidecar's coordinates;
2. coordinates not given anywhere default to the translation ``x y z``, without the
   world axis a planar tree moves across (a five-bar in the x-y plane: ``x y``);
3. no frame anywhere: :data:`~rcm_pin.model.output.NO_OUTPUT`. Forward kinematics,
   closures, dynamics, vibrations, singularities (type 2) and simulation work without an
   output; the commands that need one call :func:`require_output`, which lists the
   candidate frames and the ways to give one.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError, UnknownFrameError
from rcm_pin.model.constraints import plane_normal
from rcm_pin.model.output import TOKENS, Output
from rcm_pin.model.sidecar import LoopSpec

if TYPE_CHECKING:
    from rcm_pin.model.mechanism import Mechanism

#: How to name an output, quoted by :func:`require_output`.
HOW = (
    "--output-frame FRAME [--output-coords 'x y'] on the command line, or "
    "rcm_pin.load(path, output_frame=FRAME, output_coords=('x', 'y'))"
)


def default_coords(model: pin.Model) -> tuple[str, ...]:
    """``x y z`` without the world axis normal to a planar tree (rule 2)."""
    normal = plane_normal(model)
    if normal is None:
        return ("x", "y", "z")
    axis = int(np.argmax(np.abs(normal)))
    if abs(abs(normal[axis]) - 1.0) > 1e-12:
        return ("x", "y", "z")  # a plane that no world axis is normal to
    return tuple(c for i, c in enumerate(("x", "y", "z")) if i != axis)


def parse_coords(coords: object) -> tuple[str, ...]:
    """Output coordinates from ``"x y"`` / ``"x,y"`` or a sequence of tokens.

    Raises:
        InvalidInputError: not a string or a sequence of strings, or an unknown token.
    """
    if isinstance(coords, str):
        tokens = tuple(coords.replace(",", " ").split())
    elif isinstance(coords, (list, tuple)) and all(isinstance(c, str) for c in coords):
        tokens = tuple(coords)
    else:
        raise InvalidInputError(
            f"output_coords {coords!r}; valid: tokens from {', '.join(TOKENS)}, e.g. 'x y'"
        )
    bad = [c for c in tokens if c not in TOKENS]
    if bad or not tokens:
        raise InvalidInputError(
            f"output_coords {list(tokens)}; valid: one or more of {', '.join(TOKENS)}"
        )
    return tokens


def closed_spec(
    model: pin.Model,
    spec: LoopSpec,
    output_frame: str | None = None,
    output_coords: tuple[str, ...] | None = None,
) -> LoopSpec:
    """The loop spec with the output of the module docstring's rule.

    Raises:
        InvalidInputError: ``output_coords`` without any output frame.
    """
    frame = output_frame or spec.output_frame
    if not frame:
        if output_coords:
            raise InvalidInputError(
                f"output_coords {list(output_coords)} given but {model.name} names no output "
                f"frame; valid: also an output frame ({HOW})"
            )
        return spec
    coords = output_coords or spec.output_coords or default_coords(model)
    return replace(spec, output_frame=frame, output_coords=coords)


def candidate_frames(mech: Mechanism) -> list[str]:
    """Body and operational frames of the model (the candidates for an output)."""
    kinds = (pin.FrameType.BODY, pin.FrameType.OP_FRAME)
    names = [f.name for f in mech.model.frames if f.type in kinds and f.name != "universe"]
    return sorted(set(names), key=names.index)


def require_output(mech: Mechanism, what: str) -> Output:
    """The mechanism's output, or a typed error for a closed one that names none.

    Args:
        mech: the mechanism.
        what: the command or analysis that needs the output (for the message).

    Raises:
        UnknownFrameError: no output frame; the message lists the candidate frames and
            how to give one (:data:`HOW`).
    """
    if mech.output.present:
        return mech.output
    raise UnknownFrameError(
        f"{what} of {mech.name} needs an output frame and its sidecar names none; valid: "
        f"{HOW} with FRAME one of {', '.join(candidate_frames(mech))}"
    )


__all__ = [
    "HOW",
    "candidate_frames",
    "closed_spec",
    "default_coords",
    "parse_coords",
    "require_output",
]
