"""Mechanism families: the only place that knows a mechanism by its kind.

Each family module (a subpackage where it needs more than ~300 lines) holds the closed
forms of its papers with their misprints written down, its named configurations, and the
hooks of :class:`rcm_pin.model.family.Family` that generic code asks for. Each module
exposes ``FAMILY``; the catalogue (:mod:`rcm_pin.catalog.table`) imports the modules
explicitly, and its entries are the one list of families.

The public names are the families themselves (``docs/api.md``): ``from rcm_pin.mechanisms
import rcm`` then ``rcm.closed_form.tool_pose(q)``; a family package's modules are its
attributes, each imported on first access.
"""

from __future__ import annotations

from rcm_pin.lazy import lazy_modules

__all__ = [
    "arms",
    "eye_4dof",
    "five_bar",
    "four_bar",
    "planar_3rrr",
    "rcm",
    "spherical_3rrr",
    "translational_3ppapa",
]

__getattr__, __dir__ = lazy_modules(__name__, __all__)
