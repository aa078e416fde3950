"""``rcm-pin ocp ik | track``: the CasADi layer (numerical IK, tracking OCP) from the CLI."""

from __future__ import annotations

import argparse

from rcm_pin.cli._common import add_common, emit, parse_vector, parse_xacro_args
from rcm_pin.errors import InvalidInputError


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``ocp`` with its ``ik`` and ``track`` subcommands."""
    p = sub.add_parser("ocp", help="CasADi problems: numerical IK NLP, tracking OCP")
    ocp_sub = p.add_subparsers(dest="ocp_command", required=True, metavar="PROBLEM")

    ik = ocp_sub.add_parser("ik", help="numerical IK of the tool frame (LM / IPOPT / SQP)")
    add_common(ik)
    ik.add_argument("--xyz", required=True, help="tool-centre position x,y,z [m]")
    ik.add_argument("--rpy", help="alpha,beta,gamma [rad], R = Rz(gamma)Ry(beta)Rx(alpha)")
    ik.add_argument("--q0", help="initial guess q1,...,qn (default: restarts from the middle)")
    ik.add_argument("--solver", default="auto", choices=("auto", "lm", "ipopt", "sqpmethod"))
    ik.set_defaults(func=cmd_ik)

    tr = ocp_sub.add_parser("track", help="paper 000 tracking OCP (direct collocation)")
    tr.add_argument("name", nargs="?", default="rcm_bevel", metavar="NAME")
    tr.add_argument("--n", type=int, default=100, help="collocation intervals (default 100)")
    tr.add_argument("--solver", default="ipopt", choices=("ipopt", "fatrop"))
    tr.add_argument(
        "--limit-scale",
        type=float,
        help="drive limits on q1..q3 at this fraction of the analytic peak efforts",
    )
    tr.add_argument("--json", action="store_true")
    tr.set_defaults(func=cmd_track)


def cmd_ik(args: argparse.Namespace) -> int:
    from ocp.commands import format_ik, ik_command

    payload = ik_command(
        args.name,
        parse_vector(args.xyz, "xyz", 3),
        rpy=None if args.rpy is None else parse_vector(args.rpy, "rpy", 3),
        q0=None if args.q0 is None else parse_vector(args.q0, "q0"),
        solver=args.solver,
        xacro_args=parse_xacro_args(args.arg),
    )
    emit(args, payload, format_ik(payload))
    return 0


def cmd_track(args: argparse.Namespace) -> int:
    from ocp.commands import format_track, track_command

    if args.n < 2:
        raise InvalidInputError(f"--n {args.n} is too small; valid: an integer >= 2")
    payload = track_command(
        args.name, n_intervals=args.n, solver=args.solver, limit_scale=args.limit_scale
    )
    emit(args, payload, format_track(payload))
    return 0
