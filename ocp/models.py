"""Where ``ocp`` gets its models: the catalogue, or any URDF by path.

Every catalogue entry (``rcm_pin.names()``: the RCM mechanisms, the closed planar ones,
and the example-robot-data arms ``panda`` and ``ur5``) is a :class:`rcm_pin.Mechanism`
from :func:`rcm_pin.load`; :class:`~ocp.ik.IKProblem` and
:class:`~ocp.tracking.TrackingOCP` take it directly (tool frame, limits, loops) or any
``pin.Model`` with a frame. Nothing here reads the repository: the catalogue finds its
files through the installed packages.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeAlias

import pinocchio as pin

import rcm_pin
from ocp.symbolic import SymbolicModel
from rcm_pin.catalog import ENTRIES
from rcm_pin.errors import InvalidInputError
from rcm_pin.model.build import parse_models
from rcm_pin.model.mechanism import Mechanism

#: What the CasADi layer accepts as a model.
ModelSource: TypeAlias = pin.Model | SymbolicModel | Mechanism


@dataclass(frozen=True)
class Resolved:
    """A model source resolved to its symbolic twin and a frame.

    Attributes:
        sm: the symbolic twin of the (mimic) Pinocchio model.
        frame_id: Pinocchio frame id of the frame the problem is about.
        mechanism: the Mechanism when one was given (None for a bare model).
    """

    sm: SymbolicModel
    frame_id: int
    mechanism: Mechanism | None


def load(name_or_path: str | Path, **kwargs: Any) -> Mechanism:
    """:func:`rcm_pin.load`: a catalogue name (``"panda"``, ``"planar_3rrr"``, ...) or a
    URDF / xacro path, with ``tool_frame``, ``rcm_frame`` and xacro arguments."""
    return rcm_pin.load(name_or_path, **kwargs)


def catalogue() -> tuple[str, ...]:
    """Every catalogue name (serial and closed mechanisms, the reference arms)."""
    return tuple(rcm_pin.names())


def serial_names() -> tuple[str, ...]:
    """The catalogue names of the serial mechanisms (no loop closures)."""
    return tuple(e.name for e in ENTRIES if e.kind == "serial")


def model_from_urdf(path: str | Path, mimic: bool = True) -> pin.Model:
    """Parse a URDF file (mimic joints kept as ``JointModelMimic`` by default) as
    :func:`rcm_pin.load` does: continuous joints of mimic pairs as unbounded revolute
    (``docs/joints.md``).

    Raises:
        InvalidInputError: no file at ``path``, or a URDF Pinocchio cannot build.
    """
    p = Path(path)
    if not p.is_file():
        raise InvalidInputError(f"no URDF file at {p}; valid: the path of an existing .urdf")
    model, model_full = parse_models(p.read_text(), p.stem)
    return model if mimic else model_full


def require_serial(source: Any, what: str) -> None:
    """Refuse a closed Mechanism where only trees make sense (``what`` names the problem).

    Raises:
        InvalidInputError: ``source`` is a Mechanism with loop closures; the message lists
            the serial catalogue entries.
    """
    if isinstance(source, Mechanism) and source.loops is not None:
        raise InvalidInputError(
            f"{what} takes a serial mechanism; {source.name} has loop closures (its efforts "
            "need the constraint forces of the loops); valid: a serial rcm_pin.Mechanism "
            f"({', '.join(serial_names())}) or a pin.Model of a tree"
        )


def resolve(source: ModelSource, frame: str | int | None) -> Resolved:
    """The symbolic twin and frame of a Mechanism (default frame: its tool / output
    frame) or of a ``pin.Model`` / :class:`SymbolicModel` (frame required).

    Raises:
        InvalidInputError: a bare model without a frame, or not a model at all.
        UnknownFrameError: a frame the model does not have.
    """
    if isinstance(source, Mechanism):
        sm = SymbolicModel(source.model)
        fid = source.tool_frame_id if frame is None else sm.frame_id(frame)
        return Resolved(sm, fid, source)
    if isinstance(source, (pin.Model, SymbolicModel)):
        if frame is None:
            raise InvalidInputError(
                "a frame is required with a bare pin.Model; valid: a frame name or id, or "
                "pass an rcm_pin.Mechanism (its tool frame is the default)"
            )
        sm = source if isinstance(source, SymbolicModel) else SymbolicModel(source)
        return Resolved(sm, sm.frame_id(frame), None)
    raise InvalidInputError(
        f"model must be an rcm_pin.Mechanism, a pin.Model or an ocp.SymbolicModel; "
        f"got {type(source).__name__}"
    )


__all__ = [
    "ModelSource",
    "Resolved",
    "catalogue",
    "load",
    "model_from_urdf",
    "require_serial",
    "resolve",
    "serial_names",
]
