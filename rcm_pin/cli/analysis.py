"""``rcm-pin singularities | workspace | accuracy``: Jacobian analyses of a mechanism."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from rcm_pin.catalog import get_spec
from rcm_pin.cli._common import add_common, emit, fmt, parse_vector, parse_xacro_args
from rcm_pin.errors import InvalidInputError, UnknownMechanismError
from rcm_pin.mechanism import load

_CLOSED_HELP = "closed loops (planar_3rrr, five_bar): "


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommands of this module."""
    p = sub.add_parser(
        "singularities",
        help="Jacobian rank, singular values, named causes (closed loops: type 1 / type 2)",
    )
    add_common(p)
    p.add_argument(
        "--q",
        help="q1,...,qn [rad, m]: analyse one configuration ("
        + _CLOSED_HELP
        + "drive angles, every assembly mode)",
    )
    p.add_argument(
        "--grid",
        nargs="?",
        const="",
        help="i,j[,N]: map a measure over coordinates qi, qj (1-based); "
        + _CLOSED_HELP
        + "bare --grid maps det A / det B over the workspace",
    )
    p.add_argument("--pose", help=_CLOSED_HELP + "output pose x,y,phi (five_bar: x,y)")
    p.add_argument("--mode", help=_CLOSED_HELP + "working mode, index or signs like +-+")
    p.add_argument("--phi", type=float, default=0.0, help=_CLOSED_HELP + "grid orientation [rad]")
    p.add_argument("--n", type=int, default=121, help=_CLOSED_HELP + "grid points per side")
    p.add_argument("--task", default="full", choices=("full", "position"))
    p.add_argument(
        "--measure",
        default="manipulability",
        choices=("manipulability", "sigma_min", "inverse_condition"),
    )
    p.add_argument("--wide", action="store_true", help="grid over +-pi (q3: +-q3_upper)")
    p.add_argument("--plot", type=Path, help="grid: write a PNG")
    p.set_defaults(func=cmd_singularities)

    p = sub.add_parser(
        "workspace",
        help="reachable tool-centre set, volume, rig-spec check (closed loops: areas)",
    )
    add_common(p)
    p.add_argument("--samples", type=int, default=200_000, help="joint samples (default 2e5)")
    p.add_argument("--plot", type=Path, help="write a PNG of workspace sections")
    p.add_argument(
        "--phi", type=float, default=0.0, help=_CLOSED_HELP + "constant orientation [rad]"
    )
    p.add_argument(
        "--phi-range", help=_CLOSED_HELP + "lo,hi [rad] of the total workspace (default -pi,pi)"
    )
    p.add_argument("--n", type=int, default=121, help=_CLOSED_HELP + "grid points per side")
    p.set_defaults(func=cmd_workspace)

    p = sub.add_parser("accuracy", help="first-order sensitivity to manufacturing errors")
    add_common(p)
    p.add_argument("--q", help="configuration q1,...,qn (default: a regular mid-range one)")
    p.set_defaults(func=cmd_accuracy)


def _base_q(mech, text: str | None) -> np.ndarray:
    if text:
        return parse_vector(text, "q", mech.nq)
    q = 0.5 * (mech.lower + mech.upper)
    if mech.nq == 6:
        q[4] = 0.5  # away from the zyz wrist singularity sin q5 = 0
    return q


def is_closed(name: str) -> bool:
    """True for a closed-loop catalogue entry (paths and unknown names stay serial)."""
    try:
        return get_spec(name).kind == "closed"
    except UnknownMechanismError:
        return False


def _closed_only(args: argparse.Namespace, options: dict[str, object]) -> None:
    given = [k for k, v in options.items() if v]
    if given:
        raise InvalidInputError(
            f"{', '.join(given)} apply to closed mechanisms only; valid for {args.name}: "
            "see rcm-pin " + args.command + " --help"
        )


def cmd_singularities(args: argparse.Namespace) -> int:
    from rcm_pin import singularity as sg

    if is_closed(args.name):
        return _closed_singularities(args)
    _closed_only(args, {"--pose": args.pose, "--mode": args.mode})
    mech = load(args.name, **parse_xacro_args(args.arg))
    if (args.q is None) == (args.grid is None):
        raise InvalidInputError("singularities needs exactly one of --q or --grid")
    if args.grid == "":
        raise InvalidInputError("--grid needs i,j[,N] for serial mechanisms, e.g. --grid 1,2,41")
    if args.q is not None:
        q = parse_vector(args.q, "q", mech.nq)
        analyses = {t: sg.analyse(mech, q, t) for t in sg.TASKS}
        causes = sg.classify(mech, q) if mech.rcm_frame_id >= 0 else []
        payload = {
            "mechanism": mech.name,
            "q": q,
            "rank_tolerance": sg.RANK_TOL,
            **{t: a.to_json() for t, a in analyses.items()},
            "causes": [c.__dict__ for c in causes],
        }
        lines = [
            f"{t}: rank {a.rank}/{a.full_rank}, sigma = {fmt(a.singular_values, 4)}, "
            f"manipulability {a.manipulability:.4g}, condition {a.condition:.4g}"
            for t, a in analyses.items()
        ]
        lines += [f"cause: {c.name}: {c.description} ({c.condition})" for c in causes]
        lines += ["regular"] if not causes and not analyses["full"].singular else []
        emit(args, payload, "\n".join(lines))
        return 0
    parts = parse_vector(args.grid, "grid")
    if len(parts) not in (2, 3) or not all(float(v).is_integer() for v in parts):
        raise InvalidInputError(f"--grid {args.grid!r}; valid: i,j[,N] with integers, e.g. 1,2,41")
    i, j = int(parts[0]) - 1, int(parts[1]) - 1
    n = int(parts[2]) if len(parts) == 3 else 41
    q0 = _base_q(mech, None)
    span = None
    if args.wide:
        wide = [(-np.pi, np.pi)] * mech.nq
        wide[2] = (-mech.upper[2], mech.upper[2])
        if 0 <= i < mech.nq and 0 <= j < mech.nq:
            span = (wide[i], wide[j])
    xs, ys, vals = sg.grid(mech, q0, i, j, n, args.task, args.measure, span)
    if args.plot:
        _plot_grid(args, mech.name, xs, ys, vals, i, j)
    payload = {
        "mechanism": mech.name,
        "base_q": q0,
        "coordinates": [i + 1, j + 1],
        "task": args.task,
        "measure": args.measure,
        "x": xs,
        "y": ys,
        "values": vals,
        "min": float(vals.min()),
        "max": float(vals.max()),
        "plot": str(args.plot) if args.plot else None,
    }
    text = (
        f"{args.measure} ({args.task}) over q{i + 1} x q{j + 1} ({n}x{n}): "
        f"min {vals.min():.4g}, max {vals.max():.4g}"
    )
    emit(args, payload, text + (f"\nwrote {args.plot}" if args.plot else ""))
    return 0


def _plot_grid(args, name, xs, ys, vals, i, j) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 5))
    im = ax.pcolormesh(xs, ys, vals, shading="auto", cmap="viridis")
    fig.colorbar(im, ax=ax, label=f"{args.measure} ({args.task} Jacobian)")
    ax.set(xlabel=f"q{i + 1}", ylabel=f"q{j + 1}", title=f"{name}: {args.measure}")
    fig.tight_layout()
    fig.savefig(args.plot, dpi=110)
    plt.close(fig)


def cmd_workspace(args: argparse.Namespace) -> int:
    from rcm_pin import workspace as ws

    if is_closed(args.name):
        return _closed_workspace(args)
    _closed_only(args, {"--phi-range": args.phi_range})
    mech = load(args.name, **parse_xacro_args(args.arg))
    if args.samples < 1000:
        raise InvalidInputError(f"--samples {args.samples}; valid: >= 1000")
    s = ws.summary(mech, args.samples)
    if args.plot:
        ws.plot_sections(mech, args.plot, min(args.samples, 200_000))
    s["plot"] = str(args.plot) if args.plot else None
    spec = s["spec"]
    assert isinstance(spec, dict)
    text = "\n".join(
        [
            f"volume analytic {s['volume_analytic']:.6g} m^3, Monte Carlo "
            f"{s['volume_monte_carlo']:.6g} +- {s['volume_monte_carlo_stderr']:.2g}, voxels "
            f"{s['volume_voxels']:.6g} (edge {s['voxel_edge']} m)",
            *[f"boundary: {b}" for b in s["boundary"]],  # type: ignore[attr-defined]
            "rig spec (60 deg cone, 0.05..0.12 m): "
            f"{'contained' if spec['contains'] else 'NOT contained'}"
            f"; angular margin {np.rad2deg(spec['angular_margin']):.3g} deg, inner "
            f"{spec['inner_margin']:.3g} m, outer {spec['outer_margin']:.3g} m",
        ]
    )
    emit(args, s, text + (f"\nwrote {args.plot}" if args.plot else ""))
    return 0


def cmd_accuracy(args: argparse.Namespace) -> int:
    from rcm_pin import accuracy as acc

    xargs = parse_xacro_args(args.arg)
    mech = load(args.name, **xargs)
    q = _base_q(mech, args.q)
    if args.q is None:  # ratio errors act through q2: take q2 at 80 % of its limit
        q[0], q[1] = 0.5 * mech.upper[0], 0.8 * mech.upper[1]
    rep = acc.report(args.name, q, xargs)
    lines = [
        f"{r['parameter']:<26} {r['kind']:<14} tool {r['tool_per_error']:.3g} m, "
        f"RCM line {r['rcm_per_error']:.3g} m"
        for r in rep["rows"]
    ]
    emit(args, rep, "\n".join(lines))
    return 0


# ------------------------------------------------------------------ closed loops
def _closed_singularities(args: argparse.Namespace) -> int:
    from rcm_pin.closed_loop import direct_position, load_closed
    from rcm_pin.closed_loop import summary as sm
    from rcm_pin.closed_loop.core import wrap

    mech = load_closed(args.name, **parse_xacro_args(args.arg))
    given = [
        o
        for o, v in (("--pose", args.pose), ("--q", args.q), ("--grid", args.grid))
        if v is not None
    ]
    if len(given) != 1:
        raise InvalidInputError(
            f"singularities {args.name} needs exactly one of --pose, --q or --grid"
        )
    mode = sm.parse_mode(mech, args.mode)
    if args.grid is not None:
        if args.grid != "":
            raise InvalidInputError(
                f"--grid takes no value for closed mechanisms (got {args.grid!r}); "
                "valid: --grid [--mode M] [--phi PHI] [--n N]"
            )
        res = sm.singularity_map(mech, 0 if mode is None else mode, args.phi, args.n)
        if args.plot:
            res["plot"] = str(sm.plot_singularity_map(res, args.plot))
        else:
            res["plot"] = None
        text = (
            f"{mech.name}: det A / det B map, mode {res['mode']}"
            + (f", phi = {args.phi:g} rad" if res["phi"] is not None else "")
            + f" ({args.n}x{args.n}): reachable area {res['reachable_area']:.4g} m^2, "
            f"{res['type2_sign_changes']} type-2 crossings along rows, "
            f"min |det A| {res['min_abs_det_A']:.3g}, min |det B| {res['min_abs_det_B']:.3g}"
        )
        emit(args, sm.nan_to_none(res), text + (f"\nwrote {args.plot}" if args.plot else ""))
        return 0
    if args.plot:
        raise InvalidInputError("--plot needs --grid")
    if args.pose is not None:
        res = sm.pose_singularities(mech, parse_vector(args.pose, "pose", mech.dof), mode)
    else:
        if mode is not None:
            raise InvalidInputError("--mode selects a working mode of --pose or --grid, not --q")
        drives = parse_vector(args.q, "q", mech.dof)
        modes = []
        for sol in direct_position(mech, drives, all_modes=True).solutions:
            one = sm.pose_singularities(mech, sol.pose, None)
            for m in one["modes"]:
                if float(np.max(np.abs(wrap(m["q"] - sol.q)))) < 1e-7:
                    modes.append({**m, "pose": sol.pose, "assembly": sol.mode})
        res = {
            "mechanism": mech.name,
            "q_drives": drives,
            "output_coords": list(mech.output_coords),
            "tol": sm.SINGULAR_TOL,
            "modes": modes,
        }
    lines = [f"{mech.name}: tolerance {res['tol']:g} on sigma_min/sigma_max"]
    for m in res["modes"]:
        where = f" {m['assembly']} pose {fmt(m['pose'], 5)}," if "assembly" in m else ""
        screw = "agrees" if m["screw_agrees"] else "DISAGREES"
        lines.append(
            f"mode {m['mode']}:{where} {m['verdict']}; det A {m['det_A']:.4g}, det B "
            f"{m['det_B']:.4g}, sigma(A) {fmt(m['sigma_A'], 4)}, sigma(B) {fmt(m['sigma_B'], 4)}; "
            f"screw test {screw}"
        )
    emit(args, res, "\n".join(lines))
    return 0


def _closed_workspace(args: argparse.Namespace) -> int:
    from rcm_pin.closed_loop import load_closed
    from rcm_pin.closed_loop import summary as sm

    mech = load_closed(args.name, **parse_xacro_args(args.arg))
    lo_hi = (-np.pi, np.pi)
    if args.phi_range:
        lo, hi = parse_vector(args.phi_range, "phi-range", 2)
        lo_hi = (float(lo), float(hi))
    if not np.isfinite(args.phi):
        raise InvalidInputError(f"--phi {args.phi}; valid: a finite angle [rad]")
    res = sm.workspace_areas(mech, args.phi, lo_hi, n=args.n)
    res["plot"] = str(sm.plot_workspace(mech, args.plot, args.phi, args.n)) if args.plot else None
    text = (
        f"{mech.name} ({args.n}x{args.n} grid): constant-orientation area "
        f"{res['constant_orientation_area']:.5g} m^2"
        + (f" (phi = {args.phi:g} rad)" if res["phi"] is not None else "")
        + f", total {res['total_area']:.5g} m^2, reachable {res['reachable_area']:.5g} m^2"
    )
    emit(args, res, text + (f"\nwrote {args.plot}" if args.plot else ""))
    return 0
