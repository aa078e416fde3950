"""``rcm-pin singularities | workspace | accuracy``: analyses of any mechanism, one path each.

The analysis functions decide what the mechanism's structure means (a serial Jacobian's
rank, or a closed mechanism's type 1 / type 2); the commands only parse and print.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

from rcm_pin.analysis.singularity import MEASURES, TASKS
from rcm_pin.cli._common import (
    add_common,
    emit,
    fmt,
    load_mechanism,
    output_path,
    parse_vector,
    target_from_args,
)
from rcm_pin.errors import InvalidInputError
from rcm_pin.model.mechanism import Mechanism


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommands of this module."""
    p = sub.add_parser(
        "singularities",
        help="singular verdicts: Jacobian rank and named causes, or type 1 / type 2 (loops)",
    )
    add_common(p)
    p.add_argument("--q", help="inputs: coordinates (closed: drives; every assembly mode)")
    p.add_argument(
        "--pose",
        help="an output target (every branch / working mode): a 3x4 tool "
        "pose, or a closed mechanism's output coordinates",
    )
    p.add_argument("--xyz", help="serial: tool position x,y,z [m] (every position branch)")
    p.add_argument("--rpy", help="serial, with --xyz: alpha,beta,gamma [rad]")
    p.add_argument(
        "--grid",
        nargs="?",
        const="",
        help="i,j[,N]: map a measure over q_i, q_j "
        "(1-based); closed: bare --grid maps det A, "
        "det B over the workspace",
    )
    p.add_argument("--mode", help="working mode (index or label) of --pose or --grid")
    p.add_argument("--phi", type=float, help="closed --grid: angle output [rad] (default 0)")
    p.add_argument("--n", type=int, help="closed --grid: points per side (default 121)")
    p.add_argument("--task", choices=TASKS, help="serial: Jacobian rows (default full)")
    p.add_argument("--measure", choices=MEASURES, help="serial --grid (default manipulability)")
    p.add_argument("--wide", action="store_true", help="serial --grid over ±pi (lengths: ±max)")
    p.add_argument("--plot", type=Path, help="--grid: write a PNG")
    p.set_defaults(func=cmd_singularities)

    p = sub.add_parser("workspace", help="reachable set: volumes, areas, the family's figures")
    add_common(p)
    p.add_argument(
        "--samples", type=int, help="input samples (default 2e5; closed, numeric route: 1000)"
    )
    p.add_argument("--plot", type=Path, help="write a PNG of the workspace")
    p.add_argument("--phi", type=float, help="closed: constant orientation [rad] (default 0)")
    p.add_argument("--phi-range", help="closed: lo,hi [rad] of the total workspace")
    p.add_argument("--n", type=int, help="closed: grid points per side (default 121)")
    p.set_defaults(func=cmd_workspace)

    p = sub.add_parser("accuracy", help="first-order sensitivity to manufacturing errors")
    add_common(p)
    p.add_argument("--q", help="configuration (default: the family's regular / home one)")
    p.set_defaults(func=cmd_accuracy)


def supported(
    mech: Mechanism, args: argparse.Namespace, closed: tuple[str, ...] = (),
    serial: tuple[str, ...] = (),
) -> None:  # fmt: skip
    """Refuse options that do not apply to this kind of mechanism (never ignore them).

    Raises:
        InvalidInputError: names the option, the mechanism and the kind it applies to.
    """
    kind, others = ("closed", serial) if mech.loops is not None else ("serial", closed)
    for option in others:
        value = getattr(args, option.lstrip("-").replace("-", "_"), None)
        if value not in (None, False):
            applies = "serial" if kind == "closed" else "closed"
            raise InvalidInputError(
                f"{option} applies to {applies} mechanisms; {mech.name} is {kind}"
            )


def _mode_lines(rep: dict[str, Any]) -> list[str]:
    lines = []
    for m in rep["modes"]:
        if "full" in m:  # serial
            causes = "; ".join(c["name"] for c in m["causes"]) or "none"
            lines.append(
                f"{m['mode']}: {m['verdict']}; full rank {m['full']['rank']}/"
                f"{m['full']['full_rank']}, sigma {fmt(np.array(m['full']['singular_values']), 4)}"
                f"; position rank {m['position']['rank']}/{m['position']['full_rank']}; "
                f"causes: {causes}"
            )
        elif "sigma_passive" in m:  # closed, no output: type 2 alone
            lines.append(
                f"mode {m['mode']}: {m['verdict']}; measure {m['measure_type2']:.4g}, "
                f"sigma(J_c,p) {fmt(m['sigma_passive'], 4)}"
            )
        else:
            screw = {True: "agrees", False: "DISAGREES", None: "n/a (no legs)"}[m["screw_agrees"]]
            dets = "" if m["det_A"] is None else f"det A {m['det_A']:.4g}, det B {m['det_B']:.4g}, "
            lines.append(
                f"mode {m['mode']}: {m['verdict']}; {dets}sigma(A) {fmt(m['sigma_A'], 4)}, "
                f"sigma(B) {fmt(m['sigma_B'], 4)}; screw test {screw}"
            )
    return lines


def _grid_coords(text: str) -> tuple[tuple[int, int] | None, int | None]:
    if text == "":
        return None, None
    parts = parse_vector(text, "grid")
    if len(parts) not in (2, 3) or not all(float(v).is_integer() for v in parts):
        raise InvalidInputError(f"--grid {text!r}; valid: i,j[,N] with integers, e.g. 1,2,41")
    return (int(parts[0]) - 1, int(parts[1]) - 1), (int(parts[2]) if len(parts) == 3 else None)


def cmd_singularities(args: argparse.Namespace) -> int:
    """``rcm-pin singularities``."""
    from rcm_pin.analysis import singularity_report
    from rcm_pin.analysis.closed_singularity import parse_mode

    if args.plot:
        output_path(args.plot, "--plot")
    mech = load_mechanism(args)
    target = args.pose if args.pose is not None else args.xyz
    given = [
        o
        for o, v in (("--q", args.q), ("--pose/--xyz", target), ("--grid", args.grid))
        if v is not None
    ]
    if len(given) != 1:
        raise InvalidInputError("singularities needs exactly one of --q, --pose (--xyz) or --grid")
    supported(mech, args, closed=("--phi", "--n"), serial=("--task", "--measure", "--wide"))
    phi = 0.0 if args.phi is None else args.phi
    task, measure = args.task or "full", args.measure or "manipulability"
    mode = parse_mode(mech, args.mode) if mech.loops is not None else None
    if args.mode is not None and mech.loops is None:
        raise InvalidInputError(
            f"--mode selects a working mode of a closed mechanism; {mech.name} is serial"
        )
    if args.grid is not None:
        coords, n = _grid_coords(args.grid)
        n = n or (args.n or 121 if mech.loops is not None else 41)
        res = singularity_report.grid_map(
            mech, coords, n, task=task, measure=measure, wide=args.wide, mode=mode or 0, phi=phi
        )
        res["plot"] = str(_plot_grid(mech, res, args.plot)) if args.plot else None
        emit(args, res, _grid_text(mech, res))
        return 0
    if args.plot:
        raise InvalidInputError("--plot needs --grid")
    if args.q is not None:
        if mode is not None:
            raise InvalidInputError("--mode selects a working mode of --pose or --grid, not --q")
        n = mech.loops.dof if mech.loops is not None else mech.nq
        rep = singularity_report.at_inputs(mech, parse_vector(args.q, "q", n))
    else:
        value, target_coords = target_from_args(mech, args)
        rep = singularity_report.at_target(mech, value, target_coords, mode=mode)
    emit(args, rep, "\n".join([f"{mech.name}: tolerance {rep['tol']:g}", *_mode_lines(rep)]))
    return 0


def _grid_text(mech: Mechanism, res: dict[str, Any]) -> str:
    if mech.loops is None:
        i, j = res["coordinates"]
        return (
            f"{res['measure']} ({res['task']}) over q{i} x q{j}: min {res['min']:.4g}, "
            f"max {res['max']:.4g}"
        ) + (f"\nwrote {res['plot']}" if res["plot"] else "")
    return (
        f"{mech.name}: det A / det B map, mode {res['mode']}: reachable area "
        f"{res['reachable_area']:.4g} m^2, {res['type2_sign_changes']} type-2 crossings along "
        f"rows"
    ) + (f"\nwrote {res['plot']}" if res["plot"] else "")


def _plot_grid(mech: Mechanism, res: dict[str, Any], path: Path) -> Path:
    if mech.loops is not None:
        from rcm_pin.analysis.maps import plot_singularity_map

        return plot_singularity_map(res, path)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 5))
    im = ax.pcolormesh(res["x"], res["y"], res["values"], shading="auto", cmap="viridis")
    fig.colorbar(im, ax=ax, label=f"{res['measure']} ({res['task']} Jacobian)")
    i, j = res["coordinates"]
    ax.set(xlabel=f"q{i}", ylabel=f"q{j}", title=f"{mech.name}: {res['measure']}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def cmd_workspace(args: argparse.Namespace) -> int:
    """``rcm-pin workspace``."""
    from rcm_pin.analysis import workspace as ws
    from rcm_pin.analysis.workspace import workspace_model

    if args.plot:
        output_path(args.plot, "--plot")
    mech = load_mechanism(args)
    supported(mech, args, closed=("--phi", "--phi-range", "--n"))
    uses = workspace_model(mech).options
    for key in ("samples", "n", "phi", "phi_range"):
        if getattr(args, key) is not None and key not in uses:
            valid = ", ".join("--" + o.replace("_", "-") for o in uses) or "no options"
            raise InvalidInputError(
                f"--{key.replace('_', '-')} does not apply to the workspace of {mech.name}; "
                f"valid: {valid}"
            )
    phi = 0.0 if args.phi is None else args.phi
    if not np.isfinite(phi):
        raise InvalidInputError(f"--phi {phi}; valid: a finite angle [rad]")
    if args.samples is not None and not ws.MIN_SAMPLES <= args.samples <= ws.MAX_SAMPLES:
        raise InvalidInputError(
            f"--samples {args.samples}; valid: {ws.MIN_SAMPLES}..{ws.MAX_SAMPLES}"
        )
    options: dict[str, Any] = {"phi": phi, "n": 121 if args.n is None else args.n}
    if args.phi_range:
        lo, hi = parse_vector(args.phi_range, "phi-range", 2)
        options["phi_range"] = (float(lo), float(hi))
    s = ws.summary(mech, args.samples, **options)
    s["plot"] = None
    if args.plot:
        n_plot = min(args.samples or 200_000, 200_000)
        s["plot"] = str(ws.plot(mech, args.plot, n_plot, **options))
    lines = [f"{mech.name} workspace"]
    lines += [
        f"  {k}: {v:.6g}" if isinstance(v, float) else f"  {k}: {v}"
        for k, v in s.items()
        if k not in ("mechanism", "plot") and not isinstance(v, (dict, list, np.ndarray))
    ]
    emit(args, s, "\n".join(lines) + (f"\nwrote {s['plot']}" if s["plot"] else ""))
    return 0


def cmd_accuracy(args: argparse.Namespace) -> int:
    """``rcm-pin accuracy``: the family's table, or every joint placement's sensitivity."""
    from rcm_pin.analysis.accuracy import accuracy_model
    from rcm_pin.analysis.capabilities import reference_poses

    mech = load_mechanism(args)
    q = parse_vector(args.q, "q", mech.nq) if args.q else reference_poses(mech).accuracy(mech)
    rep = accuracy_model(mech).report(mech, q)
    emit(args, rep.to_dict(), "\n".join(rep.lines()))
    return 0
