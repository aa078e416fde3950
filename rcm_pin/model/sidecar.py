"""What a URDF cannot say: tool and RCM frames, the papers' coordinates, loop closures.

URDF describes trees. rcm-pin writes the rest **once**, in the xacro, as an extension
element that URDF parsers ignore (like ``<gazebo>`` or ``<transmission>``)::

    <rcm_pin family="rcm" tool_frame="tool" rcm_frame="rcm" rcm_axis_frame="output_link"
             rcm_axis="z" coordinates="pair4 pair7 pair24 pair23 pair26 pair27"/>

    <rcm_pin family="planar_3rrr" output_frame="platform_centre" output_coords="x y rz">
      <closed_loop frame_a="tip_2" frame_b="platform_v2" type="3d" rows="x y"/>
      <actuated joint="A1"/>  <extra_actuated joint="B1"/>
      <leg joints="A2 B2" closure="tip_2"/>
      <param name="distal_2" value="0.25"/>
    </rcm_pin>

Rendered from the same arguments as the links, frame names, drives and closed-form
geometry never drift apart from the tree. The YAML sidecar ``urdf/<name>.yaml`` of a closed
mechanism is a projection of the element in the format of LAAS's *example-parallel-robots*
(``closed_loop: [[frameA, frameB], ...]``, ``type: ['3d' | '6d']``, ``name_mot``), with
``actuated`` as an alias of ``name_mot`` and the rcm-pin extras under the ``rcm_pin`` key,
which the LAAS loaders ignore.

Closure rows: ``type="3d"`` makes the points of frames a and b coincide (rows ``x y z`` of
R_aᵀ(p_a − p_b)), ``type="6d"`` the frames (rows ``x y z rx ry rz`` of log₆(ᵃM_b)). ``rows``
keeps a subset, e.g. the two in-plane rows of a planar loop whose out-of-plane row is
identically zero; without ``rows`` every row is kept and redundant ones are resolved by
rank (see :mod:`rcm_pin.model.newton`).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from rcm_pin.errors import InvalidInputError

ELEMENT = "rcm_pin"
KINDS = {"3d": ("x", "y", "z"), "6d": ("x", "y", "z", "rx", "ry", "rz")}


@dataclass(frozen=True)
class ClosureSpec:
    """Frames a and b that coincide (``3d``: points, ``6d``: frames) and the rows kept."""

    frame_a: str
    frame_b: str
    kind: str = "3d"
    rows: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise InvalidInputError(
                f"closure type {self.kind!r} is not supported; valid: {', '.join(KINDS)}"
            )
        bad = [r for r in self.rows if r not in KINDS[self.kind]]
        if bad or len(set(self.rows)) != len(self.rows):
            raise InvalidInputError(
                f"closure {self.frame_a}-{self.frame_b} rows {list(self.rows)}; valid: distinct "
                f"rows from {', '.join(KINDS[self.kind])}"
            )

    @property
    def row_indices(self) -> tuple[int, ...]:
        """Kept rows as indices into the closure's residual (all when ``rows`` is empty)."""
        names = KINDS[self.kind]
        return tuple(names.index(r) for r in self.rows) if self.rows else tuple(range(len(names)))


@dataclass(frozen=True)
class LegSpec:
    """One leg, base to output body, for the screw-theory route.

    Attributes:
        joints: tree joints of the leg, base first.
        closure: frame a of the closure where the leg meets the output body (empty when the
            leg's last joint already carries the output body).
    """

    joints: tuple[str, ...]
    closure: str = ""


@dataclass(frozen=True)
class LoopSpec:
    """Closures, drives and output of a closed mechanism (module docstring)."""

    closures: tuple[ClosureSpec, ...]
    actuated: tuple[str, ...]
    output_frame: str
    output_coords: tuple[str, ...]
    extra_actuated: tuple[str, ...] = ()
    legs: tuple[LegSpec, ...] = ()
    params: Mapping[str, float] = field(default_factory=dict)
    length_scale: float | None = None


@dataclass(frozen=True)
class Description:
    """The ``<rcm_pin>`` element: family, frames, coordinates and loops (all optional)."""

    family: str = ""
    tool_frame: str = ""
    rcm_frame: str = ""
    rcm_axis_frame: str = ""
    rcm_axis: str = "z"
    coordinates: tuple[str, ...] = ()
    loops: LoopSpec | None = None
    #: LAAS ``joint_name`` / ``joint_type`` pairs (:mod:`rcm_pin.model.laas_joints`).
    joint_types: tuple[tuple[str, str], ...] = ()


def _words(element: ET.Element, key: str) -> tuple[str, ...]:
    return tuple(element.attrib.get(key, "").split())


def read_description(urdf: str) -> Description:
    """The ``<rcm_pin>`` element of a URDF (an empty :class:`Description` without one).

    Raises:
        InvalidInputError: malformed XML or a malformed element.
    """
    try:
        root = ET.fromstring(urdf)
    except ET.ParseError as exc:
        raise InvalidInputError(f"the URDF is not well-formed XML: {exc}") from None
    element = root.find(ELEMENT)
    if element is None:
        return Description()
    a = element.attrib
    loops = None
    closures = tuple(
        ClosureSpec(
            c.attrib["frame_a"], c.attrib["frame_b"], c.attrib.get("type", "3d"), _words(c, "rows")
        )
        for c in element.iter("closed_loop")
    )
    if closures:
        loops = LoopSpec(
            closures=closures,
            actuated=tuple(j.attrib["joint"] for j in element.iter("actuated")),
            output_frame=a.get("output_frame", ""),
            output_coords=_words(element, "output_coords"),
            extra_actuated=tuple(j.attrib["joint"] for j in element.iter("extra_actuated")),
            legs=tuple(
                LegSpec(_words(leg, "joints"), leg.attrib.get("closure", ""))
                for leg in element.iter("leg")
            ),
            params={p.attrib["name"]: float(p.attrib["value"]) for p in element.iter("param")},
            length_scale=float(a["length_scale"]) if "length_scale" in a else None,
        )
    return Description(
        family=a.get("family", ""),
        tool_frame=a.get("tool_frame", a.get("output_frame", "")),
        rcm_frame=a.get("rcm_frame", ""),
        rcm_axis_frame=a.get("rcm_axis_frame", ""),
        rcm_axis=a.get("rcm_axis", "z"),
        coordinates=_words(element, "coordinates"),
        loops=loops,
    )


def to_yaml_dict(desc: Description) -> dict[str, Any]:
    """The sidecar as a plain dict: LAAS keys plus the ``rcm_pin`` extras."""
    spec = desc.loops
    if spec is None:
        raise InvalidInputError("a loop sidecar needs closures; this description has none")
    extras: dict[str, Any] = {
        "family": desc.family,
        "output_frame": spec.output_frame,
        "output_coords": list(spec.output_coords),
        "rows": [list(c.rows) for c in spec.closures],
        "extra_actuated": list(spec.extra_actuated),
        "legs": [{"joints": list(leg.joints), "closure": leg.closure} for leg in spec.legs],
        "params": dict(spec.params),
    }
    if spec.length_scale is not None:
        extras["length_scale"] = spec.length_scale
    return {
        "closed_loop": [[c.frame_a, c.frame_b] for c in spec.closures],
        "type": [c.kind for c in spec.closures],
        "name_mot": list(spec.actuated),
        "actuated": list(spec.actuated),
        "rcm_pin": extras,
    }


def to_yaml(desc: Description) -> str:
    """YAML text of the sidecar (flow-style lists, as in example-parallel-robots)."""
    header = (
        "# Loop closures of the cut-open URDF tree (LAAS example-parallel-robots format).\n"
        "# Generated from the <rcm_pin> element of the xacro; do not edit by hand.\n"
    )
    import yaml  # lazy: ~20 ms to import, only for sidecars

    body = yaml.safe_dump(to_yaml_dict(desc), sort_keys=False, default_flow_style=None)
    return header + body


def description_from_yaml(text: str) -> Description:
    """Parse a sidecar (LAAS keys ``closed_loop``, ``type``, ``name_mot`` or ``actuated``).

    As LAAS's *example-parallel-robots* writes it: ``type`` in either case (``6d``, ``3D``;
    ``6d`` for every closure when absent), no output frame (the output is then optional,
    :mod:`rcm_pin.model.output_choice`); the rcm-pin extras under ``rcm_pin``.

    ``joint_name`` / ``joint_type`` (the LAAS loader's joint replacements) are kept in
    :attr:`Description.joint_types`, applied by :mod:`rcm_pin.model.laas_joints`.

    Raises:
        InvalidInputError: not YAML, or no ``closed_loop`` or drive list, or joint names
            and types of different lengths.
    """
    import yaml  # lazy: ~20 ms to import, only for sidecars

    try:
        raw = yaml.safe_load(text) or {}
    except yaml.YAMLError as exc:
        raise InvalidInputError(f"the loop sidecar is not valid YAML: {exc}") from None
    if not isinstance(raw, dict) or "closed_loop" not in raw:
        raise InvalidInputError("loop sidecar has no 'closed_loop' key; valid: LAAS format")
    actuated = raw.get("actuated", raw.get("name_mot"))
    if actuated is None:
        raise InvalidInputError("loop sidecar has neither 'actuated' nor 'name_mot'")
    pairs = [(str(a), str(b)) for a, b in raw["closed_loop"]]
    extras = raw.get("rcm_pin") or {}
    kinds = [str(t).lower() for t in raw.get("type", ["6d"] * len(pairs))]  # LAAS: '3D' too
    names, types = raw.get("joint_name") or [], raw.get("joint_type") or []
    if len(names) != len(types):
        raise InvalidInputError(
            f"loop sidecar has {len(names)} joint_name and {len(types)} joint_type entries; "
            "valid: one type per joint name"
        )
    rows = extras.get("rows") or [[] for _ in pairs]
    if not len(kinds) == len(rows) == len(pairs):
        raise InvalidInputError(
            f"loop sidecar has {len(pairs)} closures, {len(kinds)} types and {len(rows)} row "
            "lists; valid: one of each per closure"
        )
    spec = LoopSpec(
        closures=tuple(
            ClosureSpec(a, b, k, tuple(str(r) for r in rw))
            for (a, b), k, rw in zip(pairs, kinds, rows, strict=True)
        ),
        actuated=tuple(str(j) for j in actuated),
        output_frame=str(extras.get("output_frame", "")),
        output_coords=tuple(str(c) for c in extras.get("output_coords", ())),
        extra_actuated=tuple(str(j) for j in extras.get("extra_actuated", ())),
        legs=tuple(
            LegSpec(tuple(leg["joints"]), leg.get("closure", "")) for leg in extras.get("legs", ())
        ),
        params={k: float(v) for k, v in (extras.get("params") or {}).items()},
        length_scale=float(extras["length_scale"]) if "length_scale" in extras else None,
    )
    return Description(
        family=str(extras.get("family", "")),
        tool_frame=spec.output_frame,
        loops=spec,
        joint_types=tuple((str(n), str(t)) for n, t in zip(names, types, strict=True)),
    )


__all__ = [
    "ELEMENT",
    "KINDS",
    "ClosureSpec",
    "Description",
    "LegSpec",
    "LoopSpec",
    "description_from_yaml",
    "read_description",
    "to_yaml",
    "to_yaml_dict",
]
