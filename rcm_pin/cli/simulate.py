"""``rcm-pin simulate``: the one computed-torque law on the one simulate, any mechanism.

A run is a scenario of the mechanism's family (``--scenario``; ``rcm-pin simulate NAME
--list`` shows them) with options that override its gains, duration, limits and drive
switching. ``--compare`` runs a mechanism with extra drives three ways: main drives
without limits, main drives with the limit, and switching (paper 004's study).

The plant and the controller's model are both the mechanism built with the ``--arg``
xacro arguments (e.g. ``rcm_bevel --arg q3_upper=0.3`` for paper 000's scenario). A run
that leaves the joint range stops with a :class:`~rcm_pin.errors.JointLimitError` (exit
status 2) naming the time [s], the joint and its limit; ``--allow-outside-limits``
continues and lists the excursions in the output (``outside_limits``).
"""

from __future__ import annotations

import argparse
from dataclasses import replace
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
from rcm_pin.errors import InvalidInputError, require

if TYPE_CHECKING:  # the command functions import the control layer (not needed for --help)
    from rcm_pin.control.result import SimulationResult
    from rcm_pin.control.scenario import Scenario
    from rcm_pin.model.mechanism import Mechanism


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``simulate`` subcommand."""
    p = sub.add_parser(
        "simulate", help="computed-torque tracking on the Pinocchio dynamics", description=__doc__
    )
    add_common(p)
    p.add_argument(
        "--scenario",
        "--trajectory",
        dest="scenario",
        help="scenario name (default: the family's first; --list shows them)",
    )
    p.add_argument("--list", action="store_true", help="list the scenarios and exit")
    gains = p.add_mutually_exclusive_group()
    gains.add_argument("--gains", help="Kn,Kc [1/s^2, 1/s]")
    gains.add_argument("--tau-zeta", help="tau,zeta of tau^2 e'' + 2 zeta tau e' + e = 0 [s, -]")
    p.add_argument(
        "--duration",
        type=float,
        help="simulated time [s]; beyond 60 s a 1 s probe estimates the wall time and a run "
        "over 600 s is refused",
    )
    p.add_argument("--space", choices=("task", "joint"), default="task")
    p.add_argument("--no-feedforward", action="store_true", help="drop the reference acceleration")
    p.add_argument("--printed-sign", action="store_true", help="paper 000's printed Kn(x - x_t)")
    p.add_argument("--no-limits", action="store_true", help="ignore the drive effort limits")
    p.add_argument("--tau-max", type=float, help="one effort limit for every drive [N*m, N]")
    p.add_argument(
        "--switching",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="drive switching to the extra drives (mechanisms that have them)",
    )
    p.add_argument(
        "--compare",
        action="store_true",
        help="extra drives: main unlimited, main limited, switching",
    )
    p.add_argument("--no-gravity", action="store_true", help="simulate without gravity")
    p.add_argument(
        "--allow-outside-limits",
        action="store_true",
        help="continue when a joint leaves its range (recorded in the output) instead of stopping",
    )
    p.add_argument(
        "--backend",
        default="python",
        help="right-hand side: python (default, every mechanism) or compiled (one compiled "
        "CasADi function; serial with a square position task, or closed without drive "
        "switching; the trajectory to the tolerances)",
    )
    p.add_argument("--plot", type=Path, metavar="DIR", help="write the figures into DIR")
    p.add_argument(
        "--engine",
        choices=("pinocchio", "mujoco"),
        default="pinocchio",
        help="mujoco: also run it on the MJCF export (docs/mujoco.md; the mujoco extra)",
    )
    p.set_defaults(func=cmd_simulate)


def _scenario(mech: Mechanism, args: argparse.Namespace) -> tuple[str, Scenario]:
    from rcm_pin.control.computed_torque import Gains
    from rcm_pin.control.scenario import scenarios
    from rcm_pin.control.simulate import MIN_DURATION

    table = scenarios(mech)
    name = args.scenario or next(iter(table))
    if name not in table:
        raise InvalidInputError(
            f"unknown scenario {name!r} for {mech.name}; valid: {', '.join(table)}"
        )
    sc = table[name]
    if args.gains:
        kn, kc = parse_vector(args.gains, "gains", 2)
        sc = replace(sc, gains=Gains(float(kn), float(kc)))
    if args.tau_zeta:
        tau, zeta = parse_vector(args.tau_zeta, "tau-zeta", 2)
        sc = replace(sc, gains=Gains.from_tau_zeta(float(tau), float(zeta)))
    if args.duration is not None:
        if not (np.isfinite(args.duration) and args.duration >= MIN_DURATION):
            raise InvalidInputError(
                f"--duration {args.duration} is invalid; valid: >= {MIN_DURATION:g} [s]"
            )
        sc = replace(sc, duration=args.duration)
    if args.tau_max is not None:
        if not (np.isfinite(args.tau_max) and args.tau_max > 0):
            raise InvalidInputError(f"--tau-max {args.tau_max} is invalid; valid: > 0 [N*m, N]")
        sc = replace(sc, limit=args.tau_max)
    if args.no_limits:
        sc = replace(sc, limit=None, use_limits=False)
    extra = mech.loops is not None and bool(mech.loops.extra_drives)
    if (args.switching or args.compare) and not extra:
        raise InvalidInputError(f"--switching / --compare need extra drives; {mech.name} has none")
    if args.switching is False:
        sc = replace(sc, switching=None)
    elif args.switching and sc.switching is None:
        sc = replace(sc, switching=0.2)
    return name, sc


#: Simulated time [s] up to which a run starts without a cost estimate.
FREE_DURATION = 60.0
#: Simulated time [s] of the probe that measures the cost of a longer run.
PROBE_DURATION = 1.0
#: Longest estimated run [s of wall time] that ``simulate`` starts.
MAX_SECONDS = 600.0


def check_cost(mech: Mechanism, sc: Scenario, **options: Any) -> None:
    """Refuse a run longer than :data:`FREE_DURATION` whose wall time, estimated from a
    :data:`PROBE_DURATION` probe of the same scenario, exceeds :data:`MAX_SECONDS`.

    Raises:
        InvalidInputError: the estimate is over the budget (message: estimate, bound).
    """
    from rcm_pin.control.scenario import run

    if sc.duration <= FREE_DURATION:
        return
    probe = run(mech, replace(sc, duration=PROBE_DURATION), **options)
    # the integration's own wall time (the set-up is paid once, not per simulated second)
    rate = probe.wall_time / max(float(probe.t[-1]), 1e-3)
    if rate * sc.duration > MAX_SECONDS:
        raise InvalidInputError(
            f"--duration {sc.duration:g} s would take about {rate * sc.duration:.3g} s "
            f"({rate:.3g} s per simulated second, measured on a {PROBE_DURATION:g} s probe); "
            f"valid: at most about {MAX_SECONDS / rate:.4g} s of simulated time for this run "
            f"(a {MAX_SECONDS:g} s budget)"
        )


def _summary(mech: Mechanism, label: str, res: SimulationResult, sc: Scenario) -> dict[str, Any]:
    from rcm_pin.control.linear import error_response

    out = {"label": label, **res.summary()}
    after = res.t >= 5.0 * sc.gains.tau  # the error's transient: five time constants
    out["transient_time"] = 5.0 * sc.gains.tau
    out["max_error_after_transient"] = (
        float(np.max(np.abs(res.error[after]))) if after.any() else None
    )
    if sc.offset and mech.loops is not None:  # the linear error dynamics from the start error
        e = res.x - res.x_ref
        expected = error_response(
            res.t, sc.gains.tau, sc.gains.zeta, e[0], (res.xd - res.xd_ref)[0]
        )
        out["max_deviation_from_error_dynamics"] = float(np.max(np.abs(e - expected)))
    if mech.loops is not None and mech.loops.extra_drives:
        out["time_on_extras"] = float(np.sum(np.diff(res.t) * res.alternate[1:]))
    return out


def cmd_simulate(args: argparse.Namespace) -> int:
    """``rcm-pin simulate``."""
    from rcm_pin.control.scenario import run, scenarios
    from rcm_pin.dynamics.tree import with_gravity

    if args.plot:
        output_path(args.plot, "--plot", directory=True)
    mech = load_mechanism(args)
    if args.list:
        table = scenarios(mech)
        emit(
            args,
            {"mechanism": mech.name, "scenarios": {k: v.description for k, v in table.items()}},
            "\n".join(f"{k}: {v.description}" for k, v in table.items()),
        )
        return 0
    if args.engine == "mujoco":  # before any work: MissingExtraError names the extra
        require("mujoco", "mujoco")
    if args.no_gravity:
        mech = with_gravity(mech, None)
    name, sc = _scenario(mech, args)
    law = {
        "space": args.space,
        "feedforward": not args.no_feedforward,
        "printed_sign": args.printed_sign,
    }
    plans = [(name, sc)]
    if args.compare:
        limit = sc.limit if sc.limit is not None else 0.5
        plans = [
            ("main drives, unlimited", replace(sc, switching=None, limit=None, use_limits=False)),
            (f"main drives, limit {limit:g}", replace(sc, switching=None, limit=limit)),
            (
                f"switching, limit {limit:g}",
                replace(sc, limit=limit, switching=sc.switching or 0.2),
            ),
        ]
    allow, backend = args.allow_outside_limits, args.backend
    for _, s in plans:
        check_cost(mech, s, allow_outside_limits=allow, backend=backend, **law)
    runs = [
        (label, s, run(mech, s, allow_outside_limits=allow, backend=backend, **law))
        for label, s in plans
    ]
    payload: dict[str, Any] = {
        "mechanism": mech.name,
        "scenario": name,
        "description": sc.description,
        "space": args.space,
        "runs": [_summary(mech, lb, r, s) for lb, s, r in runs],
        "figures": [],
    }
    if args.engine == "mujoco":  # the same law on the MJCF export, compared at the samples
        from rcm_pin.export.simulate import simulate_mujoco

        for summary, (_, s, r) in zip(payload["runs"], runs, strict=True):
            summary["mujoco"] = simulate_mujoco(mech, s, compare=r, **law).summary()
    if args.plot:
        payload["figures"] = [str(f) for f in _figures(mech, runs[-1][2], args.plot)]
    lines = [
        f"{mech.name}: scenario {name} ({sc.description}); Kn = {sc.gains.kn:g}, "
        f"Kc = {sc.gains.kc:g}, {args.space} space"
    ]
    for r in payload["runs"]:
        lines.append(
            f"{r['label']}: {r['status']} at {r['duration']:.3f} s; RMS error "
            f"{r['rms_error']:.4g}; peak efforts {fmt(np.array(r['peak_effort']), 4)}; "
            f"max closure residual {r['max_closure_residual']:.1e}"
        )
        lines += [
            f"  outside its range: {o['joint']} passes its {o['side']} limit {o['limit']:.6g} "
            f"at t = {o['time_s']:.4g} s (farthest {o['farthest']:.6g})"
            for o in r["outside_limits"]
        ]
        if "mujoco" in r:
            mj = r["mujoco"]
            lines.append(
                f"  MuJoCo (dt {mj['timestep']:g} s, law held {mj['control_period']:g} s): max "
                f"difference {mj['max_difference_from_pinocchio']:.1e}, max equality residual "
                f"{mj['max_equality_residual']:.1e}"
            )
    lines += [f"wrote {f}" for f in payload["figures"]]
    emit(args, payload, "\n".join(lines))
    return 0


def _figures(mech: Mechanism, res: SimulationResult, out: Path) -> list[Path]:
    """Deviation, phase and efforts (serial); task error and efforts (closed)."""
    from rcm_pin.control.plots import plot_deviation, plot_efforts, plot_phase

    out.mkdir(exist_ok=True)
    figs = [plot_deviation(res, out / "deviation.png"), plot_phase(res, out / "phase.png")]
    if mech.loops is None and mech.nq >= 3:
        figs.append(plot_efforts(res, out / "efforts.png"))
    return figs
