"""The options of every subcommand that loads a mechanism, beside ``NAME`` and ``--arg``:
the frames a file may not name (``--tool-frame``, ``--rcm-frame``, ``--rcm-axis-frame``,
``--rcm-axis``, ``--output-frame``, ``--output-coords``), where its packages and meshes are
(:mod:`rcm_pin.cli._folders`) and ``--trusted``; each is a keyword of :func:`rcm_pin.load`.
"""

from __future__ import annotations

import argparse
from typing import Any

from rcm_pin.cli._folders import add_folder_options, folders_from_args

#: The frame options, as keywords of :func:`rcm_pin.load`.
FRAME_KEYS = (
    "tool_frame",
    "rcm_frame",
    "rcm_axis_frame",
    "rcm_axis",
    "output_frame",
    "output_coords",
)


def add_load_options(parser: argparse.ArgumentParser) -> None:
    """Add the frame, folder and trust options to a subcommand parser."""
    parser.add_argument(
        "--tool-frame", metavar="FRAME", help="a path's tool frame (if the file names none)"
    )
    parser.add_argument(
        "--rcm-frame", metavar="FRAME", help="a path's remote-centre frame (optional)"
    )
    parser.add_argument(
        "--rcm-axis-frame",
        metavar="FRAME",
        help="frame whose --rcm-axis is the shaft line through the RCM (default: the "
        "file's, else the tool frame)",
    )
    parser.add_argument(
        "--rcm-axis", metavar="AXIS", help="x, y or z: the shaft axis of --rcm-axis-frame (z)"
    )
    add_folder_options(parser)
    parser.add_argument(
        "--trusted",
        action="store_true",
        help="a .xacro path you vouch for: evaluate its expressions unchecked (default: "
        "only the allow-list of SECURITY.md; a xacro file is code)",
    )
    parser.add_argument(
        "--output-frame", metavar="FRAME", help="closed: output frame (as --tool-frame)"
    )
    parser.add_argument(
        "--output-coords", metavar="'X Y ...'", help="closed: output coordinates, e.g. 'x y'"
    )


def path_frames(args: argparse.Namespace) -> dict[str, str]:
    """The frame options given, as keywords of :func:`rcm_pin.load`."""
    return {k: getattr(args, k) for k in FRAME_KEYS if getattr(args, k, None)}


def load_keywords(args: argparse.Namespace) -> dict[str, Any]:
    """Every option of this module given, as keywords of :func:`rcm_pin.load`."""
    trusted = bool(getattr(args, "trusted", False))
    return {**path_frames(args), **folders_from_args(args), "trusted": trusted}


__all__ = ["FRAME_KEYS", "add_load_options", "load_keywords", "path_frames"]
