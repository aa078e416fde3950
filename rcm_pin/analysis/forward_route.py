"""The hot path of :func:`rcm_pin.forward` of one configuration or of one guess.

``forward(mech, q)`` (serial) and ``forward(mech, drives, q_guess=q)`` (closed) spend
about a microsecond in Pinocchio or three in the compiled closure Newton; around it,
the general route (:func:`forward_reference`, kept as the reference) validates its inputs
twice, evaluates the output and the limit flag through general helpers and builds two
frozen dataclasses. This route gives the same results (every array bit for bit, the same
types and errors; ``tests/test_forward_route.py`` compares both on seeded random inputs
of every closed catalogue mechanism; one exception below) at a fraction of that cost:

* inputs: float64 arrays of the right shapes whose entries pass one ``math.hypot`` within
  :data:`~rcm_pin.rotations.MAX_ABS` are what :meth:`~rcm_pin.model.mechanism.Mechanism.check_q`
  accepts unchanged (every |entry| ≤ the hypot: finite and within the bound); anything
  else takes ``check_q``, its typed errors and their messages. The guess is read, never
  kept (the kernel copies it into its buffers, the numpy Newton into its own array);
* the solve: the closure Newton kernel's ``forward`` call
  (:class:`~rcm_pin.model.newton_kernel.ClosureNewton`) where there is one: the solve of
  :func:`~rcm_pin.analysis.closed_position.solve_drives` (the same q, iterations and
  residual), the output value and the limit flag, in one compiled call. The flag is
  ``within_limits``'s comparisons on the same floats; the output value comes from the
  kernel's symbolic forward kinematics, Pinocchio's to rounding (bit for bit on most
  mechanisms, 1.4e-17 apart on spherical_3rrr: the exception). Where the kernel declines
  or is disabled, :func:`~rcm_pin.analysis.closed_position.solve_numpy` and Pinocchio;
* per Mechanism (a ``WeakKeyDictionary``, a :class:`Plan`): the limit bounds
  lower − :data:`~rcm_pin.analysis.branch_check.LIMIT_TOL` and upper + ``LIMIT_TOL`` as
  floats, the very floats that :func:`~rcm_pin.analysis.branch_check.within_limits`
  computes on each call;
* the result and its solution built by :func:`~rcm_pin.analysis.results.one_solution`
  (equal to the constructors').
"""

from __future__ import annotations

import math
import weakref
from operator import le
from typing import Any

import numpy as np
import pinocchio as pin

from rcm_pin.analysis import closed_position as cp
from rcm_pin.analysis.branch_check import LIMIT_TOL, placement, within_limits
from rcm_pin.analysis.results import PositionResult, PositionSolution, one_solution
from rcm_pin.model import kernels
from rcm_pin.model.loops import Loops
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.newton import MAX_ITER, MAX_STEP
from rcm_pin.rotations import MAX_ABS

#: The methods of the two results.
TREE, GUESS = "Pinocchio forward kinematics", "Newton on Pinocchio closures from the guess"
_F64 = np.dtype(np.float64)  # (another float64 descriptor only takes check_q)


class Plan:
    """What the hot path reads of one Mechanism (module docstring)."""

    __slots__ = ("dof", "hi", "identity", "lo", "model", "nq", "output")

    def __init__(self, mech: Mechanism) -> None:
        self.nq, self.identity = mech.nq, mech.identity_order
        self.model, self.output = mech.model, mech.output
        self.dof = 0 if mech.loops is None else mech.loops.dof
        self.lo = (mech.lower - LIMIT_TOL).tolist()
        self.hi = (mech.upper + LIMIT_TOL).tolist()


_plans: weakref.WeakKeyDictionary[Mechanism, Plan] = weakref.WeakKeyDictionary()


def plan(mech: Mechanism) -> Plan:
    """The :class:`Plan` of ``mech`` (built on the first request, then cached)."""
    p = _plans.get(mech)
    if p is None:
        p = _plans[mech] = Plan(mech)
    return p


def serial(mech: Mechanism, q: Any) -> PositionResult:
    """``forward(mech, q)`` of a serial mechanism (the tool's value, one solution)."""
    p = plan(mech)
    if type(q) is np.ndarray and q.dtype is _F64 and q.shape == (p.nq,):
        ql = q.tolist()
        qc = q.copy() if math.hypot(*ql) <= MAX_ABS else mech.check_q(q)
    else:
        qc = mech.check_q(q)
        ql = qc.tolist()
    model, data, output = p.model, mech.data, p.output
    pin.forwardKinematics(model, data, qc if p.identity else mech.to_pin(qc))
    value = output.value(pin.updateFramePlacement(model, data, output.frame_id))
    inside = all(map(le, p.lo, ql)) and all(map(le, ql, p.hi))
    return one_solution(mech, "forward", qc, TREE, (qc, value, "tree", 0.0, 0, inside))


def from_guess(mech: Mechanism, loops: Loops, q: Any, q_guess: Any) -> PositionResult:
    """``forward(mech, drives, q_guess=...)`` of a closed mechanism (one Newton solve)."""
    p = plan(mech)
    if (
        type(q) is np.ndarray
        and type(q_guess) is np.ndarray
        and q.dtype is _F64
        and q_guess.dtype is _F64
        and q.shape == (p.dof,)
        and q_guess.shape == (p.nq,)
        and math.hypot(*q.tolist(), *q_guess.tolist()) <= MAX_ABS
    ):
        drives, q0 = q.copy(), q_guess
    else:
        drives = mech.check_q(q, "drives", loops.dof)
        q0 = mech.check_q(q_guess, "q_guess")
    kernel = kernels.closure_newton(mech)
    out = None if kernel is None else kernel.forward(q0, drives, MAX_ITER, MAX_STEP)
    if out is not None:  # the solve, the output value and the limit flag in one call
        qs, it, res, value, inside = out
    else:
        qs, it, res = cp.solve_numpy(mech, drives, q0, MAX_ITER, MAX_STEP)
        model, data, output = p.model, mech.data, p.output
        pin.forwardKinematics(model, data, qs)  # as Mechanism.output_value
        value = output.value(pin.updateFramePlacement(model, data, output.frame_id))
        ql = qs.tolist()
        inside = all(map(le, p.lo, ql)) and all(map(le, ql, p.hi))
    return one_solution(mech, "forward", drives, GUESS, (qs, value, "guess", res, it, inside))


def forward_reference(mech: Mechanism, q: Any, q_guess: Any = None) -> PositionResult:
    """The general route of :func:`serial` (``q_guess`` None) and :func:`from_guess`."""
    if mech.loops is None:
        qc = mech.check_q(q)
        value = mech.output.value(placement(mech, qc))
        sol = PositionSolution(qc, value, "tree", 0.0, 0, within_limits(mech, qc))
        return PositionResult(mech, "forward", qc, mech.output, (sol,), TREE)
    drives = mech.check_q(q, "drives", mech.loops.dof)
    q0 = mech.check_q(q_guess, "q_guess")
    qs, it, res = cp.solve_drives(mech, drives, q0)
    inside = within_limits(mech, qs)
    sol = PositionSolution(qs, mech.output_value(qs), "guess", res, it, inside)
    return PositionResult(mech, "forward", drives, mech.output, (sol,), GUESS)


__all__ = ["GUESS", "TREE", "Plan", "forward_reference", "from_guess", "plan", "serial"]
