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

    p = sub.add_parser(
        "simulate",
        help="computed-torque tracking on the Pinocchio dynamics",
        description="Serial RCM mechanisms: computed-torque tracking of a tool-centre "
        "trajectory. Closed loops: five_bar only, the drive-switching study of paper 004 "
        "(a path across the type-2 curve of the main drives; --switching hands over to the "
        "two extra elbow drives inside the band); planar_3rrr: computed-torque tracking of a "
        "platform circle with a phi oscillation (--tau-zeta, --duration).",
    )
    add_common(p)
    p.add_argument("--trajectory", default="paper000", choices=sorted(TRAJECTORIES))
    gains = p.add_mutually_exclusive_group()
    gains.add_argument("--gains", help="Kn,Kc [1/s^2, 1/s] (default 720,12, paper 000)")
    gains.add_argument("--tau-zeta", help="tau,zeta of tau^2 e'' + 2 zeta tau e' + e = 0 [s, -]")
    p.add_argument(
        "--duration", type=float, default=None, help="simulated time [s] (default 2; five_bar: 1)"
    )
    p.add_argument("--space", choices=("task", "joint"), default="task")
    p.add_argument("--no-feedforward", action="store_true", help="drop the reference acceleration")
    p.add_argument("--printed-sign", action="store_true", help="paper 000's printed Kn(x - x_t)")
    p.add_argument("--no-limits", action="store_true", help="ignore the URDF drive effort limits")
    p.add_argument("--no-gravity", action="store_true", help="simulate without gravity")
    p.add_argument("--plot", type=Path, metavar="DIR", help="write deviation/phase/effort PNGs")
    p.add_argument(
        "--switching",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="five_bar: switch to the extra drives near the type-2 curve (default on)",
    )
    p.add_argument(
        "--tau-max", type=float, default=None, help="five_bar: drive torque limit [N*m] (0.5)"
    )
    p.add_argument(
        "--compare",
        action="store_true",
        help="five_bar: run main-unlimited, main-saturated and switching (the paper's study)",
    )
    p.set_defaults(func=cmd_simulate)


def _gains(args: argparse.Namespace):
    from rcm_pin.control import Gains

    if args.tau_zeta:
        tau, zeta = parse_vector(args.tau_zeta, "tau-zeta", 2)
        return Gains.from_tau_zeta(float(tau), float(zeta))
    kn, kc = parse_vector(args.gains or "720,12", "gains", 2)
    return Gains(float(kn), float(kc))


def cmd_simulate(args: argparse.Namespace) -> int:
    from rcm_pin.cli.analysis import is_closed
    from rcm_pin.control import ComputedTorque, drive_limits
    from rcm_pin.dynamics import with_gravity
    from rcm_pin.mechanism import load
    from rcm_pin.simulation import simulate
    from rcm_pin.simulation_plots import plot_deviation, plot_efforts, plot_phase
    from rcm_pin.trajectories import get_trajectory

    if args.duration is not None and not (np.isfinite(args.duration) and args.duration > 0):
        raise InvalidInputError(f"--duration {args.duration} is invalid; valid: > 0 [s]")
    if is_closed(args.name):
        return _closed_simulate(args)
    for opt, val in (("--switching", args.switching), ("--tau-max", args.tau_max)):
        if val is not None:
            raise InvalidInputError(f"{opt} applies to five_bar only; {args.name} is serial")
    if args.compare:
        raise InvalidInputError(f"--compare applies to five_bar only; {args.name} is serial")
    if args.duration is None:
        args.duration = 2.0
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


#: Closed mechanisms with a simulation (paper 004: five-bar drive switching, 3-RRR tracking).
CLOSED_SIMULATIONS = ("five_bar", "planar_3rrr")


def _closed_simulate(args: argparse.Namespace) -> int:
    from dataclasses import replace

    from rcm_pin.closed_loop import load_closed
    from rcm_pin.closed_loop.plots import switching_figure
    from rcm_pin.closed_loop.switching import StudySettings, simulate, torque_along_reference

    if args.name not in CLOSED_SIMULATIONS:
        raise InvalidInputError(
            f"simulate has no closed-loop simulation for {args.name}; valid closed mechanisms: "
            f"{', '.join(CLOSED_SIMULATIONS)} (serial: rcm_bevel, rcm_bevel_4dof, rcm_belt)"
        )
    if args.name == "planar_3rrr":
        return _planar_3rrr_simulate(args)
    tau_max = 0.5 if args.tau_max is None else args.tau_max
    if not (np.isfinite(tau_max) and tau_max > 0):
        raise InvalidInputError(f"--tau-max {args.tau_max} is invalid; valid: > 0 [N*m]")
    mech = load_closed(args.name, **parse_xacro_args(args.arg))
    s = StudySettings(tau_max=tau_max)
    if args.duration is not None:
        s = replace(s, duration=args.duration)
    switching = True if args.switching is None else args.switching
    plans = [(f"switching, torque limit {tau_max:g} N*m", True, tau_max)]
    if args.compare:
        plans = [
            ("main drives, unlimited", False, None),
            (f"main drives, torque limit {tau_max:g} N*m", False, tau_max),
            *plans,
        ]
    elif not switching:
        plans = [(f"main drives, torque limit {tau_max:g} N*m", False, tau_max)]
    runs = [simulate(mech, label, sw, lim, s, 5e-3) for label, sw, lim in plans]
    payload: dict[str, object] = {
        "mechanism": mech.name,
        "settings": s.__dict__,
        "runs": [r.summary() for r in runs],
        "figures": [],
    }
    if args.plot:
        args.plot.mkdir(parents=True, exist_ok=True)
        ref = torque_along_reference(mech, s, n=801)
        payload["figures"] = [
            str(switching_figure(runs, ref, args.plot / "five_bar_switching.png"))
        ]
    lines = [
        f"{mech.name}: path {s.p0} -> {s.p1} m in {s.duration:g} s across the type-2 curve "
        f"(tau_c = {s.tau_c} s, band {s.band}, limit {tau_max:g} N*m)"
    ]
    for r in payload["runs"]:  # type: ignore[attr-defined]
        lines.append(
            f"{r['label']}: {'completed' if r['completed'] else 'stopped'} at {r['t_end']:.3f} s, "
            f"peak main {r['peak_main_torque']:.3g} N*m, peak extra {r['peak_extra_torque']:.3g} "
            f"N*m, max error after 0.2 s {r['max_error_after_transient']:.3g} m, "
            f"{r['time_on_extras']:.3f} s on extras"
        )
    lines += [f"wrote {f}" for f in payload["figures"]]  # type: ignore[attr-defined]
    emit(args, payload, "\n".join(lines))
    return 0


def _planar_3rrr_simulate(args: argparse.Namespace) -> int:
    """Computed-torque tracking of the 3-RRR platform (:mod:`rcm_pin.closed_loop.tracking`)."""
    from dataclasses import replace

    from rcm_pin.closed_loop import load_closed
    from rcm_pin.closed_loop.tracking import TrackingSettings, simulate_tracking, tracking_figure

    for opt, val in (
        ("--switching", args.switching),
        ("--tau-max", args.tau_max),
        ("--compare", args.compare or None),
    ):
        if val is not None:
            raise InvalidInputError(f"{opt} applies to five_bar only, not planar_3rrr")
    if args.gains:
        raise InvalidInputError("--gains does not apply to planar_3rrr; use --tau-zeta tau,zeta")
    s = TrackingSettings()
    if args.tau_zeta:
        tau, zeta = parse_vector(args.tau_zeta, "tau-zeta", 2)
        if not (tau > 0 and zeta > 0):
            raise InvalidInputError(
                f"--tau-zeta {args.tau_zeta} is invalid; valid: tau > 0 [s], zeta > 0"
            )
        s = replace(s, tau=float(tau), zeta=float(zeta))
    if args.duration is not None:
        s = replace(s, duration=args.duration, samples=max(201, int(200 * args.duration) + 1))
    mech = load_closed(args.name, **parse_xacro_args(args.arg))
    result = simulate_tracking(mech, s)
    payload: dict[str, object] = {"mechanism": mech.name, **result.summary(), "figures": []}
    if args.plot:
        args.plot.mkdir(parents=True, exist_ok=True)
        payload["figures"] = [str(tracking_figure(result, args.plot / "planar_3rrr_tracking.png"))]
    d = result.summary()
    lines = [
        f"{mech.name}: circle r = {s.radius} m about {list(s.centre)} m, phi amplitude "
        f"{s.phi_amp} rad, {s.duration:g} s, mode {s.mode} "
        f"(tau = {s.tau:g} s, zeta = {s.zeta:g}: Kn = {d['kn']:g}, Kc = {d['kc']:g})",
        f"path regular: min measures type 1 {d['min_measure_type1']:.3g}, "
        f"type 2 {d['min_measure_type2']:.3g}",
        f"error (x, y [m], phi [rad]): initial {fmt(result.error[0], 3)}, "
        f"final {fmt(result.error[-1], 3)}; deviation from the linear error dynamics "
        f"{d['max_deviation_from_error_dynamics']:.2e}",
        f"peak drive torques [N*m]: {fmt(np.array(d['peak_torque']), 4)}; "
        f"max closure residual {d['max_closure_residual']:.2e} m; {d['nfev']} evaluations",
    ]
    lines += [f"wrote {f}" for f in payload["figures"]]  # type: ignore[attr-defined]
    emit(args, payload, "\n".join(lines))
    return 0
