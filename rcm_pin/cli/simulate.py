"""``rcm-pin simulate``: computed-torque tracking of a tool-centre trajectory."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from rcm_pin.cli._common import add_common, emit, fmt, parse_vector, parse_xacro_args
from rcm_pin.errors import InvalidInputError


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``simulate`` subcommand."""
    from rcm_pin.trajectories import TRAJECTORIES

    p = sub.add_parser("simulate", help="computed-torque tracking on the Pinocchio dynamics")
    add_common(p)
    p.add_argument("--trajectory", default="paper000", choices=sorted(TRAJECTORIES))
    gains = p.add_mutually_exclusive_group()
    gains.add_argument("--gains", help="Kn,Kc [1/s^2, 1/s] (default 720,12, paper 000)")
    gains.add_argument("--tau-zeta", help="tau,zeta of tau^2 e'' + 2 zeta tau e' + e = 0 [s, -]")
    p.add_argument("--duration", type=float, default=2.0, help="simulated time [s]")
    p.add_argument("--space", choices=("task", "joint"), default="task")
    p.add_argument("--no-feedforward", action="store_true", help="drop the reference acceleration")
    p.add_argument("--printed-sign", action="store_true", help="paper 000's printed Kn(x - x_t)")
    p.add_argument("--no-limits", action="store_true", help="ignore the URDF drive effort limits")
    p.add_argument("--no-gravity", action="store_true", help="simulate without gravity")
    p.add_argument("--plot", type=Path, metavar="DIR", help="write deviation/phase/effort PNGs")
    p.set_defaults(func=cmd_simulate)


def _gains(args: argparse.Namespace):
    from rcm_pin.control import Gains

    if args.tau_zeta:
        tau, zeta = parse_vector(args.tau_zeta, "tau-zeta", 2)
        return Gains.from_tau_zeta(float(tau), float(zeta))
    kn, kc = parse_vector(args.gains or "720,12", "gains", 2)
    return Gains(float(kn), float(kc))


def cmd_simulate(args: argparse.Namespace) -> int:
    from rcm_pin.control import ComputedTorque, drive_limits
    from rcm_pin.dynamics import with_gravity
    from rcm_pin.mechanism import load
    from rcm_pin.simulation import plot_deviation, plot_efforts, plot_phase, simulate
    from rcm_pin.trajectories import get_trajectory

    if not (np.isfinite(args.duration) and args.duration > 0):
        raise InvalidInputError(f"--duration {args.duration} is invalid; valid: > 0 [s]")
    mech = load(args.name, **parse_xacro_args(args.arg))
    if mech.rcm_frame_id < 0 or mech.nq < 3:
        raise InvalidInputError(f"simulate needs an RCM mechanism; {args.name} is not one")
    if args.no_gravity:
        mech = with_gravity(mech, None)
    ctrl = ComputedTorque(
        mech,
        get_trajectory(args.trajectory),
        _gains(args),
        space=args.space,
        feedforward=not args.no_feedforward,
        printed_sign=args.printed_sign,
        limits=None if args.no_limits else drive_limits(mech),
    )
    result = simulate(
        mech,
        ctrl,
        args.duration,
        samples=int(200 * args.duration) + 1,
        progress=not args.json and args.duration >= 2.0,
    )
    payload = {"trajectory": args.trajectory, "space": args.space, **result.summary()}
    if args.plot:
        args.plot.mkdir(parents=True, exist_ok=True)
        payload["figures"] = [
            str(plot_deviation(result, args.plot / "deviation_x.png")),
            str(plot_phase(result, args.plot / "phase_x.png")),
            str(plot_efforts(result, args.plot / "efforts.png")),
        ]
    s = payload
    text = "\n".join(
        [
            f"{mech.name}: {s['status']} after {s['duration']:.3f} s "
            f"(Kn = {ctrl.gains.kn:g}, Kc = {ctrl.gains.kc:g}, {args.space} space)",
            f"RMS error {1e3 * s['rms_error']:.4f} mm; max |e| for t >= {s['steady_from']:.3g} s "
            f"[mm]: {fmt(1e3 * np.array(s['steady_error']), 4)}",
            f"peak efforts [N*m, N]: {fmt(np.array(s['peak_effort']), 4)}; "
            f"saturated {100 * s['saturated_fraction']:.1f} % of samples",
            f"wall time {s['wall_time']:.2f} s, {s['nfev']} dynamics evaluations",
        ]
        + [f"wrote {f}" for f in payload.get("figures", [])]
    )
    emit(args, payload, text)
    return 0
