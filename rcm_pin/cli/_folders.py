"""``--package-dir PKG=PATH`` and ``--mesh-dir PATH``: where a file's packages and meshes are.

Both are repeatable and go to :func:`rcm_pin.load` as ``package_dirs`` and ``mesh_dirs``
(:mod:`rcm_pin.model.packages`, :mod:`rcm_pin.model.meshes`).
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from typing import Any

from rcm_pin.errors import InvalidInputError


def parse_package_dirs(pairs: Sequence[str] | None) -> dict[str, str]:
    """Parse repeated ``--package-dir pkg=PATH`` options.

    Raises:
        InvalidInputError: a pair that is not NAME=PATH.
    """
    out: dict[str, str] = {}
    for pair in pairs or []:
        name, sep, path = pair.partition("=")
        if not sep or not name.strip() or not path.strip():
            raise InvalidInputError(
                f"--package-dir {pair!r} is not NAME=PATH; valid: e.g. --package-dir "
                "my_robot_description=~/ws/src/my_robot_description"
            )
        out[name.strip()] = path.strip()
    return out


def folders_from_args(args: argparse.Namespace) -> dict[str, Any]:
    """``package_dirs`` and ``mesh_dirs`` keywords of :func:`rcm_pin.load` from the options.

    Raises:
        InvalidInputError: a malformed ``--package-dir``.
    """
    return {
        "package_dirs": parse_package_dirs(getattr(args, "package_dir", None)),
        "mesh_dirs": tuple(getattr(args, "mesh_dir", None) or ()),
    }


def add_folder_options(parser: argparse.ArgumentParser) -> None:
    """Add ``--package-dir`` and ``--mesh-dir`` to a subcommand parser."""
    parser.add_argument(
        "--package-dir",
        action="append",
        metavar="PKG=PATH",
        help="folder of ROS package PKG, for $(find PKG) and package://PKG/... (repeatable); "
        "searched before ROS_PACKAGE_PATH, AMENT_PREFIX_PATH and the folders above the file",
    )
    parser.add_argument(
        "--mesh-dir",
        action="append",
        metavar="PATH",
        help="allow mesh files from this folder too (repeatable); by default only the "
        "file's own tree and its packages",
    )


__all__ = ["add_folder_options", "folders_from_args", "parse_package_dirs"]
