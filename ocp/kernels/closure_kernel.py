"""The closure Newton kernel of one Mechanism: the CasADi function on per-thread buffers.

:class:`ClosureNewtonKernel` implements :class:`rcm_pin.model.kernels.ClosureNewton`: it
calls the ``n``-iteration function of :mod:`ocp.kernels.newton_function` through bound
numpy buffers (``Function.buffer()``, about 1 µs of call overhead instead of the
10–60 µs of an ordinary call with its DM conversions), chunk after chunk from the last
iterate, until an iterate is below ``RESIDUAL_TOL``, and returns

* the outcome (the same iterate, iteration count and residual as the numpy route), or
* with :meth:`ClosureNewtonKernel.forward`, the same outcome with the output value and
  the limit flag of the solution (the function's ``output`` and ``info[3]``; the
  Mechanism's bounds are written into each buffer once), or
* None, for the caller to run the numpy route from the same start, when numpy would
  have left its plain solve (a step ≥ 1e3 or NaN: least squares / LM), when no iterate
  within ``min(max_iter, MAX_ITER)`` converges (numpy then either converges later, after
  a longer walk, or raises its typed error with its own message).

:class:`SharedFunction` holds the function of one kinematic structure for every
Mechanism of that structure: CasADi's virtual machine first (the SX graph is built in
0.05–0.3 s, no compiler), the same function compiled to C (:func:`ocp.compiled.compile_lazy`,
disk cache; ``-ffp-contract=off`` keeps every operation as the VM rounds it) once the
structure has served :data:`COMPILE_AFTER` calls (functions of at most
:data:`COMPILE_MAX_INSTRUCTIONS`), so a one-shot solve never waits for a compiler and a
sweep runs compiled. The two give the same bits (tests/test_kernels.py),
so a result does not depend on how many solves came before it.

Buffers are per thread (a ``threading.local``), so one Mechanism solves from any number
of threads, as its Pinocchio data does.
"""

from __future__ import annotations

import threading
import warnings
from collections.abc import Callable
from typing import TypeVar

import casadi as ca
import numpy as np

from ocp.buffered import BufferedFunction
from rcm_pin.model.kernels import KernelWarning
from rcm_pin.model.newton import RESIDUAL_TOL
from rcm_pin.model.newton_kernel import ForwardOutcome, NewtonOutcome

#: Iterations the kernel walks before it leaves a start to numpy. Warm starts converge in
#: 2–5; a longer walk (a far start) goes to numpy, whose iterates the kernel would only
#: reproduce to rounding, which a long, clipped walk may amplify.
MAX_ITER = 12
#: Calls of a structure's function in the VM before it is compiled: the VM's extra cost
#: until then (at most ~50 µs a call) stays far below a compilation (0.15–2 s, once per
#: machine: the disk cache), which only a long sweep or a map repays.
COMPILE_AFTER = 1000
#: Larger functions stay in the VM unless :meth:`SharedFunction.compile` is called: the C
#: compiler needs about 0.2 ms per VM instruction at -O1 (translational_3ppapa_loops,
#: 74k instructions: 11 s), too long to start inside a user's loop.
COMPILE_MAX_INSTRUCTIONS = 20_000
#: C compiler flags: -O1, and no fused multiply-adds (the VM's rounding, bit for bit).
COMPILE_FLAGS = "-O1 -ffp-contract=off"
#: A NamedTuple from its fields without its keyword-parsing ``__new__``.
_new = tuple.__new__
_T = TypeVar("_T")


class SharedFunction:
    """The Newton function of one kinematic structure (module docstring)."""

    def __init__(self, function: ca.Function, key: str, compile_after: int | None) -> None:
        self.function, self.key = function, key
        if function.n_instructions() > COMPILE_MAX_INSTRUCTIONS:
            compile_after = None
        self.compile_after = compile_after  # None: stay in the VM
        self.compiled = False
        self.calls = 0
        self._lock = threading.Lock()

    def count(self) -> None:
        """One more call; compiles at :attr:`compile_after` calls."""
        self.calls += 1
        if self.compile_after is not None and self.calls >= self.compile_after:
            self.compile()

    def bound(self, local: threading.local, bind: Callable[[BufferedFunction], _T]) -> _T:
        """A thread's binding of the function, kept in ``local``: counts the call (see
        :meth:`count`), and on the thread's first call or after a compilation binds anew,
        ``bind(BufferedFunction(self.function))`` (a kernel writes its fixed inputs there)."""
        if self.compile_after is not None:
            self.count()
        fun = self.function
        if getattr(local, "source", None) is not fun:  # first call here, or just compiled
            local.bound, local.source = bind(BufferedFunction(fun)), fun
        out: _T = local.bound
        return out

    def compile(self) -> ca.Function:
        """The function compiled to C (from the disk cache when it is there)."""
        with self._lock:
            if not self.compiled:
                from ocp.compiled import CompileWarning, compile_lazy

                vm = self.function
                try:
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore", CompileWarning)  # VM: same bits
                        out = compile_lazy(vm.name(), self.key, lambda: vm, opt=COMPILE_FLAGS)
                    self.function, self.compiled = out.function, True
                except Exception as exc:  # e.g. an unloadable library: the VM serves on
                    msg = f"{vm.name()} stays in CasADi's VM: {exc}"
                    warnings.warn(msg, KernelWarning, stacklevel=2)
                self.compile_after = None
        return self.function


class ClosureNewtonKernel:
    """The drives-fixed Newton of one mechanism (module docstring).

    Args:
        shared: the function of the mechanism's structure.
        n: iterations per call of the function.
        bounds: (2 nq,) the limit flag's bounds, lower − ``LIMIT_TOL`` then upper +
            ``LIMIT_TOL`` [rad, m] (default: unbounded, the flag always 1).
    """

    def __init__(self, shared: SharedFunction, n: int, bounds: np.ndarray | None = None) -> None:
        self.shared, self.n = shared, n
        nq = shared.function.nnz_in(0)
        inf = np.full(nq, np.inf)
        self.bounds = np.concatenate([-inf, inf]) if bounds is None else np.array(bounds, float)
        self._local = threading.local()

    def _buffers(self) -> BufferedFunction:
        """This thread's buffers (the bounds written once)."""
        return self.shared.bound(self._local, self._bind)

    def _bind(self, buf: BufferedFunction) -> BufferedFunction:
        buf.inputs[3][:] = self.bounds
        return buf

    def _solve(
        self, q_guess: np.ndarray, drives: np.ndarray, max_iter: int, max_step: float
    ) -> tuple[list[np.ndarray], int, float, float] | None:
        """Chunks from ``q_guess`` until an iterate converges: (the output buffers, the
        iterations, ρ, the limit flag), or None (the numpy route)."""
        buf = self._buffers()
        q_in, qa_in, step_in, _ = buf.inputs
        outputs = buf.outputs
        q_last, info = outputs[1], outputs[2]
        q_in[:] = q_guess
        qa_in[:] = drives
        step_in[0] = max_step
        done, limit = 0, min(max_iter, MAX_ITER)
        while done <= limit:
            buf.evaluate()
            rho, it, bad, inside = info.tolist()
            if bad:
                return None
            if rho < RESIDUAL_TOL:
                total = done + int(it)
                return (outputs, total, rho, inside) if total <= limit else None
            done += self.n
            q_in[:] = q_last
        return None

    def __call__(
        self, q_guess: np.ndarray, drives: np.ndarray, *, max_iter: int, max_step: float
    ) -> NewtonOutcome | None:
        """Newton from ``q_guess`` (nq,) with ``drives`` (k,); None: use the numpy route."""
        out = self._solve(q_guess, drives, max_iter, max_step)
        if out is None:
            return None
        outputs, total, rho, _ = out
        return _new(NewtonOutcome, (outputs[0].copy(), total, rho))

    def forward(
        self, q_guess: np.ndarray, drives: np.ndarray, max_iter: int, max_step: float
    ) -> ForwardOutcome | None:
        """:meth:`__call__` with the output value and the limit flag of the solution
        (:class:`~rcm_pin.model.newton_kernel.ForwardOutcome`)."""
        out = self._solve(q_guess, drives, max_iter, max_step)
        if out is None:
            return None
        outputs, total, rho, inside = out
        fields = (outputs[0].copy(), total, rho, outputs[3].copy(), inside == 1.0)
        return _new(ForwardOutcome, fields)


__all__ = [
    "COMPILE_AFTER",
    "COMPILE_FLAGS",
    "COMPILE_MAX_INSTRUCTIONS",
    "MAX_ITER",
    "ClosureNewtonKernel",
    "SharedFunction",
]
