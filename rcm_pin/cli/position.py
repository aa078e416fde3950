"""``rcm-pin fk | ik``: the position problems of every mechanism, one path each.

``fk`` takes the mechanism's inputs (``--q``: the coordinates of a serial mechanism, the
drive values of a closed one) and prints every assembly mode with ``--all``; ``ik`` takes an
output target (``--pose``: a 3×4 tool pose ``"r11,r12,r13,x;..."`` or the output coordinates
of a closed mechanism; ``--xyz`` with or without ``--rpy`` / ``--rotation`` for a tool frame;
``--rpy`` or ``--rotation`` alone for an output that is a rotation) and prints every
branch / working mode. A solution whose output has a rotation also carries it as
``rotation`` (3×3). JSON schema in ``docs/cli.md``.
"""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

from rcm_pin.analysis.position import PositionResult, forward, inverse
from rcm_pin.cli._common import (
    add_common,
    emit,
    fmt,
    load_mechanism,
    parse_vector,
    target_from_args,
)
from rcm_pin.errors import InvalidInputError
from rcm_pin.model.output import POSE
from rcm_pin.rotations import project_to_rotation


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommands of this module."""
    p = sub.add_parser("fk", help="forward (direct) position problem")
    add_common(p)
    p.add_argument(
        "--q", required=True, help="inputs: coordinates q1..qn [rad, m] (closed: drives)"
    )
    p.add_argument("--all", action="store_true", help="closed loops: every assembly mode")
    p.set_defaults(func=cmd_fk)

    p = sub.add_parser("ik", help="inverse position problem, every branch / working mode")
    add_common(p)
    p.add_argument(
        "--pose",
        help='"r11,r12,r13,x;r21,r22,r23,y;r31,r32,r33,z", or the output '
        "coordinates of a closed mechanism (e.g. x,y,phi)",
    )
    p.add_argument("--xyz", help="tool-frame position x,y,z [m]")
    p.add_argument(
        "--rpy",
        help="alpha,beta,gamma [rad], R = Rz(gamma)Ry(beta)Rx(alpha): the tool orientation "
        "(with --xyz), or the target of a mechanism whose output is a rotation",
    )
    p.add_argument(
        "--rotation",
        help="r11,r12,...,r33 (row by row): a rotation matrix, as --rpy (orthonormal within "
        "1e-2, then projected onto SO(3))",
    )
    p.add_argument("--within-limits", action="store_true", help="only solutions inside limits")
    p.add_argument(
        "--starts",
        type=int,
        metavar="N",
        help="starts of the numeric multistart where no closed form answers (serial: 16, "
        "closed: 96; seeded); none found: exit 3 unless the reach bound proves the target "
        "unreachable",
    )
    p.set_defaults(func=cmd_ik)


def result_text(result: PositionResult) -> str:
    """Human-readable lines of a position result."""
    mech = result.mechanism
    lines = [
        f"{mech.name}: {result.kind} position problem, {result.count} solution(s) ({result.method})"
    ]
    if result.solutions:  # the legend of the prefix of each solution line
        keep = "; ik --within-limits keeps the 'in' ones" if result.kind == "inverse" else ""
        lines.append(f"in / out: every coordinate inside its joint limits / some outside{keep}")
    for sol in result.solutions:
        out = result.output.to_json(sol.output)
        scalars = {k: v for k, v in out.items() if k not in ("rotation", "angles")}
        where = "in " if sol.within_limits else "out"
        values = fmt(np.array(list(scalars.values())))
        if "angles" in out and not scalars:  # a rotation output: the papers' α, β, γ
            values = f"alpha,beta,gamma {fmt(np.array(out['angles']))}"
        lines.append(
            f"{where} {sol.mode}: q = {fmt(sol.q, 6)}  output {values}"
            + (f"  residual {sol.residual:.1e}" if mech.loops is not None else "")
        )
    if mech.loops is None and result.kind == "forward":
        pose = np.array(result.to_json()["solutions"][0]["pose"])
        lines.append(f"tool pose =\n{np.array2string(pose, precision=6, suppress_small=True)}")
    return "\n".join(lines)


def cmd_fk(args: argparse.Namespace) -> int:
    """``rcm-pin fk``."""
    mech = load_mechanism(args)
    n = mech.loops.dof if mech.loops is not None else mech.nq
    if args.all and mech.loops is None:
        raise InvalidInputError(
            f"--all lists the assembly modes of closed mechanisms; {mech.name} is serial"
        )
    result = forward(mech, parse_vector(args.q, "q", n), all_modes=args.all)
    emit(args, with_rotations(result.to_json()), result_text(result))
    return 0


def cmd_ik(args: argparse.Namespace) -> int:
    """``rcm-pin ik``."""
    mech = load_mechanism(args)
    value, coords = target_from_args(mech, args)
    result = inverse(mech, value, coords, limits=args.within_limits, starts=args.starts)
    payload = with_rotations(result.to_json())
    payload["position_only"] = coords == ("x", "y", "z")
    if "rotation" in coords:  # distance of the given R from SO(3) (it was projected)
        k = 3 if coords == POSE else 0
        payload["rotation_projection_distance"] = float(
            project_to_rotation(value[k : k + 9].reshape(3, 3))[1]
        )
    emit(args, payload, result_text(result))
    return 0


def with_rotations(payload: dict[str, Any]) -> dict[str, Any]:
    """Each solution's output rotation (3×3) also as its ``rotation`` key (when it has one)."""
    for sol in payload["solutions"]:
        if "rotation" in sol["output"]:
            sol["rotation"] = sol["output"]["rotation"]
    return payload
