"""The ``rcm-pin`` command line.

Each subcommand lives in its own module with a ``register(subparsers)`` function that
adds its parser and sets ``func``. Every subcommand accepts ``--json`` and then prints
one JSON document on stdout (schema in ``docs/cli.md``); errors print
``{"error": {"type": ..., "message": ...}}`` with exit status 2.
"""

from __future__ import annotations

import argparse
import importlib
import json
import sys
from collections.abc import Sequence

from rcm_pin.errors import RcmPinError

#: Modules that contribute subcommands, in help order.
COMMAND_MODULES: tuple[str, ...] = (
    "rcm_pin.cli.basic",
    "rcm_pin.cli.reproduce",
    "rcm_pin.cli.analysis",
    "rcm_pin.cli.simulate",
    "rcm_pin.cli.ocp",
    "rcm_pin.cli.view",
)


def build_parser() -> argparse.ArgumentParser:
    """The argparse parser with every available subcommand."""
    parser = argparse.ArgumentParser(
        prog="rcm-pin",
        description="RCM and parallel mechanisms on Pinocchio (papers 000-004).",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name in COMMAND_MODULES:
        try:
            module = importlib.import_module(name)
        except ModuleNotFoundError as exc:
            if exc.name == name:
                continue  # that part of the toolkit is not installed in this tree
            raise
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``rcm-pin`` console script."""
    parser = build_parser()
    args = parser.parse_args(argv)
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
