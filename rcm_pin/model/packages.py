"""ROS package resolution without ROS: ``$(find pkg)`` in xacro, ``package://pkg/...`` in URDF.

A package name resolves to a folder, the first found in this order:

1. the declared map: ``load(..., package_dirs={"pkg": path})``, CLI ``--package-dir pkg=PATH``;
2. ``ROS_PACKAGE_PATH`` (ROS 1): each root crawled for folders with a ``package.xml``
   whose ``<name>`` is the package (a package's own subfolders are not crawled, nor
   hidden folders or folders marked ``CATKIN_IGNORE`` / ``COLCON_IGNORE`` /
   ``AMENT_IGNORE``);
3. ``AMENT_PREFIX_PATH`` (ROS 2): ``PREFIX/share/pkg`` of a prefix whose ament index
   lists the package or whose ``share/pkg`` holds a ``package.xml``;
4. the folders above the file being loaded: each folder from the file's own up to the
   parent of the outermost one holding a ``package.xml`` (the workspace's ``src``), the
   folder itself and its direct subfolders, matched by ``<name>`` as ROS does;
5. the installed ``cmeel`` prefix of the Python environment, an ament prefix too (so the
   ``package://example-robot-data/...`` meshes of an installed example-robot-data resolve
   by themselves).

A package found nowhere raises :class:`~rcm_pin.errors.PackageNotFoundError` naming it and
``--package-dir`` / ``package_dirs=``. :func:`find_hook` installs the search as xacro's
``$(find)`` (xacro 2 otherwise imports ``ament_index_python``, which needs ROS 2).
"""

from __future__ import annotations

import contextlib
import os
import re
import sys
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path

from rcm_pin.errors import InvalidInputError, PackageNotFoundError

_NAME = re.compile(rb"<name>\s*([^<\s]+)\s*</name>")
_IGNORE = ("CATKIN_IGNORE", "COLCON_IGNORE", "AMENT_IGNORE")
_INDEX = Path("share", "ament_index", "resource_index", "packages")


def package_name(folder: Path) -> str | None:
    """The ``<name>`` of ``folder/package.xml`` (None: no readable package.xml there)."""
    try:
        match = _NAME.search((folder / "package.xml").read_bytes()[:65536])
    except OSError:
        return None
    return match.group(1).decode("utf-8", "replace") if match else None


def crawl(root: Path) -> Iterator[tuple[str, Path]]:
    """(name, folder) of every package under ``root``, as rospack crawls ROS_PACKAGE_PATH
    (symbolic links followed, each real folder once)."""
    seen: set[str] = set()
    for here, dirs, files in os.walk(root, followlinks=True):
        real = os.path.realpath(here)
        if real in seen or any(marker in files for marker in _IGNORE):
            dirs[:] = []
            continue
        if "package.xml" in files:
            dirs[:] = []
            name = package_name(Path(here))
            if name:
                yield name, Path(here)
            continue
        seen.add(real)
        dirs[:] = sorted(d for d in dirs if not d.startswith("."))


def _env_paths(variable: str) -> list[Path]:
    return [Path(p) for p in os.environ.get(variable, "").split(os.pathsep) if p]


def _ament(name: str, prefix: Path) -> Path | None:
    share = prefix / "share" / name
    if share.is_dir() and ((prefix / _INDEX / name).exists() or (share / "package.xml").exists()):
        return share
    return None


def _above(name: str, near: Path) -> Path | None:
    start = near.resolve()
    folders = [start, *start.parents] if start.is_dir() else list(start.parents)
    in_package = [i for i, f in enumerate(folders) if (f / "package.xml").is_file()]
    if not in_package:
        return None
    for folder in folders[: in_package[-1] + 2]:
        if package_name(folder) == name:
            return folder
        with contextlib.suppress(OSError):
            for child in sorted(folder.iterdir()):
                if child.is_dir() and package_name(child) == name:
                    return child
    return None


def installed_prefix() -> Path | None:
    """The ``cmeel.prefix`` of the running Python environment (None: not installed)."""
    for entry in sys.path:
        prefix = Path(entry or ".") / "cmeel.prefix"
        if (prefix / "share").is_dir():
            return prefix
    return None


@dataclass(frozen=True)
class PackageSearch:
    """Where packages are looked for (module docstring for the order).

    Attributes:
        declared: the declared ``(name, folder)`` pairs, in the order given.
        near: the file (or folder) whose folders above are searched (None: none).
    """

    declared: tuple[tuple[str, Path], ...] = ()
    near: Path | None = None

    def find(self, name: str) -> Path:
        """The folder of package ``name``.

        Raises:
            PackageNotFoundError: found in no searched place (the message names the
                package, the places and ``--package-dir name=PATH``).
        """
        for declared, folder in self.declared:
            if declared == name:
                return folder
        for root in _env_paths("ROS_PACKAGE_PATH"):
            for found, folder in crawl(root):
                if found == name:
                    return folder
        prefixes = _env_paths("AMENT_PREFIX_PATH")
        for prefix in prefixes:
            if (share := _ament(name, prefix)) is not None:
                return share
        if self.near is not None and (above := _above(name, self.near)) is not None:
            return above
        installed = installed_prefix()
        if installed is not None and (share := _ament(name, installed)) is not None:
            return share
        where = f", the folders above {self.near}" if self.near is not None else ""
        raise PackageNotFoundError(
            f"ROS package {name!r} not found (searched: package_dirs, ROS_PACKAGE_PATH, "
            f"AMENT_PREFIX_PATH{where}); valid: --package-dir {name}=PATH or "
            f"package_dirs={{{name!r}: PATH}}, PATH the folder holding its package.xml"
        )

    def key(self) -> str:
        """What the search depends on beyond the files, for cache keys."""
        declared = ";".join(f"{n}={f}" for n, f in self.declared)
        env = [os.environ.get(v, "") for v in ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH")]
        return f"declared={declared}\0ros={env[0]}\0ament={env[1]}"


def package_search(
    package_dirs: Mapping[str, str | Path] | None = None, near: str | Path | None = None
) -> PackageSearch:
    """A :class:`PackageSearch` with the declared folders checked.

    Args:
        package_dirs: package name -> its folder (the one holding its package.xml).
        near: the file loaded, whose folders above are searched last.

    Raises:
        InvalidInputError: an empty name, or a folder that does not exist.
    """
    declared = []
    for name, folder in (package_dirs or {}).items():
        try:
            path = Path(folder).expanduser()
        except RuntimeError:  # "~user" of no known user
            path = Path("/nonexistent") / str(folder)
        if not name or "/" in name or not path.is_dir():
            raise InvalidInputError(
                f"package directory {name}={folder}: "
                + ("not a package name" if not name or "/" in name else "not a folder")
                + "; valid: --package-dir NAME=PATH (package_dirs={NAME: PATH}), PATH an "
                "existing folder"
            )
        declared.append((name, path.resolve()))
    return PackageSearch(tuple(declared), None if near is None else Path(near))


@dataclass(frozen=True)
class XacroReads:
    """What xacro's substitutions looked up during one render.

    Attributes:
        found: package -> folder of every ``$(find pkg)`` answered.
        env: variable -> value (None: unset) of every ``$(env)`` / ``$(optenv)`` read.
    """

    found: dict[str, Path]
    env: dict[str, str | None]


@contextlib.contextmanager
def find_hook(search: PackageSearch) -> Iterator[XacroReads]:
    """xacro's ``$(find pkg)`` answered by ``search`` while the block runs, and every
    lookup of packages and environment variables recorded (:class:`XacroReads`, filled as
    xacro asks). Not thread-safe: xacro keeps its state in module globals (callers hold a
    lock).
    """
    from xacro import substitution_args as sa  # type: ignore[attr-defined]

    reads = XacroReads({}, {})
    env, optenv = sa._eval_env, sa._eval_optenv

    def find(name: str) -> str:
        reads.found[name] = search.find(name)
        return str(reads.found[name])

    def read_env(name: str) -> str:
        reads.env[name] = os.environ.get(name)
        return str(env(name))

    def read_optenv(name: str, default: str = "") -> str:
        reads.env[name] = os.environ.get(name)
        return str(optenv(name, default))

    names = ("find", "env", "optenv")
    saved = [getattr(sa, f"_eval_{n}") for n in names], [sa._eval_dict[n] for n in names]
    for name, hook in zip(names, (find, read_env, read_optenv), strict=True):
        setattr(sa, f"_eval_{name}", hook)
        sa._eval_dict[name] = hook
    try:
        yield reads
    finally:
        for name, module_level, in_eval in zip(names, *saved, strict=True):
            setattr(sa, f"_eval_{name}", module_level)
            sa._eval_dict[name] = in_eval


__all__ = ["PackageSearch", "crawl", "find_hook", "installed_prefix", "package_name"]
__all__ += ["XacroReads", "package_search"]
