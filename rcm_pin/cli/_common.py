"""Helpers shared by the CLI subcommands: parsing vectors, xacro args, JSON output."""

from __future__ import annotations

import argparse
import json
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from rcm_pin.errors import InvalidInputError, XacroArgumentError


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


def add_common(parser: argparse.ArgumentParser, mechanism: bool = True) -> None:
    """Add ``NAME``, ``--arg`` and ``--json`` to a subcommand parser."""
    if mechanism:
        parser.add_argument("name", metavar="NAME", help="mechanism name (rcm-pin list)")
        parser.add_argument(
            "--arg", action="append", metavar="KEY=VALUE", help="xacro argument (repeatable)"
        )
    parser.add_argument("--json", action="store_true", help="print one JSON document")


def to_jsonable(value: Any) -> Any:
    """Numpy arrays and scalars to lists and floats, recursively."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (np.floating, np.integer)):
        return value.item()
    if isinstance(value, dict):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_jsonable(v) for v in value]
    return value


def emit(args: argparse.Namespace, payload: dict[str, Any], text: str) -> None:
    """Print ``payload`` as JSON with ``--json``, else the human-readable ``text``."""
    if getattr(args, "json", False):
        print(json.dumps(to_jsonable(payload), indent=2))
    else:
        print(text)


def fmt(values: np.ndarray, digits: int = 6) -> str:
    """Format a vector compactly."""
    return "[" + ", ".join(f"{v:.{digits}g}" for v in np.asarray(values).ravel()) + "]"
