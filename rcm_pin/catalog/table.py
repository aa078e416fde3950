"""The mechanisms rcm-pin ships, in one table.

A :class:`CatalogEntry` names a family (:mod:`rcm_pin.mechanisms`), a source (a xacro
file of the package data, or a URDF of an installed robot-description package), the
xacro arguments that define the variant (every argument's valid range is declared in its
xacro and checked by :mod:`rcm_pin.model.xacro_ranges`). Everything else
(tool and RCM frames, the papers' coordinates, loop closures) comes from the rendered
URDF's ``<rcm_pin>`` element, so a catalogue entry and its committed rendering
``urdf/<name>.urdf`` loaded by path give the same mechanism.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

from rcm_pin.errors import UnknownMechanismError
from rcm_pin.mechanisms import (
    arms,
    eye_4dof,
    five_bar,
    four_bar,
    planar_3rrr,
    rcm,
    spherical_3rrr,
    translational_3ppapa,
)
from rcm_pin.model.family import Family
from rcm_pin.model.resources import urdf_dir, xacro_dir


@dataclass(frozen=True)
class CatalogEntry:
    """One shipped mechanism.

    Attributes:
        name: catalogue name (``rcm-pin list``).
        family: the family whose hooks apply.
        xacro: xacro file name in the package's ``xacro/`` (empty for a URDF source).
        description: one line for listings.
        fixed_args: xacro arguments that define this variant.
        urdf: for URDF sources, returns the file's path (e.g. example-robot-data).
        tool_frame: tool frame of a URDF source (xacro sources name it in the URDF).
    """

    name: str
    family: Family
    xacro: str
    description: str
    fixed_args: Mapping[str, str] = field(default_factory=dict)
    urdf: Callable[[], Path] | None = None
    tool_frame: str = ""

    @property
    def xacro_path(self) -> Path:
        """Absolute path of the xacro source."""
        return xacro_dir() / self.xacro

    @property
    def urdf_path(self) -> Path:
        """Committed default rendering (xacro sources) or the source URDF itself."""
        return self.urdf() if self.urdf is not None else urdf_dir() / f"{self.name}.urdf"

    @property
    def kind(self) -> str:
        """``closed`` for families with loop closures, else ``serial``."""
        return "closed" if self.family.closed else "serial"


#: Every shipped mechanism, in listing order.
ENTRIES: tuple[CatalogEntry, ...] = (
    CatalogEntry(
        "rcm_bevel",
        rcm.FAMILY,
        "rcm_bevel.urdf.xacro",
        "RCM mechanism, two bevel-gear trains, 6 DOF (papers 000/003)",
    ),
    CatalogEntry(
        "rcm_bevel_4dof",
        rcm.FAMILY,
        "rcm_bevel.urdf.xacro",
        "RCM mechanism, bevel gears, no wrist pairs 26/27, 4 DOF (paper 000)",
        fixed_args={"wrist": "false", "robot_name": "rcm_bevel_4dof"},
    ),
    CatalogEntry(
        "rcm_belt",
        rcm.FAMILY,
        "rcm_belt.urdf.xacro",
        "RCM mechanism, two belt drives, 6 DOF (the built rig, papers 000/003)",
    ),
    CatalogEntry(
        "rcm_two_mass",
        rcm.FAMILY,
        "rcm_two_mass.urdf.xacro",
        "two-mass dynamic model of paper 000 (Fig. 3), 3 DOF q1..q3",
    ),
    CatalogEntry(
        "planar_3rrr",
        planar_3rrr.FAMILY,
        "planar_3rrr.urdf.xacro",
        "planar 3-RRR parallel mechanism, base pairs driven, 3 DOF (paper 004)",
    ),
    CatalogEntry(
        "five_bar",
        five_bar.FAMILY,
        "five_bar.urdf.xacro",
        "planar five-bar RR-RR, 2 DOF, main + 2 extra drives (paper 004 Fig. 13)",
    ),
    CatalogEntry(
        "four_bar",
        four_bar.FAMILY,
        "four_bar.urdf.xacro",
        "planar four-bar crank-rocker, crank driven, 1 DOF (paper 002 pitch drive)",
    ),
    CatalogEntry(
        "eye_4dof",
        eye_4dof.FAMILY,
        "eye_4dof.urdf.xacro",
        "spatial eye linkage: pitch four-bar, yaw yoke, Assur group, lid, roll, 4 DOF (paper 002)",
    ),
    CatalogEntry(
        "spherical_3rrr",
        spherical_3rrr.FAMILY,
        "spherical_3rrr.urdf.xacro",
        "spherical 3-RRR, base pairs driven, orthogonal Agile Eye by default, 3 DOF (paper 004)",
    ),
    CatalogEntry(
        "translational_3ppapa",
        translational_3ppapa.FAMILY,
        "translational_3ppapa.urdf.xacro",
        "translational 3-PPaPa, parallelograms as crank + mimic, 3 DOF (paper 004 Fig. 4)",
    ),
    CatalogEntry(
        "translational_3ppapa_loops",
        translational_3ppapa.FAMILY,
        "translational_3ppapa.urdf.xacro",
        "translational 3-PPaPa, parallelograms as 4R loops (over-constrained), 3 DOF (paper 004)",
        fixed_args={"model": "loops", "robot_name": "translational_3ppapa_loops"},
    ),
    CatalogEntry(
        "panda",
        arms.FAMILY,
        "",
        "Franka Emika Panda arm, 7 DOF (example-robot-data)",
        urdf=arms.urdf_path("panda"),
        tool_frame="panda_hand_tcp",
    ),
    CatalogEntry(
        "ur5",
        arms.FAMILY,
        "",
        "Universal Robots UR5 arm, 6 DOF (example-robot-data)",
        urdf=arms.urdf_path("ur5"),
        tool_frame="tool0",
    ),
)

_BY_NAME = {e.name: e for e in ENTRIES}

#: Every family of the catalogue, by name (the ``family`` attribute of a URDF's
#: ``<rcm_pin>`` element): derived from :data:`ENTRIES`, so a family is listed once.
FAMILIES: dict[str, Family] = {e.family.name: e.family for e in ENTRIES}


def mechanisms() -> list[CatalogEntry]:
    """Every shipped mechanism, in catalogue order."""
    return list(ENTRIES)


def names() -> tuple[str, ...]:
    """The catalogue names."""
    return tuple(_BY_NAME)


def family_named(name: str) -> Family:
    """The family of that name; the generic family (no hooks) for an empty name.

    Raises:
        UnknownMechanismError: a name that is no family (lists the valid ones).
    """
    if not name:
        return Family()
    try:
        return FAMILIES[name]
    except KeyError:
        raise UnknownMechanismError(
            f"unknown mechanism family {name!r}; valid: {', '.join(FAMILIES)}"
        ) from None


def get_entry(name: str) -> CatalogEntry:
    """The entry of a shipped mechanism.

    Raises:
        UnknownMechanismError: not a catalogue name; the message lists the valid names.
    """
    try:
        return _BY_NAME[name]
    except (KeyError, TypeError):
        raise UnknownMechanismError(
            f"unknown mechanism {name!r}; valid: {', '.join(_BY_NAME)} "
            "(or a path to a .urdf / .xacro file)"
        ) from None


__all__ = [
    "ENTRIES",
    "FAMILIES",
    "CatalogEntry",
    "family_named",
    "get_entry",
    "mechanisms",
    "names",
]
