"""``rcm-pin vibrations``: natural frequencies of a closed mechanism with its drives as springs.

The pose is the output target of ``rcm-pin ik`` (``--pose`` with the output coordinates,
or ``--rpy`` / ``--rotation`` for a rotation output); ``--mode`` picks the working mode
(default: the one ``ik`` lists first); or ``--q`` the drive values and ``--mode`` the
assembly mode (default: the one ``fk --all`` lists first; no output frame needed);
``--stiffness`` is c for every drive or one value
per drive [N·m/rad for a revolute drive, N/m for a prismatic one]. The frequencies solve
det(C − ω² M_q) = 0 (:mod:`rcm_pin.dynamics.vibrations`); ``--check`` adds the second route
(finite-difference linearisation of the constrained forward dynamics).
"""

from __future__ import annotations

import argparse

import numpy as np

from rcm_pin.cli._common import (
    add_common,
    emit,
    fmt,
    load_mechanism,
    parse_vector,
    target_from_args,
)
from rcm_pin.errors import InvalidInputError
from rcm_pin.model.mechanism import Mechanism


def _assembly(mech: Mechanism, args: argparse.Namespace) -> tuple[np.ndarray, str]:
    """(configuration, label) of the assembly mode ``--mode`` (default: the first that
    ``fk --all`` lists) of the drive values ``--q``."""
    from rcm_pin.analysis.position import forward

    if any(getattr(args, k, None) for k in ("pose", "rpy", "rotation")):
        raise InvalidInputError("--q conflicts with --pose / --rpy / --rotation; valid: one")
    sols = forward(mech, parse_vector(args.q, "q"), all_modes=True).solutions
    found = {s.mode: s.q for s in sols}
    mode = args.mode or sols[0].mode
    if mode not in found:
        raise InvalidInputError(
            f"mode {mode!r} is not an assembly mode of {mech.name} at these drives; valid: "
            + ", ".join(found)
        )
    return found[mode], mode


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``vibrations`` subcommand."""
    p = sub.add_parser(
        "vibrations", help="natural frequencies with the drives as springs", description=__doc__
    )
    add_common(p)
    p.add_argument("--pose", help="output coordinates of the closed mechanism (e.g. x,y,phi)")
    p.add_argument("--rpy", help="alpha,beta,gamma [rad]: a rotation output's target")
    p.add_argument("--rotation", help="r11,...,r33: a rotation output's target")
    p.add_argument(
        "--q", metavar="DRIVES", help="drive values instead of a pose (no output needed)"
    )
    p.add_argument(
        "--mode", metavar="LABEL", help="working mode (default: ik's first; --q: assembly mode)"
    )
    p.add_argument(
        "--stiffness",
        required=True,
        help="drive stiffness c, one value or one per drive [N·m/rad, N/m]",
    )
    p.add_argument("--check", action="store_true", help="add the linearised-dynamics route")
    p.set_defaults(func=cmd_vibrations)


def cmd_vibrations(args: argparse.Namespace) -> int:
    """``rcm-pin vibrations``."""
    from rcm_pin.dynamics.vibrations import linearised_frequencies, natural_frequencies
    from rcm_pin.studies.working_mode import configuration_at

    mech = load_mechanism(args)
    if mech.loops is None:
        raise InvalidInputError(
            f"vibrations needs a closed mechanism (drives as springs); {mech.name} is serial"
        )
    c = parse_vector(args.stiffness, "stiffness")
    if args.q is not None:
        q, mode = _assembly(mech, args)
    else:
        value, coords = target_from_args(mech, args)
        q, mode = configuration_at(mech, value, args.mode, coords)
    vib = natural_frequencies(mech, q, c)
    payload = {"mechanism": mech.name, "mode": mode, **vib.to_json()}
    lines = [
        f"{mech.name} ({mode}), drives {', '.join(vib.drives)}, c = {fmt(vib.stiffness)}",
        f"frequencies [rad/s] {fmt(vib.frequencies)}  [Hz] {fmt(vib.frequencies_hz)}",
    ]
    for j in range(len(vib.drives)):
        lines.append(f"mode {j + 1}: {fmt(vib.modes[:, j])}")
    if args.check:
        lin = linearised_frequencies(mech, q, vib.stiffness)
        rel = float(np.max(np.abs(lin / vib.frequencies - 1.0)))
        payload["linearised_frequencies"] = lin.tolist()
        payload["max_relative_difference"] = rel
        lines.append(f"linearised dynamics [rad/s] {fmt(lin)}  (max rel. diff. {rel:.1e})")
    emit(args, payload, "\n".join(lines))
    return 0
