"""Named configurations of a Mechanism: one rule, one default (``mech.home``).

A family may name configurations (``Family.configurations``: ``home`` and any others, in
Mechanism coordinates). ``mech.configurations`` is that mapping with ``home`` always
present; a mechanism that names no ``home`` (every URDF loaded by path without a family)
gets the one default of :func:`default_home`:

1. each coordinate at the middle of its range where both limits are finite, else 0
   (clipped into a half-bounded range);
2. a closed mechanism's passive joints then closed by Newton on the closures with the
   drives held (left open where Newton does not converge: the closure gap shows it).

Every consumer (control postures and scenarios, viewers, mobility, the CasADi IK, the
CLI, the analyses) starts from ``mech.home``; none has a fallback of its own.
"""

from __future__ import annotations

import contextlib
from typing import TYPE_CHECKING

import numpy as np

from rcm_pin.errors import SolverError
from rcm_pin.model.newton import solve_passive

if TYPE_CHECKING:
    from rcm_pin.model.mechanism import Mechanism

#: Starts tried to assemble the default home of a closed mechanism.
ASSEMBLY_STARTS = 8


def mid_range(mech: Mechanism) -> np.ndarray:
    """Middle of each finite joint range, 0 for unbounded joints (clipped to the limits)."""
    lo, hi = mech.lower, mech.upper
    both = np.isfinite(lo) & np.isfinite(hi)
    q = np.where(both, 0.5 * (np.where(both, lo, 0.0) + np.where(both, hi, 0.0)), 0.0)
    return np.clip(q, lo, hi)


def default_home(mech: Mechanism) -> np.ndarray:
    """The default ``home`` (module docstring): mid-range, then assembled if closed.

    The passive joints start at mid-range, then (where Newton fails from a degenerate
    start, e.g. a four-bar stretched flat) from deterministic offsets of ±0.5 rad / ±10 %
    of the length scale; the first converged assembly is taken.
    """
    q = mid_range(mech)
    loops = mech.loops
    if loops is None:
        return q
    drives = q[loops.drive_q]
    rng = np.random.default_rng(0)
    scale = np.where(mech.revolute, 0.5, 0.1 * loops.length_scale)
    for k in range(ASSEMBLY_STARTS):
        q0 = q.copy()
        if k:
            q0[loops.passive_q] += (scale * rng.uniform(-1.0, 1.0, mech.nq))[loops.passive_q]
        with contextlib.suppress(SolverError):
            return solve_passive(mech.model, mech.data, loops, drives, q0)[0]
    return q


def named_configurations(mech: Mechanism) -> dict[str, np.ndarray]:
    """The family's named configurations with ``home`` always present (module docstring)."""
    named = {k: mech.check_q(v, k).copy() for k, v in mech.family.configurations(mech).items()}
    if "home" not in named:
        named["home"] = default_home(mech)
    for v in named.values():
        v.setflags(write=False)
    return named


__all__ = ["default_home", "mid_range", "named_configurations"]
