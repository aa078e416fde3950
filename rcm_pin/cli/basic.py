"""``rcm-pin list | urdf | fk | ik``: catalogue, rendering, position problems."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from rcm_pin.catalog import get_spec, mechanisms
from rcm_pin.cli._common import add_common, emit, fmt, parse_matrix, parse_vector, parse_xacro_args
from rcm_pin.errors import InvalidInputError, XacroArgumentError
from rcm_pin.mechanism import load
from rcm_pin.urdf_files import check_rendered, render_default, write_rendered


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

    p = sub.add_parser("fk", help="forward position problem (tool pose from q)")
    add_common(p)
    p.add_argument("--q", required=True, help="q1,...,qn in the papers' numbering [rad, m]")
    p.add_argument("--all", action="store_true", help="closed loops: every assembly mode")
    p.set_defaults(func=cmd_fk)

    p = sub.add_parser("ik", help="inverse position problem, every branch")
    add_common(p)
    p.add_argument("--pose", help='"r11,r12,r13,x;r21,r22,r23,y;r31,r32,r33,z" (or x,y,phi)')
    p.add_argument("--xyz", help="tool-centre position x,y,z [m]")
    p.add_argument("--rpy", help="alpha,beta,gamma [rad], R = Rz(gamma)Ry(beta)Rx(alpha)")
    p.add_argument("--within-limits", action="store_true", help="only branches inside limits")
    p.set_defaults(func=cmd_ik)


def cmd_list(args: argparse.Namespace) -> int:
    rows = [{"name": s.name, "kind": s.kind, "description": s.description} for s in mechanisms()]
    text = "\n".join(f"{r['name']:<16} {r['kind']:<7} {r['description']}" for r in rows)
    emit(args, {"mechanisms": rows}, text)
    return 0


def cmd_urdf(args: argparse.Namespace) -> int:
    if args.check or args.update:
        if args.update:
            written = write_rendered()
            emit(args, {"written": [str(p) for p in written]}, "\n".join(map(str, written)))
            return 0
        stale = check_rendered()
        emit(
            args,
            {"stale": stale},
            "urdf/ is up to date" if not stale else "stale: " + ", ".join(stale),
        )
        return 1 if stale else 0
    if not args.name:
        raise XacroArgumentError("rcm-pin urdf needs NAME, --check or --update")
    urdf = render_default(args.name, parse_xacro_args(args.arg))
    if args.output:
        args.output.write_text(urdf)
        emit(args, {"written": str(args.output)}, f"wrote {args.output}")
    elif args.json:
        emit(args, {"urdf": urdf}, urdf)
    else:
        print(urdf, end="")
    return 0


def cmd_fk(args: argparse.Namespace) -> int:
    if get_spec(args.name).kind == "closed":
        from rcm_pin.closed_loop import direct_position, load_closed

        closed = load_closed(args.name, **parse_xacro_args(args.arg))
        result = direct_position(closed, parse_vector(args.q, "q"), all_modes=args.all)
        payload = result.to_json()
        emit(args, payload, _closed_text(payload))
        return 0
    from rcm_pin.kinematics import rcm_error, tool_pose

    mech = load(args.name, **parse_xacro_args(args.arg))
    q = parse_vector(args.q, "q", mech.nq)
    T = tool_pose(mech, q)
    payload = {
        "mechanism": mech.name,
        "q": dict(zip(mech.coordinate_names, q.tolist())),
        "tool_pose": T,
        "position": T[:3, 3],
        "rcm_error": rcm_error(mech, q) if mech.rcm_frame_id >= 0 else None,
    }
    text = f"q = {fmt(q)}\ntool pose =\n{np.array2string(T, precision=6, suppress_small=True)}"
    emit(args, payload, text)
    return 0


def cmd_ik(args: argparse.Namespace) -> int:
    if get_spec(args.name).kind == "closed":
        from rcm_pin.closed_loop import inverse_position, load_closed

        if not args.pose:
            raise InvalidInputError("closed mechanisms take --pose x,y,phi (five_bar: x,y)")
        closed = load_closed(args.name, **parse_xacro_args(args.arg))
        payload = inverse_position(closed, parse_vector(args.pose, "pose")).to_json()
        emit(args, payload, _closed_text(payload))
        return 0
    from rcm_pin.inverse import solve_ik, solve_ik_position

    mech = load(args.name, **parse_xacro_args(args.arg))
    T = _target(args)
    position_only = bool(args.xyz) and not args.rpy and not args.pose
    solution = solve_ik_position(mech, T[:3, 3]) if position_only else solve_ik(mech, T)
    kept = [
        (q, bool(ok))
        for q, ok in zip(solution.q, solution.within_limits)
        if ok or not args.within_limits
    ]
    branches = [
        {"q": dict(zip(mech.coordinate_names, q.tolist())), "within_limits": ok} for q, ok in kept
    ]
    payload = {
        "mechanism": mech.name,
        "target": T,
        "position_only": position_only,
        "rotation_projection_distance": solution.projection_distance,
        "branches": branches,
    }
    lines = (
        ["position only: q1..q3 (the remaining coordinates are free)"]
        if position_only
        else [f"rotation projected by {solution.projection_distance:.3g} (Frobenius)"]
    )
    lines += [f"{'in ' if ok else 'out'} q = {fmt(q, 4)}" for q, ok in kept]
    emit(args, payload, "\n".join(lines))
    return 0


def _closed_text(payload: dict) -> str:
    """Human-readable lines for a closed-loop position result."""
    head = f"{payload['mechanism']}: {payload['kind']} position problem"
    lines = [
        f"{head}, {payload['count']} solution(s) ({payload['method']})",
        f"joints: {', '.join(payload['joint_names'])}",
    ]
    for sol in payload["solutions"]:
        pose, q = fmt(np.array(sol["pose"])), fmt(np.array(sol["q"]), 4)
        lines.append(f"mode {sol['mode']}: pose = {pose}  q = {q}  residual {sol['residual']:.1e}")
    return "\n".join(lines)


def _target(args: argparse.Namespace) -> np.ndarray:
    from rcm_pin.rotations import rpy_to_matrix

    T = np.eye(4)
    if args.pose:
        M = parse_matrix(args.pose, "pose")
        if M.shape not in {(3, 4), (4, 4)}:
            raise InvalidInputError(f"--pose has shape {M.shape}; valid: 3 rows of 4 numbers")
        T[:3, :] = M[:3, :]
        return T
    if not args.xyz:
        raise InvalidInputError("ik needs --pose, or --xyz (with --rpy for six-DOF mechanisms)")
    T[:3, 3] = parse_vector(args.xyz, "xyz", 3)
    if args.rpy:
        T[:3, :3] = rpy_to_matrix(*parse_vector(args.rpy, "rpy", 3))
    return T
