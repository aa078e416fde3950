"""Helpers shared by the CLI subcommands: parsing vectors, xacro args, JSON output."""

from __future__ import annotations

import argparse
import json
import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from rcm_pin.catalog import load
from rcm_pin.cli._load_options import add_load_options, load_keywords
from rcm_pin.errors import InvalidInputError, NotARotationError, XacroArgumentError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import POSE
from rcm_pin.model.output_choice import require_output
from rcm_pin.rotations import MAX_ABS, ROTATION_TOL, project_to_rotation, rpy_to_matrix


def parse_vector(text: str, name: str, length: int | None = None) -> np.ndarray:
    """Parse ``"a,b,c"`` into a float vector.

    Raises:
        InvalidInputError: a non-number, NaN, or the wrong count (message gives the valid
            form).
    """
    try:
        values = [float(v) for v in text.replace(" ", "").split(",") if v != ""]
    except ValueError:
        raise InvalidInputError(
            f"--{name} {text!r} is not a comma-separated list of numbers; valid: e.g. 0,0.1,0.05"
        ) from None
    if length is not None and len(values) != length:
        raise InvalidInputError(f"--{name} has {len(values)} values; valid: exactly {length}")
    if not all(math.isfinite(v) for v in values):
        raise InvalidInputError(f"--{name} has NaN or infinite values: {text!r}")
    return np.array(values)


def parse_matrix(text: str, name: str) -> np.ndarray:
    """Parse ``"r11,r12,r13,x;r21,...;r31,..."`` (rows separated by ``;``) into a matrix."""
    rows = [parse_vector(row, name) for row in text.split(";") if row.strip()]
    if len({len(r) for r in rows}) != 1:
        raise InvalidInputError(f"--{name} rows have different lengths; valid: 3 rows of 4")
    return np.vstack(rows)


def parse_xacro_args(pairs: Sequence[str] | None) -> dict[str, str]:
    """Parse repeated ``--arg key=value`` options."""
    out: dict[str, str] = {}
    for pair in pairs or []:
        key, sep, value = pair.partition("=")
        if not sep or not key:
            raise XacroArgumentError(f"--arg {pair!r} is not key=value; valid: e.g. --arg l9=0.25")
        out[key.strip()] = value.strip()
    return out


def _angles(text: str) -> np.ndarray:
    """R = Rz(γ)Ry(β)Rx(α) of ``--rpy α,β,γ`` [rad]."""
    angles = parse_vector(text, "rpy", 3)
    if np.max(np.abs(angles)) > MAX_ABS:
        raise InvalidInputError(
            f"--rpy has an angle of magnitude {np.max(np.abs(angles)):.3g} rad; valid: "
            f"|angle| <= {MAX_ABS:g} rad (larger angles are meaningless)"
        )
    return rpy_to_matrix(*angles)


def _rotation(text: str) -> np.ndarray:
    """The 3×3 matrix of ``--rotation r11,...,r33`` (row by row), as given (the solvers
    project it onto SO(3); ``ik`` reports the distance).

    Raises:
        NotARotationError: farther than :data:`rcm_pin.rotations.ROTATION_TOL` from SO(3).
    """
    m = parse_vector(text, "rotation", 9).reshape(3, 3)
    try:
        project_to_rotation(m, ROTATION_TOL)
        return m
    except NotARotationError as exc:
        raise NotARotationError(
            f"--rotation: {exc}; valid: an orthonormal matrix with determinant +1, "
            "r11,r12,r13,r21,...,r33 row by row"
        ) from None


def _orientation(args: argparse.Namespace) -> np.ndarray | None:
    """R from ``--rpy`` or ``--rotation`` (None: neither given)."""
    rpy, rotation = getattr(args, "rpy", None), getattr(args, "rotation", None)
    if rpy and rotation:
        raise InvalidInputError("--rpy conflicts with --rotation; valid: one of them")
    if rpy:
        return _angles(rpy)
    return _rotation(rotation) if rotation else None


def target_from_args(
    mech: Mechanism, args: argparse.Namespace
) -> tuple[np.ndarray, tuple[str, ...]]:
    """(target value, output coordinates solved for) from ``--pose`` / ``--xyz`` / ``--rpy``
    / ``--rotation``.

    ``--pose`` is a 3×4 tool pose ``"r11,r12,r13,x;...;r31,r32,r33,z"`` for a serial
    mechanism, or the output coordinates of a closed one; ``--xyz`` (with ``--rpy`` or
    ``--rotation`` for the orientation) a tool position. A mechanism whose output is a
    rotation alone takes ``--rpy α,β,γ`` (R = Rz(γ)Ry(β)Rx(α)) or ``--rotation r11,...,r33``.

    Raises:
        InvalidInputError: a missing, malformed or conflicting target, or an option that
            does not apply to the mechanism's output.
        UnknownFrameError: a closed mechanism without an output frame (lists candidates).
        NotARotationError: ``--rotation`` too far from SO(3).
    """
    pose, xyz, rpy, rotation = (getattr(args, k, None) for k in ("pose", "xyz", "rpy", "rotation"))
    coords = require_output(mech, "a target").coords
    tool_pose, rotation_output = coords == POSE, coords == ("rotation",)
    if pose and (xyz or rpy):
        raise InvalidInputError("--pose conflicts with --xyz / --rpy; valid: one of them")
    if pose and rotation:
        raise InvalidInputError("--pose conflicts with --rotation; valid: one of them")
    if pose:
        return _pose(mech, pose, tool_pose)
    if rotation_output and not xyz:
        R = _orientation(args)
        if R is None:
            raise InvalidInputError(
                f"ik of {mech.name} needs its output rotation; valid: --rpy alpha,beta,gamma, "
                "--rotation r11,...,r33 or --pose r11,...,r33"
            )
        return R.reshape(9), coords
    if rotation_output:
        raise InvalidInputError(
            f"--xyz does not apply to {mech.name}: its output is the rotation of frame "
            f"{mech.output.frame}; valid: --rpy alpha,beta,gamma, --rotation r11,...,r33 or "
            "--pose r11,...,r33"
        )
    if not xyz or not tool_pose:
        raise InvalidInputError(
            "ik needs --pose, or --xyz (with --rpy or --rotation for the orientation)"
            if tool_pose
            else f"closed mechanisms take --pose {','.join(coords)}; {mech.name} has no tool "
            "pose for --xyz and no rotation output for --rpy / --rotation"
        )
    p = parse_vector(xyz, "xyz", 3)
    R = _orientation(args)
    return (p, ("x", "y", "z")) if R is None else (np.r_[p, R.reshape(9)], POSE)


def _pose(mech: Mechanism, pose: str, tool_pose: bool) -> tuple[np.ndarray, tuple[str, ...]]:
    """The target of ``--pose`` (:func:`target_from_args`)."""
    if ";" not in pose:
        if tool_pose:
            raise InvalidInputError(
                f"--pose for {mech.name} is a 3x4 tool pose 'r11,r12,r13,x;...;r31,r32,r33,z'"
            )
        return parse_vector(pose, "pose", mech.output.size), mech.output.coords
    M = parse_matrix(pose, "pose")
    if not tool_pose or M.shape not in {(3, 4), (4, 4)}:
        raise InvalidInputError(
            f"--pose has shape {M.shape}; valid: 3 rows of 4 numbers for a tool pose"
            if tool_pose
            else f"{mech.name} takes --pose with its output coordinates "
            f"{','.join(mech.output.coords)} (comma-separated)"
        )
    return np.r_[M[:3, 3], M[:3, :3].reshape(9)], POSE


def output_path(path: Path, option: str, directory: bool = False) -> Path:
    """Check an output path before any work: its parent folder must exist (nothing creates
    a missing tree silently); a file path must not be a folder, a folder not a file.
    ``directory``: the path is a folder to write into (created when its parent exists).

    Raises:
        InvalidInputError: the parent is missing or not writable, or the kind is wrong.
    """
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise InvalidInputError(
            f"{option} {str(path)!r}: folder {str(parent)!r} does not exist; valid: a path in "
            "an existing folder"
        )
    if not os.access(parent, os.W_OK):
        raise InvalidInputError(f"{option} {str(path)!r}: folder {str(parent)!r} is not writable")
    if directory and path.exists() and not path.is_dir():
        raise InvalidInputError(f"{option} {str(path)!r} is a file; valid: a folder")
    if not directory and path.is_dir():
        raise InvalidInputError(f"{option} {str(path)!r} is a folder; valid: a file path")
    if directory:
        try:
            path.mkdir(exist_ok=True)
        except OSError as exc:
            raise InvalidInputError(
                f"{option} {str(path)!r}: cannot create the folder ({exc.strerror}); valid: a "
                "folder in a writable location"
            ) from None
    return path


def exclusive(args: argparse.Namespace, *options: str) -> None:
    """At most one of these options may be given.

    Raises:
        InvalidInputError: two or more of them are set (the message names them).
    """
    given = [o for o in options if getattr(args, o.lstrip("-").replace("-", "_"), None)]
    if len(given) > 1:
        raise InvalidInputError(
            f"{' and '.join(given)} conflict; valid: one of {', '.join(options)}"
        )


def load_mechanism(args: argparse.Namespace) -> Mechanism:
    """The mechanism named on the command line, with its ``--arg`` xacro arguments and the
    options of :mod:`rcm_pin.cli._load_options` (frames, folders, ``--trusted``)."""
    keywords: dict[str, Any] = {**load_keywords(args), **parse_xacro_args(args.arg)}
    return load(args.name, **keywords)


def add_common(parser: argparse.ArgumentParser, mechanism: bool = True) -> None:
    """Add ``NAME``, ``--arg``, the frame options of :func:`load_mechanism` and ``--json``
    to a subcommand parser."""
    if mechanism:
        parser.add_argument(
            "name", metavar="NAME", help="mechanism name (rcm-pin list) or a .urdf/.xacro path"
        )
        parser.add_argument(
            "--arg", action="append", metavar="KEY=VALUE", help="xacro argument (repeatable)"
        )
        add_load_options(parser)
    parser.add_argument("--json", action="store_true", help="print one JSON document")


def to_jsonable(value: Any) -> Any:
    """Numpy arrays and scalars to lists and floats, recursively; NaN and ±inf to None
    (strict JSON)."""
    if isinstance(value, np.ndarray):
        return to_jsonable(value.tolist())
    if isinstance(value, (np.floating, np.integer, np.bool_)):
        return to_jsonable(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_jsonable(v) for v in value]
    return value


def emit(args: argparse.Namespace, payload: dict[str, Any], text: str) -> None:
    """Print ``payload`` as JSON with ``--json``, else the human-readable ``text``."""
    if getattr(args, "json", False):
        print(json.dumps(to_jsonable(payload), indent=2, allow_nan=False))
    else:
        print(text)


def fmt(values: np.ndarray, digits: int = 6) -> str:
    """Format a vector compactly."""
    return "[" + ", ".join(f"{v:.{digits}g}" for v in np.asarray(values).ravel()) + "]"
