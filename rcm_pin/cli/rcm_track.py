"""``rcm-pin rcm-track NAME --path circle|spiral|arc``: the surgical task through a trocar.

For an arm (panda, ur5) the tool shaft (z axis of its tool frame, extended by
:data:`rcm_pin.studies.rcm_comparison.TOOL_LENGTH`) is kept through the trocar by the
programmable RCM (one QP per control step at ``--rate``); the default trocar is the one
chosen by reachability and manipulability (:func:`rcm_pin.studies.rcm_comparison.choose_trocar`).
For a mechanism with a mechanical RCM (rcm_bevel, ..., or a file loaded with
``--rcm-frame``) the trocar is its remote centre, the shaft the ``--rcm-axis`` of
``--rcm-axis-frame`` (default: the tool frame's z) and each sample is solved by its
analytic inverse kinematics, else by least squares from the previous sample. ``NAME`` is a
catalogue name or a .urdf / .xacro path (never looked up by its stem), loaded with
``--tool-frame`` (the arm's shaft frame) and the other frame options of every command.
``rcm_error_max`` is the largest distance of the trocar from the shaft line over the
returned samples, recomputed from ``q`` by Pinocchio forward kinematics; ``tip_error_max``
the largest tip tracking error.
"""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

from rcm_pin.cli._common import add_common, emit, load_mechanism, parse_vector
from rcm_pin.studies.surgical_paths import DURATIONS, PATHS


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``rcm-track``."""
    p = sub.add_parser(
        "rcm-track", help="tool tip along a surgical path with the shaft through a trocar"
    )
    add_common(p)  # NAME (a name or a path), --arg, --tool-frame (arms: the shaft), --rcm-*
    p.add_argument("--path", required=True, choices=PATHS, help="tip path inside the cone")
    p.add_argument("--trocar", help="arms: trocar point x,y,z [m] (default: chosen)")
    p.add_argument("--tool-axis", default="z", choices=("x", "y", "z"), help="shaft axis (z)")
    p.add_argument("--rate", type=float, default=1000.0, help="control rate [Hz] (1000)")
    p.add_argument(
        "--duration", type=float, help="stop after this time [s] (default: the whole path)"
    )
    p.add_argument("--method", default="qp", choices=("qp", "pink"), help="arms' QP route")
    p.set_defaults(func=cmd_rcm_track)


def payload(track: Any) -> dict[str, Any]:
    """The JSON document of a :class:`~rcm_pin.studies.rcm_comparison.RcmTrack`."""
    from rcm_pin.studies.rcm_metrics import errors

    s = track.setup
    rcm, tip_err = errors(track)
    return {
        "name": s.mech.name,
        "path": track.path,
        "rcm": "mechanical" if s.mechanical else "programmable",
        "joint_names": list(s.mech.joint_names),
        "q": track.q,
        "t": track.t,
        "p_ref": track.p_ref,
        "tool_frame": s.tool_frame,
        "tool_axis": s.tool.axis_name,
        "tip_offset": s.tool.tip_offset,
        "tip_frame": str(s.mech.model.frames[s.tool.tip_frame].name),
        "trocar": list(s.tool.trocar),
        "rcm_error_max": float(rcm.max()),
        "rcm_error_rms": float(np.sqrt(np.mean(rcm**2))),
        "tip_error_max": float(tip_err.max()),
        "step_time_median": float(np.median(track.step_time)) if track.step_time.size else 0.0,
    }


def cmd_rcm_track(args: argparse.Namespace) -> int:
    from rcm_pin.studies.rcm_comparison import make_setup, run

    trocar = None if args.trocar is None else parse_vector(args.trocar, "trocar", 3)
    setup = make_setup(load_mechanism(args), trocar, axis=args.tool_axis)
    track = run(setup, args.path, rate=args.rate, duration=args.duration, method=args.method)
    doc = payload(track)
    text = (
        f"{doc['name']} ({doc['rcm']} RCM) {args.path}: {len(track.t)} samples over "
        f"{track.t[-1]:.3f} s of {DURATIONS[args.path]:g} s, trocar {np.round(doc['trocar'], 4)}, "
        f"shaft {doc['tool_frame']}.{doc['tool_axis']}\n"
        f"  RCM error max {doc['rcm_error_max']:.3e} m (RMS {doc['rcm_error_rms']:.3e} m), "
        f"tip error max {doc['tip_error_max']:.3e} m, "
        f"median step {1e3 * doc['step_time_median']:.3f} ms"
    )
    emit(args, doc, text)
    return 0


__all__ = ["cmd_rcm_track", "payload", "register"]
