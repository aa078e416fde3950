"""The catalogue layer: the table of shipped mechanisms (:mod:`.table`), :func:`load`
(:mod:`.loading`) and the committed renderings in ``urdf/`` (:mod:`.files`)."""

from rcm_pin.catalog.loading import from_urdf, load
from rcm_pin.catalog.table import ENTRIES, CatalogEntry, get_entry, mechanisms, names

__all__ = ["ENTRIES", "CatalogEntry", "from_urdf", "get_entry", "load", "mechanisms", "names"]
