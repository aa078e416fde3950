"""The four-bar from the two extreme rocker positions: every real root, checked.

Given the rocker's swing *up* φ and *down* γ [rad] from its straight position (the rocker
perpendicular to the frame line O1O2; up leans the rocker tip B towards O1, down away from
it, :mod:`rcm_pin.linkage.fourbar`), the coupler l2 and the rocker l3 [m], find the frame
l0 and the crank l1 whose dead centres are exactly these extremes.

With O2 at the origin, the straight rocker along +y and O1 = (−d, 0) (d the *signed* frame,
l1 the *signed* crank), the extremes are B_u = l3 (−sin φ, cos φ), B_d = l3 (sin γ, cos γ),
and the dead centres (crank and coupler aligned) give

    E_u:  |O1 B_u|² − (l2 − l1)² = d² − 2 d l3 sin φ + l3² − (l2 − l1)² = 0   (folded at up)
    E_d:  |O1 B_d|² − (l2 + l1)² = d² + 2 d l3 sin γ + l3² − (l2 + l1)² = 0   (extended at down)

E_d − E_u: 4 l2 l1 = 2 d l3 (sin φ + sin γ), so l1 = k d with k = l3 (sin φ + sin γ) / (2 l2);
E_u + E_d then leaves one quadratic in d,

    (1 − k²) d² + l3 (sin γ − sin φ) d + (l3² − l2²) = 0,

so the system has at most two real roots (one when 1 − k² = 0). A root with d > 0 is the
layout of paper 002 (O1 on the *up* side: folded at up, extended at down); d < 0 is its
mirror (O1 = (|d|, 0) on the *down* side, |l1| the crank: extended at up, folded at down).
A root is *valid* when it is a crank–rocker (Grashof, crank strictly the shortest): only then
does the crank turn fully and the rocker stop exactly at B_u and B_d.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rcm_pin.errors import InvalidInputError, UnreachablePoseError
from rcm_pin.linkage.fourbar import FourBar, Performance, performance

#: Link lengths accepted [m]: a micrometre to a thousand kilometres. The equations square
#: the lengths and their ratios; within this range every term stays far inside double
#: precision (1e300 overflows: 1e300² > 1.8e308).
LENGTH_RANGE = (1e-6, 1e6)
#: Layout names of a root (sign of d).
LAYOUTS = ("O1 on the up side", "O1 on the down side")


@dataclass(frozen=True)
class Root:
    """One real root of E_u = E_d = 0 (module docstring).

    Attributes:
        d: signed frame [m]; l1: signed crank [m] (l1 = k d).
        frame, crank: |d|, |l1| [m].
        layout: :data:`LAYOUTS` entry (d > 0: O1 on the up side).
        residual_up, residual_down: E_u, E_d [m²] evaluated at the root.
        valid: a crank–rocker with these extremes; reason: why not, when not.
        performance: the full-turn performance (None for a zero frame or crank).
    """

    d: float
    l1: float
    frame: float
    crank: float
    layout: str
    residual_up: float
    residual_down: float
    valid: bool
    reason: str
    performance: Performance | None


def extreme_residuals(
    up: float, down: float, coupler: float, rocker: float, d: float, l1: float
) -> tuple[float, float]:
    """(E_u, E_d) [m²] at a signed (d, l1), from the points O1, B_u, B_d."""
    o1 = np.array([-d, 0.0])
    b_up = rocker * np.array([-math.sin(up), math.cos(up)])
    b_down = rocker * np.array([math.sin(down), math.cos(down)])
    e_up = float(np.sum((b_up - o1) ** 2)) - (coupler - l1) ** 2
    e_down = float(np.sum((b_down - o1) ** 2)) - (coupler + l1) ** 2
    return e_up, e_down


def quadratic(up: float, down: float, coupler: float, rocker: float) -> tuple[float, ...]:
    """(k, a, b, c): l1 = k d and a d² + b d + c = 0 (module docstring)."""
    k = rocker * (math.sin(up) + math.sin(down)) / (2.0 * coupler)
    return k, 1.0 - k * k, rocker * (math.sin(down) - math.sin(up)), rocker**2 - coupler**2


def real_roots(a: float, b: float, c: float) -> list[float]:
    """Real roots of a x² + b x + c = 0 in ascending order (the cancellation-free form
    q = −(b + sign(b) √(b² − 4ac)) / 2, x = q / a, c / q; a = 0: the linear root)."""
    if a == 0.0:
        return [] if b == 0.0 else [-c / b]
    disc = b * b - 4.0 * a * c
    if disc < 0.0:
        return []
    q = -0.5 * (b + math.copysign(math.sqrt(disc), b))
    if q == 0.0:
        return [0.0]
    roots = {q / a, c / q}
    return sorted(roots)


def check_inputs(up: float, down: float, coupler: float, rocker: float) -> None:
    """Raises:
    InvalidInputError: a non-finite value, |φ| or |γ| ≥ π/2, φ + γ ≤ 0, or a length
        outside :data:`LENGTH_RANGE`.
    """
    values = {"up": up, "down": down, "coupler": coupler, "rocker": rocker}
    for name, v in values.items():
        if not math.isfinite(v):
            raise InvalidInputError(f"{name} = {v}; valid: a finite number")
    for name in ("up", "down"):
        if abs(values[name]) >= math.pi / 2:
            raise InvalidInputError(
                f"{name} = {math.degrees(values[name]):.6g} deg; valid: |{name}| < 90 deg "
                "(the rocker tip stays above the frame line)"
            )
    if up + down <= 0.0:
        raise InvalidInputError(
            f"up + down = {math.degrees(up + down):.6g} deg; valid: a swing up + down > 0 deg"
        )
    for name in ("coupler", "rocker"):
        check_length(name, values[name])


def check_length(name: str, value: float) -> None:
    """Raises:
    InvalidInputError: ``value`` [m] is not a finite length within :data:`LENGTH_RANGE`.
    """
    lo, hi = LENGTH_RANGE
    if not (math.isfinite(value) and lo <= value <= hi):
        raise InvalidInputError(
            f"{name} = {value:.6g} m; valid: a length from {lo:g} to {hi:g} m (the "
            "equations square the lengths: larger values overflow double precision)"
        )


def _root(up: float, down: float, coupler: float, rocker: float, d: float, k: float) -> Root:
    l1 = k * d
    e_up, e_down = extreme_residuals(up, down, coupler, rocker, d, l1)
    layout = LAYOUTS[0] if d > 0 else LAYOUTS[1]
    if d == 0.0 or l1 == 0.0:
        return Root(d, l1, abs(d), abs(l1), layout, e_up, e_down, False,
                    "zero frame or crank (a degenerate linkage)", None)  # fmt: skip
    g = FourBar(abs(d), abs(l1), coupler, rocker)
    perf = performance(g, up_towards_o1=d > 0)
    reason = "" if perf.crank_rocker else (
        f"a {perf.grashof_class} linkage, not a crank-rocker: the crank does not turn fully"
    )  # fmt: skip
    return Root(d, l1, g.l0, g.l1, layout, e_up, e_down, perf.crank_rocker, reason, perf)


def synthesize(up: float, down: float, coupler: float, rocker: float) -> list[Root]:
    """Every real root of the two extreme-position equations: d > 0 first, then d < 0.

    Args:
        up: swing φ from straight towards O1 [rad], |φ| < π/2.
        down: swing γ from straight away from O1 [rad], |γ| < π/2, φ + γ > 0.
        coupler: l2 [m] > 0.
        rocker: l3 [m] > 0.

    Returns:
        The roots (valid or not; :attr:`Root.valid`, :attr:`Root.reason`).

    Raises:
        InvalidInputError: bad input (:func:`check_inputs`).
        UnreachablePoseError: the equations have no real root.
    """
    check_inputs(up, down, coupler, rocker)
    k, a, b, c = quadratic(up, down, coupler, rocker)
    roots = real_roots(a, b, c)
    if not roots:
        raise UnreachablePoseError(
            f"no four-bar has its dead centres at up {math.degrees(up):.6g} deg and down "
            f"{math.degrees(down):.6g} deg with coupler {coupler:.6g} m and rocker "
            f"{rocker:.6g} m (the quadratic in the frame has no real root, discriminant "
            f"{b * b - 4 * a * c:.3g} m^2 < 0); valid: a longer coupler or a smaller swing"
        )
    roots.sort(key=lambda d: (d <= 0.0, abs(d)))  # the paper's layout (d > 0) first
    return [_root(up, down, coupler, rocker, d, k) for d in roots]


def valid_or_raise(roots: list[Root], up: float, down: float) -> list[Root]:
    """The valid roots.

    Raises:
        UnreachablePoseError: none is a crank–rocker (the message lists each root's reason).
    """
    valid = [r for r in roots if r.valid]
    if not valid:
        why = "; ".join(f"frame {r.frame:.6g} m, crank {r.crank:.6g} m: {r.reason}" for r in roots)
        raise UnreachablePoseError(
            f"no crank-rocker swings up {math.degrees(up):.6g} deg and down "
            f"{math.degrees(down):.6g} deg with these links ({why}); valid: a coupler and "
            "rocker for which a root is a crank-rocker (e.g. a longer coupler)"
        )
    return valid


__all__ = [
    "LAYOUTS",
    "LENGTH_RANGE",
    "Root",
    "check_inputs",
    "check_length",
    "extreme_residuals",
    "quadratic",
    "real_roots",
    "synthesize",
    "valid_or_raise",
]
