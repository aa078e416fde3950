"""``rcm-pin view``: show any mechanism in Meshcat, export static HTML or a PNG.

One path for every mechanism: ``--q`` is the input vector (``mech.input_names``: the
coordinates of a serial mechanism, the drive values of a closed one); the
:class:`rcm_pin.viz.Viewer` closes the loops (:meth:`~rcm_pin.viz.Viewer.display_inputs`)
and says when ``--assembly`` has no meaning.
"""

from __future__ import annotations

import argparse
import contextlib
import signal
import sys
import time
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from rcm_pin.cli._common import (
    add_common,
    emit,
    fmt,
    load_mechanism,
    output_path,
    parse_vector,
)
from rcm_pin.errors import InvalidInputError

if TYPE_CHECKING:
    from rcm_pin.viz.viewer import Viewer


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``view`` subcommand."""
    p = sub.add_parser(
        "view",
        help="Meshcat view of a mechanism (live on 127.0.0.1, or --html / --png files)",
    )
    add_common(p)
    p.add_argument(
        "--q",
        help="the inputs [rad, m]: q1,...,qn of a serial mechanism, the drive values of a "
        "closed one (passive joints solved); default: the home configuration",
    )
    p.add_argument(
        "--assembly",
        type=int,
        default=0,
        help="mechanisms with loops: assembly mode index for the inputs (default 0)",
    )
    p.add_argument(
        "--traj",
        type=Path,
        help="animate the rows of a .npy / .csv file of inputs (as --q)",
    )
    p.add_argument("--dt", type=float, default=0.05, help="time between --traj rows [s]")
    p.add_argument("--html", type=Path, help="write a self-contained static HTML page")
    p.add_argument("--png", type=Path, help="write a PNG (headless Chromium, else matplotlib)")
    p.add_argument(
        "--explain",
        action="store_true",
        help="also draw a base plate, x/y/z arrows at the output (tool) frame and A, a ring "
        "on every driven joint and a rod along every joint axis (docs/visualisation.md)",
    )
    p.add_argument(
        "--colors",
        choices=("auto", "urdf", "bodies"),
        default="auto",
        help="body colours: the URDF's materials, else one per body (auto, the default); "
        "the URDF's only (urdf); one per body always (bodies)",
    )
    p.add_argument(
        "--host",
        default="127.0.0.1",
        help="live mode: the address the viewer listens on (default 127.0.0.1, this machine "
        "only; e.g. 0.0.0.0 opens it to the network)",
    )
    p.add_argument(
        "--seconds",
        type=float,
        default=None,
        help="live mode: serve this long, then exit (default: until Ctrl-C)",
    )
    p.set_defaults(func=cmd_view)


def _load_traj(path: Path, n: int) -> np.ndarray:
    if not path.exists():
        raise InvalidInputError(f"--traj {path} does not exist; valid: a .npy or .csv file")
    try:
        raw = np.load(path) if path.suffix == ".npy" else np.loadtxt(path, delimiter=",", ndmin=2)
    except ValueError as exc:
        raise InvalidInputError(f"--traj {path} is not numeric: {exc}") from None
    arr = np.atleast_2d(np.asarray(raw, dtype=float))
    if arr.ndim != 2 or arr.shape[1] != n:
        raise InvalidInputError(f"--traj has shape {arr.shape}; valid: (N, {n}) rows of q")
    return arr


@contextlib.contextmanager
def _mesh_warnings() -> Iterator[list[str]]:
    """Meshes that cannot be drawn, each one line ``rcm-pin: warning: ...`` on stderr and
    kept in the yielded list (the JSON ``warnings``)."""
    from rcm_pin.model.meshes import MissingMeshWarning

    kept: list[str] = []
    shown = warnings.showwarning

    def show(message: Warning | str, category: type[Warning], *rest: Any, **kw: Any) -> None:
        if not issubclass(category, MissingMeshWarning):
            return shown(message, category, *rest, **kw)
        kept.append(str(message))
        print(f"rcm-pin: warning: {message}", file=sys.stderr)

    with warnings.catch_warnings():
        warnings.simplefilter("always", MissingMeshWarning)
        warnings.showwarning = show
        yield kept


def cmd_view(args: argparse.Namespace) -> int:
    """Show the inputs' configuration; write ``--html`` / ``--png`` or serve it live.

    JSON keys: ``mechanism``, ``input_names``, ``q`` (inputs), ``q_full`` (coordinates),
    ``coordinates``, ``joint_names``, ``assembly`` (label), ``closure_gap`` [m], ``html``,
    ``png``, ``png_method`` (with ``--png``), ``url`` (live), ``warnings`` (meshes not
    drawn, each naming the file; also printed on stderr).
    """
    with _mesh_warnings() as kept:
        return _view(args, kept)


def _view(args: argparse.Namespace, kept: list[str]) -> int:
    from rcm_pin.viz.explain import SceneStyle
    from rcm_pin.viz.snapshot import snapshot
    from rcm_pin.viz.viewer import Viewer

    for option, path in (("--html", args.html), ("--png", args.png)):
        if path is not None:
            output_path(path, option)
    mech = load_mechanism(args)
    n_inputs = len(mech.input_names)
    inputs = parse_vector(args.q, "q", n_inputs) if args.q is not None else None
    traj = _load_traj(args.traj, n_inputs) if args.traj is not None else None
    live = args.html is None and args.png is None
    colors = SceneStyle(args.colors)
    style = SceneStyle.explained(args.colors) if args.explain else colors
    with (
        _stopped_by_sigterm(),
        Viewer(mech, server=live, snapshot_style=not live, host=args.host, style=colors) as viewer,
    ):
        if inputs is not None or args.assembly != 0:
            viewer.display_inputs(viewer.inputs if inputs is None else inputs, args.assembly)
        viewer.show_style(style)  # sized at the configuration shown
        viewer.fit_camera()
        q = viewer.q.copy()
        payload: dict[str, Any] = {
            "mechanism": mech.name,
            "input_names": list(mech.input_names),
            "q": viewer.inputs,
            "q_full": q,
            "coordinates": list(mech.coordinate_names),
            "joint_names": list(mech.joint_names),
            "assembly": viewer.assembly,
            "closure_gap": viewer.closure_gap(),
            "html": None,
            "png": None,
            "warnings": kept,
        }
        if traj is not None:
            viewer.animate(viewer.input_path(traj), args.dt, repetitions=1000 if live else 1)
        if _publish(viewer, args, payload):
            return 0
    if args.png is not None:
        payload["png_method"] = snapshot(mech, q, args.png, style=style)
        payload["png"] = str(args.png)
    lines = [
        f"{mech.name} at {', '.join(mech.input_names)} = {fmt(payload['q'])} "
        f"({payload['assembly']}), closure gap {payload['closure_gap']:.1e} m"
    ]
    lines += [f"wrote {payload[k]}" for k in ("html", "png") if payload[k]]
    emit(args, payload, "\n".join(lines))
    return 0


@contextlib.contextmanager
def _stopped_by_sigterm() -> Iterator[None]:
    """SIGTERM ends the command through SystemExit (status 143), so that the viewer's
    server is stopped on the way out (SIGINT already does, through KeyboardInterrupt)."""

    def stop(signum: int, frame: object) -> None:
        raise SystemExit(128 + signum)

    try:
        previous = signal.signal(signal.SIGTERM, stop)
    except ValueError:  # not the main thread: leave the handler alone
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def _serve(seconds: float | None) -> None:
    end = None if seconds is None else time.monotonic() + seconds
    try:
        while end is None or time.monotonic() < end:
            time.sleep(0.2)
    except KeyboardInterrupt:
        pass


def _publish(viewer: Viewer, args: argparse.Namespace, payload: dict[str, Any]) -> bool:
    """Write ``--html``; with a live viewer print its address and serve until stopped.

    Returns:
        True when it served a live viewer (the command is done).
    """
    if args.html is not None:
        payload["html"] = str(viewer.save_html(args.html))
    if viewer.url is None:
        return False
    payload["url"] = viewer.url
    emit(args, payload, f"Meshcat viewer of {viewer.mech.name} at {viewer.url} (Ctrl-C stops)")
    _serve(args.seconds)
    return True
