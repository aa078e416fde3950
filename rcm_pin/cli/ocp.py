"""``rcm-pin ocp ik | track``: the CasADi layer (numerical IK, tracking OCP) from the CLI.

``ocp ik NAME`` takes every catalogue entry: serial mechanisms ``--xyz`` [``--rpy``] (the
tool frame) or ``--pose`` (a 3x4 tool pose ``"r11,r12,r13,x;...;r31,r32,r33,z"``, as for
``rcm-pin ik``; not together with ``--xyz`` / ``--rpy``), closed ones ``--pose`` with
their output coordinates (e.g. ``--pose 0.01,0.02,0.1`` = x, y, rz for planar_3rrr),
the loop closures as equality constraints.

A solve that fails (not converged, infeasible, limits violated) raises
:class:`~rcm_pin.errors.SolverError` (exit status 3) with the reason, and its ``result``
(``success: false``, ``reason``, the solver's status and statistics) instead of the last
iterate; a target at a stationary point with a residual is an
:class:`~rcm_pin.errors.UnreachablePoseError` (status 2).
"""

from __future__ import annotations

import argparse

import numpy as np

from rcm_pin.cli._common import (
    add_common,
    emit,
    load_mechanism,
    parse_matrix,
    parse_vector,
)
from rcm_pin.errors import InvalidInputError


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``ocp`` with its ``ik`` and ``track`` subcommands."""
    p = sub.add_parser("ocp", help="CasADi problems: numerical IK NLP, tracking OCP")
    ocp_sub = p.add_subparsers(dest="ocp_command", required=True, metavar="PROBLEM")

    ik = ocp_sub.add_parser(
        "ik",
        help="numerical IK of the tool frame or a closed mechanism's output (LM / IPOPT / SQP)",
    )
    add_common(ik)
    ik.add_argument("--xyz", help="serial: tool-centre position x,y,z [m]")
    ik.add_argument("--rpy", help="serial: alpha,beta,gamma [rad], R = Rz(gamma)Ry(beta)Rx(alpha)")
    ik.add_argument(
        "--pose",
        help="serial: 3x4 tool pose 'r11,r12,r13,x;...;r31,r32,r33,z'; closed: values of its "
        "output coordinates, e.g. x,y,rz [m, rad]",
    )
    ik.add_argument(
        "--q0", help="initial guess q1,...,qn (default: mid-range; closed: the home configuration)"
    )
    ik.add_argument("--solver", default="auto", choices=("auto", "lm", "ipopt", "sqpmethod"))
    ik.set_defaults(func=cmd_ik)

    tr = ocp_sub.add_parser("track", help="paper 000 tracking OCP (direct collocation)")
    # default None: ocp.paper000.MECHANISM, read in cmd_track (importing ocp loads CasADi)
    tr.add_argument("name", nargs="?", default=None, metavar="NAME")
    tr.add_argument(
        "--n",
        type=int,
        default=100,
        help="collocation intervals (default 100; at most 23860 for paper 000's model: about "
        "1 GiB of memory, ocp.tracking.check_size)",
    )
    tr.add_argument("--solver", default="ipopt", choices=("ipopt", "fatrop"))
    tr.add_argument(
        "--limit-scale",
        type=float,
        help="drive limits on q1..q3 at this fraction of the analytic peak efforts",
    )
    tr.add_argument(
        "--compile",
        action="store_true",
        help="compile the stage functions to C, cached on disk (the first build of a model "
        "takes about 10-80 s, later builds 0.1 s; each solve is 2-6x faster)",
    )
    tr.add_argument("--json", action="store_true")
    tr.set_defaults(func=cmd_track)


def cmd_ik(args: argparse.Namespace) -> int:
    from ocp.commands import format_ik, ik_command

    payload = ik_command(
        load_mechanism(args),  # the frame options of a path too
        None if args.xyz is None else parse_vector(args.xyz, "xyz", 3),
        rpy=None if args.rpy is None else parse_vector(args.rpy, "rpy", 3),
        pose=_pose(args.pose),
        q0=None if args.q0 is None else parse_vector(args.q0, "q0"),
        solver=args.solver,
    )
    emit(args, payload, format_ik(payload))
    return 0


def _pose(text: str | None) -> np.ndarray | None:
    """``--pose``: rows separated by ``;`` (a serial tool pose) or one row (closed)."""
    if text is None:
        return None
    return parse_matrix(text, "pose") if ";" in text else parse_vector(text, "pose")


def cmd_track(args: argparse.Namespace) -> int:
    from ocp.commands import format_track, track_command
    from ocp.paper000 import MECHANISM

    if args.name is None:
        args.name = MECHANISM
    if args.n < 2:
        raise InvalidInputError(f"--n {args.n} is too small; valid: an integer >= 2")
    payload = track_command(
        args.name,
        n_intervals=args.n,
        solver=args.solver,
        limit_scale=args.limit_scale,
        compile=args.compile,
    )
    emit(args, payload, format_track(payload))
    return 0
