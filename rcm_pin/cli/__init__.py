"""The ``rcm-pin`` command line.

Each subcommand lives in its own module with a ``register(subparsers)`` function that
adds its parser and sets ``func``; the modules are listed once, by explicit import. Every
subcommand accepts ``--json`` and then prints one JSON document on stdout (schema in
``docs/cli.md``); errors print ``{"error": {"type": ..., "message": ...}}`` with exit
status 2.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from collections.abc import Sequence

from rcm_pin.cli import analysis, catalog, ocp, position, reproduce, simulate, view
from rcm_pin.errors import RcmPinError

#: Modules that contribute subcommands, in help order.
COMMAND_MODULES = (catalog, position, reproduce, analysis, simulate, ocp, view)


def build_parser() -> argparse.ArgumentParser:
    """The argparse parser with every subcommand."""
    parser = argparse.ArgumentParser(
        prog="rcm-pin",
        description="RCM and parallel mechanisms on Pinocchio (papers 000-004).",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for module in COMMAND_MODULES:
        module.register(sub)
    return parser


_NEGATIVE = re.compile(r"^-(\d|\.\d)")


def join_negative_values(argv: Sequence[str]) -> list[str]:
    """``--q -0.2,0.1`` -> ``--q=-0.2,0.1``: a value that starts with a minus sign after an
    option is that option's value (argparse alone would take it for an option; no
    subcommand has a numeric positional argument)."""
    out: list[str] = []
    for token in argv:
        if out and _NEGATIVE.match(token) and out[-1].startswith("--") and "=" not in out[-1]:
            out[-1] = f"{out[-1]}={token}"
        else:
            out.append(token)
    return out


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``rcm-pin`` console script."""
    parser = build_parser()
    args = parser.parse_args(join_negative_values(sys.argv[1:] if argv is None else argv))
    try:
        return int(args.func(args) or 0)
    except BrokenPipeError:  # e.g. `rcm-pin ... | head`: the reader left, not an error
        sys.stderr.close()
        return 0
    except RcmPinError as exc:
        if getattr(args, "json", False):
            error = {"type": type(exc).__name__, "message": str(exc)}
            print(json.dumps({"error": error}))
        else:
            print(f"rcm-pin: error: {type(exc).__name__}: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
