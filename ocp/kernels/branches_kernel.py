"""The ``serial_branches`` kernel of one Mechanism: :mod:`.branches_function` on buffers.

:class:`SerialBranchesKernel` implements :class:`rcm_pin.model.serial_branches.SerialBranches`
for the six- and four-DOF RCM mechanisms: one call of the structure's function
(:class:`~ocp.kernels.closure_kernel.SharedFunction`: CasADi's VM first, compiled to C
after :data:`COMPILE_AFTER` calls, the same bits) on per-thread bound buffers, the
Mechanism's joint limits written once per buffer; None where the function flags a case
the numpy route handles otherwise (:mod:`.branches_function`).
"""

from __future__ import annotations

import threading
from collections.abc import Callable

import numpy as np

from ocp.buffered import BufferedFunction
from ocp.kernels.closure_kernel import COMPILE_AFTER as CLOSURE_COMPILE_AFTER
from ocp.kernels.closure_kernel import SharedFunction
from rcm_pin.analysis.capabilities import SERIAL_CLOSED_FORM as METHOD
from rcm_pin.model.serial_branches import BranchArrays

#: Calls in the VM before the function is compiled: the closure Newton's
#: (:data:`ocp.kernels.closure_kernel.COMPILE_AFTER`). The VM costs ~6 µs a call more
#: (7.6 against 1.5 µs), the compilation ~0.5 s once per machine (the disk cache): only a
#: sweep repays it, a one-shot solve never waits for a compiler.
COMPILE_AFTER = CLOSURE_COMPILE_AFTER
#: The branch labels of the family's position solver (``RcmPosition``), in order.
LABELS = tuple(f"branch_{b}" for b in range(8))
#: Per branch count B, the limit flags of every code Σ 2^i (branch i inside), as bools.
_INSIDE = {nb: tuple(tuple(bool(code >> i & 1) for i in range(nb)) for code in range(2**nb))
           for nb in (2, 8)}  # fmt: skip
#: A NamedTuple from its fields without its keyword-parsing ``__new__``.
_new = tuple.__new__
#: A thread's bound function: its evaluation, its value input, the q, output, info views.
_Bound = tuple[Callable[[], None], np.ndarray, np.ndarray, np.ndarray, np.ndarray]


class SerialBranchesKernel:
    """Every checked branch of one six- or four-DOF RCM Mechanism (module docstring)."""

    def __init__(self, shared: SharedFunction, lower: np.ndarray, upper: np.ndarray) -> None:
        self.shared, self.n = shared, len(lower)
        self.nb = nb = 8 if self.n == 6 else 2  # branches (six-DOF, four-DOF)
        self.labels, self._inside = LABELS[:nb], _INSIDE[nb]
        self.limits = np.concatenate([lower, upper]).astype(float)
        self._local = threading.local()

    def _buffers(self) -> _Bound:
        """This thread's bound function: its evaluation, its value input and (8, n) /
        (8, 12) / (8 + 2,) views of q, output and info (four-DOF: 2 branches)."""
        return self.shared.bound(self._local, self._bind)

    def _bind(self, buf: BufferedFunction) -> _Bound:
        buf.inputs[1][:] = self.limits
        q, out, info = buf.outputs
        nb = self.nb
        return buf.evaluate, buf.inputs[0], q.reshape(nb, self.n), out.reshape(nb, 12), info

    def __call__(self, value: np.ndarray) -> BranchArrays | None:
        """The checked branches (eight; four-DOF two) of a pose value (12,), or None (the
        numpy route)."""
        evaluate, given, q, out, info = self._buffers()
        given[:] = value
        evaluate()
        flags = info.tolist()
        if flags[-1]:
            return None
        nb = self.nb
        inside = self._inside[int(flags[nb])]
        return _new(BranchArrays, (q.copy(), out.copy(), flags[:nb], inside, self.labels, METHOD))


__all__ = ["COMPILE_AFTER", "LABELS", "SerialBranchesKernel"]
