"""``rcm-pin reproduce``: regenerate every paper's results into a report."""

from __future__ import annotations

import argparse
from pathlib import Path

from rcm_pin.cli._common import emit, output_path


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``reproduce`` subcommand."""
    p = sub.add_parser("reproduce", help="regenerate every paper result into report.md")
    p.add_argument("--out", type=Path, default=Path("report"), help="output directory")
    p.add_argument("--only", action="append", help="run only sections matching this word")
    p.add_argument("--jobs", type=int, help="parallel processes (default: the number of cores)")
    p.add_argument(
        "--no-cache", action="store_true", help="recompute sections whose inputs are unchanged"
    )
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_reproduce)


def cmd_reproduce(args: argparse.Namespace) -> int:
    from rcm_pin.report.writer import write_report

    output_path(args.out, "--out", directory=True)
    path = write_report(
        args.out, only=args.only, quiet=args.json, jobs=args.jobs, cache=not args.no_cache
    )
    emit(args, {"report": str(path)}, f"report written to {path}")
    return 0
