"""The options of one load that are not about the mechanism itself: where ROS packages
and mesh files may come from (:mod:`rcm_pin.model.packages`, :mod:`rcm_pin.model.meshes`)
and whether the user vouches for a xacro file (:mod:`rcm_pin.model.xacro_safety`)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from rcm_pin.model.meshes import resolve_meshes
from rcm_pin.model.packages import PackageSearch, package_search


class LoadOptions:
    """The package and mesh folders and the trust of one :func:`~rcm_pin.catalog.loading.load`
    (passed on to ``rebuild``, so a design variant loads the same way)."""

    def __init__(
        self,
        package_dirs: dict[str, str | Path],
        mesh_dirs: tuple[str | Path, ...],
        trusted: bool = False,
    ):
        self.package_dirs, self.mesh_dirs, self.trusted = package_dirs, mesh_dirs, trusted

    def search(self, near: Path) -> PackageSearch:
        """Where packages are found for a file at ``near``."""
        return package_search(self.package_dirs, near)

    def meshes(self, urdf: str, source: Path | None, search: PackageSearch) -> str:
        """The URDF with its mesh paths resolved inside the allowed folders."""
        return resolve_meshes(urdf, source=source, search=search, mesh_dirs=self.mesh_dirs)

    def keywords(self) -> dict[str, Any]:
        """The options as keywords of ``load``."""
        return {
            "package_dirs": self.package_dirs,
            "mesh_dirs": self.mesh_dirs,
            "trusted": self.trusted,
        }


__all__ = ["LoadOptions"]
