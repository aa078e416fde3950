"""What the viewer asks of a family: where the URDF's meshes are.

:func:`rcm_pin.viz.assets.assets` resolves a family's :class:`Assets`, else the default
with no folders (the catalogue's URDFs draw primitives or meshes by absolute path).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from rcm_pin.model.mechanism import Mechanism


class Assets(ABC):
    """The files a mechanism's visual geometry needs beyond its URDF."""

    @abstractmethod
    def mesh_dirs(self, mech: Mechanism) -> tuple[str, ...]:
        """Folders that resolve the URDF's ``package://`` mesh paths."""


__all__ = ["Assets"]
