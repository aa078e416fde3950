"""``rcm-pin list | urdf``: the catalogue and its committed renderings."""

from __future__ import annotations

import argparse
from pathlib import Path

from rcm_pin.catalog import mechanisms
from rcm_pin.catalog.files import check_rendered, render_default, stray_files, write_rendered
from rcm_pin.cli._common import add_common, emit, output_path, parse_xacro_args
from rcm_pin.errors import XacroArgumentError


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommands of this module."""
    p = sub.add_parser("list", help="list the shipped mechanisms")
    add_common(p, mechanism=False)
    p.set_defaults(func=cmd_list)

    p = sub.add_parser("urdf", help="render a mechanism's URDF; --check / --update urdf/")
    p.add_argument("name", nargs="?", metavar="NAME")
    p.add_argument("--arg", action="append", metavar="KEY=VALUE")
    p.add_argument("-o", "--output", type=Path, help="write to this file (default: stdout)")
    p.add_argument("--check", action="store_true", help="fail if urdf/ is stale")
    p.add_argument("--update", action="store_true", help="re-render every file in urdf/")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_urdf)


def cmd_list(args: argparse.Namespace) -> int:
    """``rcm-pin list``: name, kind, family and description of every entry."""
    rows = [
        {"name": e.name, "kind": e.kind, "family": e.family.name, "description": e.description}
        for e in mechanisms()
    ]
    width = max(len(r["name"]) for r in rows)
    text = "\n".join(f"{r['name']:<{width}}  {r['kind']:<7} {r['description']}" for r in rows)
    emit(args, {"mechanisms": rows}, text)
    return 0


def cmd_urdf(args: argparse.Namespace) -> int:
    """``rcm-pin urdf``: render one mechanism, or check / update ``urdf/``."""
    if args.check or args.update:
        if args.update:
            written = write_rendered()
            emit(args, {"written": [str(p) for p in written]}, "\n".join(map(str, written)))
            return 0
        stale, strays = check_rendered(), stray_files()
        emit(
            args,
            {"stale": stale, "strays": strays},
            "urdf/ is up to date"
            if not stale
            else "stale: "
            + ", ".join(stale)
            + "".join(f"\n{name}: not a catalogue rendering (remove it)" for name in strays),
        )
        return 1 if stale else 0
    if not args.name:
        raise XacroArgumentError("rcm-pin urdf needs NAME, --check or --update")
    if args.output:
        output_path(args.output, "-o")
    urdf = render_default(args.name, parse_xacro_args(args.arg))
    if args.output:
        args.output.write_text(urdf)
        emit(args, {"written": str(args.output)}, f"wrote {args.output}")
    elif args.json:
        emit(args, {"urdf": urdf}, urdf)
    else:
        print(urdf, end="")
    return 0
