"""Loop-closure sidecar: the closure list of a cut-open URDF tree, in LAAS's YAML format.

URDF holds trees only, so a closed mechanism is shipped as a tree plus a closure list. The
list is written **once**, in the xacro, as an extension element that URDF parsers ignore
(like ``<gazebo>`` or ``<transmission>``)::

    <rcm_pin_loops plane_normal="0 0 1" output_frame="platform_centre" output_coords="x y rz">
      <closed_loop frame_a="tip_2" frame_b="platform_v2" type="3d"/>
      <actuated joint="A1"/>  <extra_actuated joint="B1"/>
      <leg joints="A2 B2" closure="tip_2"/>
      <param name="distal_2" value="0.25"/>
    </rcm_pin_loops>

Because the element is rendered by xacro from the same arguments as the links, frame names,
drives and the geometry used by the closed forms can never drift apart from the tree. The
YAML sidecar ``urdf/<name>.yaml`` is a projection of that element in the format of LAAS's
*example-parallel-robots* (``closed_loop: [[frameA, frameB], ...]``, ``type: ['3d' | '6d']``,
``name_mot: [joint, ...]``), with ``actuated`` as an alias of ``name_mot`` and the rcm-pin
extras (plane, output, extra drives, legs, parameters) under the ``rcm_pin`` key, which the
LAAS loaders ignore. :func:`spec_from_urdf` and :func:`spec_from_yaml` give the same
:class:`LoopSpec`.

Planar loops: ``type: 3d`` is kept in the file (so LAAS tools read it), and ``plane_normal``
tells rcm-pin to keep only the two in-plane rows of the 3-D point constraint, see
:mod:`rcm_pin.closed_loop.core`.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import yaml

from rcm_pin.errors import InvalidInputError

_TYPES = ("3d", "6d")


@dataclass(frozen=True)
class LegSpec:
    """One leg (serial chain base -> output body) for the screw-theory route.

    Attributes:
        joints: tree joints of the leg, base first.
        closure: frame where the leg meets the output body through a cut pair (a planar
            point closure acts as a revolute pair there); empty if the leg's last joint is
            already the pair with the output body.
    """

    joints: tuple[str, ...]
    closure: str = ""


@dataclass(frozen=True)
class LoopSpec:
    """Closure list, drives and output of a closed mechanism (see module docstring).

    Attributes:
        closed_loop: pairs (frame_a, frame_b) of frames that coincide when the loop is closed.
        types: ``"3d"`` (points coincide) or ``"6d"`` (frames coincide) per pair.
        actuated: driven joints (LAAS ``name_mot``).
        extra_actuated: extra drives that may replace main ones (paper 004 Fig. 13).
        output_frame: frame of the output body.
        output_coords: output coordinates, from ``x``, ``y``, ``z``, ``rz`` (world axes).
        plane_normal: unit normal of the motion plane for planar mechanisms, else None.
        legs: legs for the screw-theory route.
        params: geometry of the closed forms [m, deg].
    """

    closed_loop: tuple[tuple[str, str], ...]
    types: tuple[str, ...]
    actuated: tuple[str, ...]
    extra_actuated: tuple[str, ...] = ()
    output_frame: str = ""
    output_coords: tuple[str, ...] = ()
    plane_normal: tuple[float, float, float] | None = None
    legs: tuple[LegSpec, ...] = ()
    params: Mapping[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if len(self.closed_loop) != len(self.types):
            raise InvalidInputError(
                f"closure list has {len(self.closed_loop)} pairs but {len(self.types)} types; "
                "valid: one type per pair"
            )
        for kind in self.types:
            if kind not in _TYPES:
                raise InvalidInputError(
                    f"closure type {kind!r} is not supported; valid: {', '.join(_TYPES)}"
                )


def spec_from_urdf(urdf: str) -> LoopSpec:
    """Read the ``<rcm_pin_loops>`` element of a rendered URDF.

    Args:
        urdf: URDF XML text.

    Returns:
        The loop specification.

    Raises:
        InvalidInputError: the URDF has no ``<rcm_pin_loops>`` element or a malformed one.
    """
    root = ET.fromstring(urdf)
    element = root.find("rcm_pin_loops")
    if element is None:
        raise InvalidInputError(
            f"URDF {root.attrib.get('name', '?')!r} has no <rcm_pin_loops> element; "
            "valid: a closed-loop model rendered from xacro/planar_3rrr or xacro/five_bar"
        )
    pairs = tuple((c.attrib["frame_a"], c.attrib["frame_b"]) for c in element.iter("closed_loop"))
    types = tuple(c.attrib.get("type", "3d") for c in element.iter("closed_loop"))
    normal_text = element.attrib.get("plane_normal", "").split()
    normal = tuple(float(v) for v in normal_text) if normal_text else None
    return LoopSpec(
        closed_loop=pairs,
        types=types,
        actuated=tuple(a.attrib["joint"] for a in element.iter("actuated")),
        extra_actuated=tuple(a.attrib["joint"] for a in element.iter("extra_actuated")),
        output_frame=element.attrib.get("output_frame", ""),
        output_coords=tuple(element.attrib.get("output_coords", "").split()),
        plane_normal=normal,  # type: ignore[arg-type]
        legs=tuple(
            LegSpec(tuple(leg.attrib["joints"].split()), leg.attrib.get("closure", ""))
            for leg in element.iter("leg")
        ),
        params={p.attrib["name"]: float(p.attrib["value"]) for p in element.iter("param")},
    )


def to_yaml_dict(spec: LoopSpec) -> dict[str, Any]:
    """The sidecar as a plain dict in LAAS's format plus the ``rcm_pin`` extras."""
    extras: dict[str, Any] = {
        "output_frame": spec.output_frame,
        "output_coords": list(spec.output_coords),
        "plane_normal": list(spec.plane_normal) if spec.plane_normal else None,
        "extra_actuated": list(spec.extra_actuated),
        "legs": [{"joints": list(leg.joints), "closure": leg.closure} for leg in spec.legs],
        "params": {k: float(v) for k, v in spec.params.items()},
    }
    return {
        "closed_loop": [list(pair) for pair in spec.closed_loop],
        "type": list(spec.types),
        "name_mot": list(spec.actuated),
        "actuated": list(spec.actuated),
        "rcm_pin": extras,
    }


def to_yaml(spec: LoopSpec) -> str:
    """YAML text of the sidecar (flow-style lists, as in example-parallel-robots)."""
    header = (
        "# Loop closures of the cut-open URDF tree (LAAS example-parallel-robots format).\n"
        "# Generated from the <rcm_pin_loops> element of the xacro; do not edit by hand.\n"
    )
    body = yaml.safe_dump(to_yaml_dict(spec), sort_keys=False, default_flow_style=None)
    return header + body


def spec_from_yaml(text: str) -> LoopSpec:
    """Parse a sidecar (LAAS keys ``closed_loop``, ``type``, ``name_mot`` or ``actuated``).

    Raises:
        InvalidInputError: missing ``closed_loop`` or drive list.
    """
    raw = yaml.safe_load(text) or {}
    if "closed_loop" not in raw:
        raise InvalidInputError("loop sidecar has no 'closed_loop' key; valid: LAAS format")
    actuated = raw.get("actuated", raw.get("name_mot"))
    if actuated is None:
        raise InvalidInputError("loop sidecar has neither 'actuated' nor 'name_mot'")
    pairs = tuple((str(a), str(b)) for a, b in raw["closed_loop"])
    extras = raw.get("rcm_pin") or {}
    normal = extras.get("plane_normal")
    return LoopSpec(
        closed_loop=pairs,
        types=tuple(str(t) for t in raw.get("type", ["6d"] * len(pairs))),
        actuated=tuple(actuated),
        extra_actuated=tuple(extras.get("extra_actuated", ())),
        output_frame=extras.get("output_frame", ""),
        output_coords=tuple(extras.get("output_coords", ())),
        plane_normal=tuple(float(v) for v in normal) if normal else None,  # type: ignore[arg-type]
        legs=tuple(
            LegSpec(tuple(leg["joints"]), leg.get("closure", "")) for leg in extras.get("legs", ())
        ),
        params={k: float(v) for k, v in (extras.get("params") or {}).items()},
    )
