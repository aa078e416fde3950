"""The mesh folders of a mechanism: its family's Assets, else none.

:func:`assets` returns the family's :class:`~rcm_pin.interfaces.viz.Assets` (listed in
``Family.capabilities``), else :class:`NoAssets` (no ``package://`` folders).
"""

from __future__ import annotations

from rcm_pin.interfaces.viz import Assets
from rcm_pin.model.mechanism import Mechanism


class NoAssets(Assets):
    """The default: no package folders (primitives and absolute mesh paths only)."""

    def mesh_dirs(self, mech: Mechanism) -> tuple[str, ...]:
        return ()


NO_ASSETS = NoAssets()


def assets(mech: Mechanism) -> Assets:
    """The family's :class:`Assets`, else :class:`NoAssets`."""
    return mech.family.capability(Assets) or NO_ASSETS  # type: ignore[type-abstract]


__all__ = ["NoAssets", "assets"]
