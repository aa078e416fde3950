"""``rcm-pin export NAME|PATH --mjcf OUT.xml``: the mechanism as a MuJoCo MJCF file.

Bodies, inertias, joints (ranges, damping), mimic transmissions as joint equalities, loop
closures as ``connect`` / ``weld`` equalities between sites, drives as motors, the tool,
RCM and output frames as sites, and solver settings chosen so that the predicted closure
drift stays under ``--drift-tol`` (``docs/mujoco.md``). Writing needs no MuJoCo;
``--check`` loads the file in MuJoCo (the ``mujoco`` extra) and reports its rigid-limit
error against rcm-pin at the home configuration at rest under seeded joint torques.
"""

from __future__ import annotations

import argparse
import math
import warnings
from pathlib import Path

import numpy as np

from rcm_pin.cli._common import add_common, emit, load_mechanism, output_path


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"{text!r}; valid: a positive number")
    return value


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``export`` subcommand."""
    p = sub.add_parser(
        "export", help="write the mechanism as a MuJoCo MJCF file", description=__doc__
    )
    add_common(p)
    p.add_argument("--mjcf", required=True, metavar="OUT.xml", help="the MJCF file to write")
    p.add_argument(
        "--timestep", type=_positive, metavar="DT", help="timestep [s] (default: chosen)"
    )
    p.add_argument(
        "--drift-tol",
        type=_positive,
        default=1e-6,
        metavar="TOL",
        help="largest predicted closure drift [m or rad] (default 1e-6)",
    )
    p.add_argument("--check", action="store_true", help="load in MuJoCo and compare (mujoco extra)")
    p.set_defaults(func=cmd_export)


def cmd_export(args: argparse.Namespace) -> int:
    """``rcm-pin export``."""
    from rcm_pin.export.mjcf import to_mjcf

    mech = load_mechanism(args)
    path = output_path(Path(args.mjcf), "--mjcf")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        export = to_mjcf(mech, path, timestep=args.timestep, drift_tol=args.drift_tol)
    notes = [str(w.message) for w in caught]
    if not args.json:
        for w in caught:
            warnings.warn(w.message, stacklevel=1)  # the same category, one line each
    payload = {**export.summary(), "warnings": notes}
    s = export.settings
    lines = [
        f"wrote {path} ({mech.name}): timestep {s.timestep:g} s, solref {s.solref[0]:g} "
        f"{s.solref[1]:g}, predicted drift {s.predicted_drift:.2g} (tolerance {s.drift_tol:g})"
    ]
    if args.check:
        from rcm_pin.export.check import load_mujoco, rigid_limit_error

        exported = export.mechanism
        mj = load_mujoco(path, exported)
        q = exported.to_pin(exported.home)
        tau = np.random.default_rng(0).normal(size=exported.model.nv)  # seeded [N·m]
        error = rigid_limit_error(mj, exported, q, np.zeros(exported.model.nv), tau)
        payload["rigid_limit_error"] = error
        lines.append(f"MuJoCo loads it; rigid-limit error at home {error:.1e} (relative q̈)")
    emit(args, payload, "\n".join(lines))
    return 0
