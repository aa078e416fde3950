"""The kernel kind ``closure_newton``: its protocol and its outcomes.

A provider of :mod:`rcm_pin.model.kernels` answers ``closure_newton(mech)`` with a
:class:`ClosureNewton`: the drives-fixed Newton of
:func:`rcm_pin.model.newton.solve_passive` from a full start, in two calls:

* ``kernel(q_guess, drives, max_iter=, max_step=)`` -> :class:`NewtonOutcome`: the
  converged configuration (used by :func:`rcm_pin.analysis.closed_position.solve_drives`);
* ``kernel.forward(q_guess, drives, max_iter, max_step)`` -> :class:`ForwardOutcome`: the
  same solve, with what :func:`rcm_pin.forward` reports of it computed in the same call:
  the output value at the solution and the joint-limit flag (used by
  :func:`rcm_pin.analysis.forward_route.from_guess`).

Both return None where the kernel cannot reproduce the numpy route; the caller then runs
that route from the same inputs.
"""

from __future__ import annotations

from typing import NamedTuple, Protocol

import numpy as np


class NewtonOutcome(NamedTuple):
    """A converged closure Newton: q (nq,) with passive revolute angles wrapped to
    [−π, π), the iterations taken, the final residual norm [m, rad]."""

    q: np.ndarray
    iterations: int
    residual: float


class ForwardOutcome(NamedTuple):
    """A converged closure Newton with what ``forward`` reports of it: q, iterations and
    residual as :class:`NewtonOutcome`; ``output`` (size,) the value of ``mech.output`` at
    q [m, rad] (empty without an output; :meth:`~rcm_pin.model.mechanism.Mechanism.output_value`'s
    to rounding); ``within_limits``: lower − LIMIT_TOL ≤ q ≤ upper + LIMIT_TOL entry by
    entry (:func:`rcm_pin.analysis.branch_check.within_limits`'s comparisons)."""

    q: np.ndarray
    iterations: int
    residual: float
    output: np.ndarray
    within_limits: bool


class ClosureNewton(Protocol):
    """Newton on the closure residual with the drives fixed, from a full start."""

    def __call__(
        self, q_guess: np.ndarray, drives: np.ndarray, *, max_iter: int, max_step: float
    ) -> NewtonOutcome | None:
        """The numpy route's converged outcome from ``q_guess`` (nq,) with ``drives`` (k,)
        [rad, m] (each step clipped to ``max_step``, at most ``max_iter`` steps), or None
        where the kernel cannot reproduce it (the caller then runs the numpy route)."""
        ...

    def forward(
        self, q_guess: np.ndarray, drives: np.ndarray, max_iter: int, max_step: float
    ) -> ForwardOutcome | None:
        """The same solve as :meth:`__call__`, with the output value and the limit flag of
        the solution (:class:`ForwardOutcome`), or None where ``__call__`` is."""
        ...


__all__ = ["ClosureNewton", "ForwardOutcome", "NewtonOutcome"]
