"""The ``rcm-pin`` command line.

Each subcommand lives in its own module with a ``register(subparsers)`` function that
adds its parser and sets ``func``; the modules are listed once, by explicit import. Every
subcommand accepts ``--json`` and then prints one JSON document on stdout (schema in
``docs/cli.md``). Exit statuses: 0 success; 1 ``urdf --check`` found stale files; 2 bad
input (any :class:`~rcm_pin.errors.RcmPinError` but a solver failure, and argparse usage
errors); 3 a solver that failed (:class:`~rcm_pin.errors.SolverError`: infeasible, not
converged, limits violated). With ``--json`` every error, argparse's included, prints one
document ``{"error": {"type": ..., "message": ...}}`` (plus ``"result"`` when a failed solve
reports one) on stdout.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
import types
import warnings
from collections.abc import Sequence

from rcm_pin.cli import (
    analysis,
    catalog,
    design,
    export,
    fourbar,
    ocp,
    position,
    rcm_track,
    reproduce,
    simulate,
    vibrations,
    view,
)
from rcm_pin.errors import RcmPinError, SolverError

#: Modules that contribute subcommands, in help order.
Modules = tuple[types.ModuleType, ...]
COMMAND_MODULES: Modules = (catalog, position, reproduce, analysis, simulate, ocp, view, design)
COMMAND_MODULES += (fourbar,)
COMMAND_MODULES += (rcm_track,)
COMMAND_MODULES += (vibrations,)
COMMAND_MODULES += (export,)


#: Exit status of bad input (typed errors and argparse usage errors).
BAD_INPUT = 2
#: Exit status of a solver that failed (infeasible, not converged, limits violated).
SOLVER_FAILED = 3


class UsageError(Exception):
    """An argparse usage error, raised instead of argparse's print-and-exit."""


class _Parser(argparse.ArgumentParser):
    """argparse that raises :class:`UsageError` so that ``--json`` can report it as JSON."""

    def error(self, message: str) -> None:  # type: ignore[override]
        raise UsageError(f"{self.prog}: {message}")


def build_parser() -> argparse.ArgumentParser:
    """The argparse parser with every subcommand."""
    parser = _Parser(
        prog="rcm-pin",
        description="RCM and parallel mechanisms on Pinocchio (papers 000-004).",
    )
    sub = parser.add_subparsers(
        dest="command", required=True, metavar="COMMAND", parser_class=_Parser
    )
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


def _report(as_json: bool, kind: str, message: str, result: object = None) -> None:
    """One line on stderr, or the JSON error document on stdout."""
    if as_json:
        from rcm_pin.cli._common import to_jsonable

        error: dict[str, object] = {"type": kind, "message": message}
        if result is not None:
            error["result"] = to_jsonable(result)
        print(json.dumps({"error": error}, allow_nan=False))
    else:
        print(f"rcm-pin: error: {kind}: {message}", file=sys.stderr)


def _format_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    line: str | None = None,
) -> str:
    """rcm-pin's own warnings as one line ``rcm-pin: warning: ...`` (others as Python has them)."""
    if category.__module__.startswith("rcm_pin."):
        return f"rcm-pin: warning: {message}\n"
    return _python_format(message, category, filename, lineno, line)


_python_format = warnings.formatwarning


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``rcm-pin`` console script (exit statuses: module docstring)."""
    warnings.formatwarning = _format_warning
    tokens = join_negative_values(sys.argv[1:] if argv is None else argv)
    try:
        args = build_parser().parse_args(tokens)
    except UsageError as exc:
        _report("--json" in tokens, "UsageError", str(exc))
        return BAD_INPUT
    try:
        return int(args.func(args) or 0)
    except BrokenPipeError:  # e.g. `rcm-pin ... | head`: the reader left, not an error
        sys.stderr.close()
        return 0
    except SolverError as exc:
        _report(getattr(args, "json", False), type(exc).__name__, str(exc), _result(exc))
        return SOLVER_FAILED
    except RcmPinError as exc:
        _report(getattr(args, "json", False), type(exc).__name__, str(exc))
        return BAD_INPUT


def _result(exc: SolverError) -> object:
    """The JSON-able summary a failed solve carries (None when it has none)."""
    result = getattr(exc, "result", None)
    if result is None or isinstance(result, (dict, list, str, int, float, bool)):
        return result
    summary = getattr(result, "summary", None)
    return summary() if callable(summary) else {"success": False}


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
