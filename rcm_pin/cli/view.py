"""``rcm-pin view``: show a mechanism in Meshcat, export static HTML or a PNG."""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rcm_pin.cli._common import add_common, emit, fmt, parse_vector, parse_xacro_args
from rcm_pin.errors import InvalidInputError
from rcm_pin.mechanism import load

if TYPE_CHECKING:
    from rcm_pin.viz_base import MeshcatScene


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``view`` subcommand."""
    p = sub.add_parser(
        "view",
        help="Meshcat view of a mechanism (live on 127.0.0.1, or --html / --png files)",
    )
    add_common(p)
    p.add_argument(
        "--q",
        help="q1,...,qn [rad, m] (default: zeros clipped to the limits); closed loops "
        "(planar_3rrr, five_bar): drive angles, passive joints solved (default: home pose)",
    )
    p.add_argument(
        "--assembly", type=int, default=0, help="closed loops: assembly mode index (default 0)"
    )
    p.add_argument(
        "--traj",
        type=Path,
        help="animate the rows of a .npy / .csv file of q (closed loops: rows of drives)",
    )
    p.add_argument("--dt", type=float, default=0.05, help="time between --traj rows [s]")
    p.add_argument("--html", type=Path, help="write a self-contained static HTML page")
    p.add_argument("--png", type=Path, help="write a PNG (headless Chromium, else matplotlib)")
    p.add_argument(
        "--seconds",
        type=float,
        default=None,
        help="live mode: serve this long, then exit (default: until Ctrl-C)",
    )
    p.set_defaults(func=cmd_view)


def _load_traj(path: Path, nq: int) -> np.ndarray:
    if not path.exists():
        raise InvalidInputError(f"--traj {path} does not exist; valid: a .npy or .csv file")
    try:
        raw = np.load(path) if path.suffix == ".npy" else np.loadtxt(path, delimiter=",", ndmin=2)
    except ValueError as exc:
        raise InvalidInputError(f"--traj {path} is not numeric: {exc}") from None
    arr = np.atleast_2d(np.asarray(raw, dtype=float))
    if arr.ndim != 2 or arr.shape[1] != nq:
        raise InvalidInputError(f"--traj has shape {arr.shape}; valid: (N, {nq}) rows of q")
    return arr


def cmd_view(args: argparse.Namespace) -> int:
    from rcm_pin.cli.analysis import is_closed
    from rcm_pin.viz import Viewer
    from rcm_pin.viz_snapshot import snapshot

    if is_closed(args.name):
        return _closed_view(args)
    if args.assembly != 0:
        raise InvalidInputError(
            f"--assembly applies to closed mechanisms only; {args.name} is serial"
        )
    mech = load(args.name, **parse_xacro_args(args.arg))
    if args.q is not None:
        q = parse_vector(args.q, "q", mech.nq)
    else:
        q = np.clip(np.zeros(mech.nq), mech.lower, mech.upper)
    traj = _load_traj(args.traj, mech.nq) if args.traj is not None else None
    live = args.html is None and args.png is None
    payload: dict[str, object] = {"mechanism": mech.name, "q": q, "html": None, "png": None}
    with Viewer(mech, server=live, snapshot_style=not live) as viewer:
        if mech.rcm_frame_id >= 0:
            viewer.show_rcm()
            viewer.show_tool_axis()
        viewer.display(q)
        viewer.fit_camera()
        if traj is not None:
            viewer.animate(traj, args.dt, repetitions=1 if not live else 1000)
        if _publish(viewer, args, payload, mech.name):
            return 0
    if args.png is not None:
        payload["png"] = str(args.png)
        payload["png_method"] = snapshot(mech, q, args.png)
    lines = [f"{mech.name} at q = {fmt(q)}"]
    lines += [f"wrote {payload[k]}" for k in ("html", "png") if payload[k]]
    emit(args, payload, "\n".join(lines))
    return 0


def _closed_view(args: argparse.Namespace) -> int:
    from rcm_pin.closed_loop import direct_position_path, load_closed
    from rcm_pin.viz_closed import ClosedViewer, snapshot_closed

    xargs = parse_xacro_args(args.arg)
    mech = load_closed(args.name, **xargs)
    live = args.html is None and args.png is None
    with ClosedViewer(mech, xacro_args=xargs, server=live, snapshot_style=not live) as viewer:
        if args.q is not None:
            viewer.display(parse_vector(args.q, "q", mech.dof), args.assembly)
        elif args.assembly != 0:
            raise InvalidInputError("--assembly needs --q (drive angles)")
        viewer.fit_camera()
        q_full = viewer.q.copy()
        payload: dict[str, object] = {
            "mechanism": mech.name,
            "q": viewer.q_drives,
            "q_full": q_full,
            "joint_names": list(mech.model.names[1:]),
            "assembly": viewer.assembly,
            "closure_gap": viewer.closure_gap(),
            "html": None,
            "png": None,
        }
        if args.traj is not None:
            drives = _load_traj(args.traj, mech.dof)
            path = direct_position_path(mech, drives, q_full)
            viewer.animate(path, args.dt, repetitions=1 if not live else 1000)
        if _publish(viewer, args, payload, mech.name):
            return 0
        if args.png is not None:
            viewer.display_full(q_full)
            payload["png_method"] = snapshot_closed(viewer, args.png)
            payload["png"] = str(args.png)
    lines = [
        f"{mech.name} at drives {fmt(viewer.q_drives)} ({viewer.assembly}), "
        f"closure gap {payload['closure_gap']:.1e} m"
    ]
    lines += [f"wrote {payload[k]}" for k in ("html", "png") if payload[k]]
    emit(args, payload, "\n".join(lines))
    return 0


def _serve(seconds: float | None) -> None:
    end = None if seconds is None else time.monotonic() + seconds
    try:
        while end is None or time.monotonic() < end:
            time.sleep(0.2)
    except KeyboardInterrupt:
        pass


def _publish(viewer: MeshcatScene, args: argparse.Namespace, payload: dict, name: str) -> bool:
    """Write ``--html``; with a live viewer print its address and serve until stopped.

    Returns:
        True when it served a live viewer (the command is done).
    """
    if args.html is not None:
        payload["html"] = str(viewer.save_html(args.html))
    if viewer.url is None:
        return False
    payload["url"] = viewer.url
    emit(args, payload, f"Meshcat viewer of {name} at {viewer.url} (Ctrl-C stops)")
    _serve(args.seconds)
    return True
