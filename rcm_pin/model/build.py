"""Building a :class:`~rcm_pin.model.mechanism.Mechanism` from URDF text.

What the URDF tree cannot say comes from its ``<rcm_pin>`` element or a YAML sidecar
(:mod:`rcm_pin.model.sidecar`), or from the caller (``tool_frame``, ``rcm_frame``). The
tool frame is never guessed: without one from any of these sources the build fails with
:class:`~rcm_pin.errors.UnknownFrameError`, listing the candidate frames.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import pinocchio as pin

from rcm_pin.errors import InvalidInputError, UnknownFrameError
from rcm_pin.model import joints as jt
from rcm_pin.model.coupling import coupling_from_urdf
from rcm_pin.model.family import Family
from rcm_pin.model.indices import frame_index
from rcm_pin.model.limits import free_missing_limits
from rcm_pin.model.loops import build_loops
from rcm_pin.model.mechanism import Mechanism, RcmSpec
from rcm_pin.model.output import POSE, Output
from rcm_pin.model.output_choice import closed_spec
from rcm_pin.model.sidecar import Description

_AXES = {"x": 0, "y": 1, "z": 2}


def parse_models(urdf: str, name: str, closed: bool = False) -> tuple[pin.Model, pin.Model]:
    """The mimic and no-mimic Pinocchio models of URDF text (continuous joints of mimic
    pairs, and of a ``closed`` mechanism every continuous joint, parsed as unbounded
    revolute: :func:`rcm_pin.model.joints.revolute_mimics`).

    Raises:
        InvalidInputError: not a URDF robot, or Pinocchio (urdfdom) cannot build a model.
    """
    text, unbounded = jt.revolute_mimics(urdf, name, every_continuous=closed)
    try:
        model = pin.buildModelFromXML(text, mimic=True)
        model_full = pin.buildModelFromXML(text)
    except (RuntimeError, ValueError) as exc:
        raise InvalidInputError(jt.parse_failure(text, name, exc)) from None
    jt.unbound(model, unbounded)
    jt.unbound(model_full, unbounded)
    return model, model_full


def candidate_tool_frames(model: pin.Model) -> list[str]:
    """Frames a tool could be: body and operational frames, leaves of the tree last."""
    kinds = (pin.FrameType.BODY, pin.FrameType.OP_FRAME)
    names = [f.name for f in model.frames if f.type in kinds and f.name != "universe"]
    return sorted(set(names), key=names.index)


def build_mechanism(
    urdf: str,
    *,
    name: str,
    description: Description,
    family: Family | None = None,
    args: Mapping[str, Any] | None = None,
    tool_frame: str | None = None,
    rcm_frame: str | None = None,
    output_coords: tuple[str, ...] | None = None,
    rebuild: Callable[..., Mechanism] | None = None,
    source: Path | None = None,
    rcm_axis_frame: str | None = None,
    rcm_axis: str | None = None,
) -> Mechanism:
    """A :class:`Mechanism` from URDF text and its description.

    Args:
        urdf: URDF XML text.
        name: mechanism name (catalogue name or file stem).
        description: the ``<rcm_pin>`` element or sidecar contents.
        family: the family (default: the generic :class:`Family`).
        args: xacro arguments it was rendered with.
        tool_frame: tool frame (closed: output frame); overrides the description.
        output_coords: closed: output coordinates (:mod:`rcm_pin.model.output_choice`).
        rcm_frame: frame of the remote centre; overrides the description.
        rcm_axis_frame: frame whose ``rcm_axis`` is the shaft (insertion) line; overrides
            the description (default there: the tool frame).
        rcm_axis: ``x``, ``y`` or ``z``; overrides the description (default ``z``).
        rebuild: renders the same source with other arguments (for design sensitivities).
        source: the xacro file rendered.

    Raises:
        UnknownFrameError: no tool frame known (lists the candidates), or a named frame or
            joint the model does not have.
        InvalidInputError: malformed URDF or loop description, an ``rcm_axis`` other than
            x, y, z, or an RCM axis without an RCM point.
    """
    model, model_full = parse_models(urdf, name, closed=description.loops is not None)
    model.name = model_full.name = name  # messages name the mechanism, not the URDF robot
    free_missing_limits(urdf, model, model_full)  # no <limit> range: unbounded, not [0, 0]
    coupling = coupling_from_urdf(urdf, model, model_full)
    loops = None
    if description.loops is not None:
        spec = closed_spec(model, description.loops, tool_frame, output_coords)
        loops = build_loops(model, spec)
    elif output_coords:
        raise InvalidInputError(
            f"{name}: output_coords applies to closed mechanisms; a serial tool's output is "
            "its pose (valid: no output_coords)"
        )
    named = description.coordinates if loops is None else ()
    coords = jt.coordinates(model, named)
    if loops is not None:
        output = loops.output
    else:
        tool = tool_frame or description.tool_frame
        if not tool:
            raise UnknownFrameError(
                f"{name}: the tool frame is not known (no tool_frame argument, no <rcm_pin "
                "tool_frame=...> element, no sidecar); valid: tool_frame=one of "
                + ", ".join(candidate_tool_frames(model))
            )
        output = Output(tool, POSE, frame_index(model, tool, "tool frame"))
    rcm = _rcm(model, description, rcm_frame, output, rcm_axis_frame, rcm_axis)
    return Mechanism(
        name=name,
        urdf=urdf,
        args={k: str(v) for k, v in (args or {}).items()},
        model=model,
        model_full=model_full,
        coupling=coupling,
        coordinate_names=tuple(f"q{i + 1}" for i in range(len(coords.q_index))),
        joint_names=coords.joints,
        q_index=coords.q_index,
        v_index=coords.v_index,
        lower=coords.lower,
        upper=coords.upper,
        revolute=coords.revolute,
        continuous=coords.continuous,
        output=output,
        family=family or Family(),
        loops=loops,
        rcm=rcm,
        rebuild=rebuild,
        source=source,
    )


def _rcm(
    model: pin.Model,
    desc: Description,
    rcm_frame: str | None,
    output: Output,
    rcm_axis_frame: str | None = None,
    rcm_axis: str | None = None,
) -> RcmSpec | None:
    """The RCM point and shaft line: the arguments, else the description; the shaft is the
    ``rcm_axis`` (default z) of ``rcm_axis_frame`` (default the tool frame)."""
    point = rcm_frame or desc.rcm_frame
    axis = rcm_axis or desc.rcm_axis
    if axis not in _AXES:
        raise InvalidInputError(
            f"rcm_axis {axis!r} is not an axis; valid: x, y or z (the shaft axis of the RCM "
            "axis frame)"
        )
    if not point:
        if rcm_axis_frame or rcm_axis:
            given = "rcm_axis_frame" if rcm_axis_frame else "rcm_axis"
            raise InvalidInputError(
                f"{model.name}: {given} is given but no RCM point (no rcm_frame argument, no "
                "<rcm_pin rcm_frame=...> element); valid: also rcm_frame=the frame at the "
                "remote centre, one of " + ", ".join(candidate_tool_frames(model))
            )
        return None
    point_id = frame_index(model, point, "RCM frame")
    axis_frame = rcm_axis_frame or desc.rcm_axis_frame or output.frame
    return RcmSpec(
        point_frame_id=point_id,
        axis_frame_id=frame_index(model, axis_frame, "RCM axis frame"),
        axis=_AXES[axis],
    )


def is_path_like(text: str) -> bool:
    """A path, not a catalogue name: a path separator or a ``.urdf`` / ``.xacro`` suffix."""
    seps = {os.sep, "/"} | ({os.altsep} if os.altsep else set())
    return any(s in text for s in seps) or text.endswith((".urdf", ".xacro"))


__all__ = ["build_mechanism", "candidate_tool_frames", "is_path_like", "parse_models"]
