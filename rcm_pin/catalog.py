"""The mechanisms rcm-pin ships: names, xacro sources, default arguments.

A :class:`MechanismSpec` names a xacro file and the arguments that distinguish one
shipped variant from another (``rcm_bevel_4dof`` is ``rcm_bevel`` with ``wrist:=false``).
``urdf/<name>.urdf`` is the rendered default, committed and checked for staleness.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from rcm_pin.errors import UnknownMechanismError
from rcm_pin.render import URDF_DIR, XACRO_DIR


@dataclass(frozen=True)
class MechanismSpec:
    """One shipped mechanism.

    Attributes:
        name: catalogue name (``rcm-pin list``).
        xacro: xacro file name in ``xacro/``.
        description: one line for listings.
        kind: ``"serial"`` (a tree, possibly with mimic joints) or ``"closed"`` (loop
            closures in a YAML sidecar).
        fixed_args: xacro arguments that define this variant.
        coordinates: URDF joint names of the independent coordinates in the papers'
            order (``q1..qn``); empty means "Pinocchio's order, named by joint".
        tool_frame: frame name of the tool centre.
        rcm_frame: frame name of the remote centre (empty when there is none).
        positive_args: argument names that must be > 0 (lengths, masses, ratios).
    """

    name: str
    xacro: str
    description: str
    kind: str = "serial"
    fixed_args: dict[str, str] = field(default_factory=dict)
    coordinates: tuple[str, ...] = ()
    tool_frame: str = "tool"
    rcm_frame: str = ""
    positive_args: tuple[str, ...] = ()

    @property
    def xacro_path(self) -> Path:
        """Absolute path of the xacro source."""
        return XACRO_DIR / self.xacro

    @property
    def urdf_path(self) -> Path:
        """Absolute path of the committed default rendering."""
        return URDF_DIR / f"{self.name}.urdf"


_RCM_COORDS = ("pair4", "pair7", "pair24", "pair23", "pair26", "pair27")
_RCM_POSITIVE = (
    "l9",
    "a7_x",
    "z13",
    "z14",
    "z16",
    "z17",
    "z18",
    "z19",
    "z21",
    "z22",
    "d1",
    "d2",
    "d3",
    "d4",
)

_SPECS: tuple[MechanismSpec, ...] = (
    MechanismSpec(
        name="rcm_bevel",
        xacro="rcm_bevel.urdf.xacro",
        description="RCM mechanism, two bevel-gear trains, 6 DOF (papers 000/003)",
        coordinates=_RCM_COORDS,
        rcm_frame="rcm",
        positive_args=_RCM_POSITIVE,
    ),
    MechanismSpec(
        name="rcm_bevel_4dof",
        xacro="rcm_bevel.urdf.xacro",
        description="RCM mechanism, bevel gears, no wrist pairs 26/27, 4 DOF (paper 000)",
        fixed_args={"wrist": "false"},
        coordinates=_RCM_COORDS[:4],
        rcm_frame="rcm",
        positive_args=_RCM_POSITIVE,
    ),
    MechanismSpec(
        name="rcm_belt",
        xacro="rcm_belt.urdf.xacro",
        description="RCM mechanism, two belt drives, 6 DOF (the built rig, papers 000/003)",
        coordinates=_RCM_COORDS,
        rcm_frame="rcm",
        positive_args=_RCM_POSITIVE,
    ),
)

_REGISTRY: dict[str, MechanismSpec] = {spec.name: spec for spec in _SPECS}


def register(spec: MechanismSpec) -> None:
    """Add a mechanism to the catalogue (used by the closed-loop package)."""
    _REGISTRY[spec.name] = spec


def mechanisms() -> list[MechanismSpec]:
    """Every shipped mechanism, in catalogue order."""
    _ensure_plugins()
    return list(_REGISTRY.values())


def get_spec(name: str) -> MechanismSpec:
    """The spec of a shipped mechanism.

    Raises:
        UnknownMechanismError: the name is not shipped; the message lists valid names.
    """
    _ensure_plugins()
    try:
        return _REGISTRY[name]
    except KeyError:
        raise UnknownMechanismError(
            f"unknown mechanism {name!r}; valid: {', '.join(_REGISTRY)}"
        ) from None


def _ensure_plugins() -> None:
    """Import the modules that register more mechanisms (closed loops, two-mass model)."""
    import importlib

    for module in _PLUGINS:
        try:
            importlib.import_module(module)
        except ModuleNotFoundError as exc:
            if exc.name is None or not module.startswith(exc.name):
                raise


#: Modules whose import registers further mechanisms.
_PLUGINS: tuple[str, ...] = ("rcm_pin.closed_loop.catalog", "rcm_pin.two_mass")
