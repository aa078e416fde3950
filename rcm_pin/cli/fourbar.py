"""``rcm-pin fourbar synthesize | analyse``: the planar four-bar in closed form.

``synthesize``: the frame and crank whose dead centres are the rocker's extremes *up* and
*down* [deg] from straight (:mod:`rcm_pin.linkage.synthesis`), every valid root;
``analyse``: the same figures for given link lengths [m] (:mod:`rcm_pin.linkage.fourbar`).
"""

from __future__ import annotations

import argparse
import math
from typing import Any

from rcm_pin.cli._common import add_common, emit
from rcm_pin.errors import InvalidInputError
from rcm_pin.linkage.fourbar import FourBar, Performance, performance
from rcm_pin.linkage.synthesis import check_length, synthesize, valid_or_raise

#: Length options of ``analyse`` (FourBar field order).
LENGTHS = ("frame", "crank", "coupler", "rocker")


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``fourbar`` and its two subcommands."""
    p = sub.add_parser("fourbar", help="planar four-bar: synthesis from the rocker's extremes")
    inner = p.add_subparsers(dest="fourbar_command", required=True, metavar="SUBCOMMAND")
    s = inner.add_parser(
        "synthesize", help="frame and crank for a rocker swing (every crank-rocker root)"
    )
    s.add_argument("--up", type=float, required=True, help="swing up from straight [deg]")
    s.add_argument("--down", type=float, required=True, help="swing down from straight [deg]")
    s.add_argument("--coupler", type=float, required=True, help="coupler l2 [m]")
    s.add_argument("--rocker", type=float, required=True, help="rocker l3 [m]")
    add_common(s, mechanism=False)
    s.set_defaults(func=cmd_synthesize)
    a = inner.add_parser("analyse", help="Grashof class, transmission angle, swing, time ratio")
    for name in LENGTHS:
        a.add_argument(f"--{name}", type=float, required=True, help=f"{name} length [m]")
    add_common(a, mechanism=False)
    a.set_defaults(func=cmd_analyse)


def _deg(x: float | None) -> float | None:
    return None if x is None else math.degrees(x)


def figures(perf: Performance) -> dict[str, Any]:
    """The JSON keys of one linkage (lengths [m], angles [deg])."""
    g = perf.linkage
    dead = {}
    for name, dc in (("folded", perf.folded), ("extended", perf.extended)):
        dead[name] = (
            None if dc is None else {"crank_deg": _deg(dc.crank), "rocker_deg": _deg(dc.rocker)}
        )
    return {
        "frame": g.l0,
        "crank": g.l1,
        "coupler": g.l2,
        "rocker": g.l3,
        "grashof": perf.grashof_class,
        "crank_rocker": perf.crank_rocker,
        "transmission_angle_deg": [math.degrees(v) for v in perf.transmission_angle],
        "time_ratio": perf.time_ratio,
        "up_deg": _deg(perf.up),
        "down_deg": _deg(perf.down),
        "stroke_deg": _deg(perf.stroke),
        "dead_centres": dead,
    }


def _line(f: dict[str, Any]) -> str:
    if not f["crank_rocker"]:
        return (
            f"frame {f['frame']:.6g} m, crank {f['crank']:.6g} m: {f['grashof']}, transmission "
            f"angle {f['transmission_angle_deg'][0]:.4g}..{f['transmission_angle_deg'][1]:.4g} "
            "deg over the crank's range; the crank does not turn fully (no swing, no time ratio)"
        )
    return (
        f"frame {f['frame']:.6g} m, crank {f['crank']:.6g} m: {f['grashof']}, up "
        f"{f['up_deg']:.6g} deg, down {f['down_deg']:.6g} deg, transmission angle "
        f"{f['transmission_angle_deg'][0]:.4g}..{f['transmission_angle_deg'][1]:.4g} deg, "
        f"time ratio {f['time_ratio']:.6g}"
    )


def cmd_synthesize(args: argparse.Namespace) -> int:
    """``rcm-pin fourbar synthesize``: every crank–rocker with these extremes."""
    up, down = math.radians(args.up), math.radians(args.down)
    roots = synthesize(up, down, args.coupler, args.rocker)
    valid = valid_or_raise(roots, up, down)
    solutions = []
    for r in valid:
        assert r.performance is not None  # a valid root has one
        solutions.append(
            {**figures(r.performance), "layout": r.layout, "signed_frame": r.d,
             "signed_crank": r.l1, "residual_up": r.residual_up, "residual_down": r.residual_down}
        )  # fmt: skip
    rejected = [
        {"signed_frame": r.d, "signed_crank": r.l1, "reason": r.reason}
        for r in roots
        if not r.valid
    ]
    payload = {
        "given": {"up_deg": args.up, "down_deg": args.down, "coupler": args.coupler,
                  "rocker": args.rocker},
        "count": len(solutions),
        "solutions": solutions,
        "rejected": rejected,
    }  # fmt: skip
    text = "\n".join(f"{s['layout']}: {_line(s)}" for s in solutions)
    emit(args, payload, text)
    return 0


def cmd_analyse(args: argparse.Namespace) -> int:
    """``rcm-pin fourbar analyse``: the figures of given link lengths."""
    values = [getattr(args, name) for name in LENGTHS]
    for name, v in zip(LENGTHS, values, strict=True):
        check_length(f"--{name}", v)
    g = FourBar(*values)
    if not g.assemblable:
        raise InvalidInputError(
            f"links {g.lengths} [m] cannot be assembled: the longest is not shorter than the "
            "sum of the other three; valid: longest < sum of the others"
        )
    f = figures(performance(g))
    emit(args, f, _line(f))
    return 0


__all__ = ["cmd_analyse", "cmd_synthesize", "figures", "register"]
