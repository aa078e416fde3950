"""Compiled CasADi kernels for the generic layers: the provider of :mod:`rcm_pin.model.kernels`.

Registered as the entry point ``casadi = "ocp.kernels:provider"`` of the group
``rcm_pin.kernels`` (pyproject.toml), so ``rcm_pin`` finds it without importing ``ocp``
(the import-linter contracts forbid that). :data:`provider` implements
:class:`rcm_pin.model.kernels.KernelProvider`:

* ``closure_newton(mech)``: the drives-fixed closure Newton of
  :mod:`ocp.kernels.newton_function` (``CHUNK`` unrolled iterations per call; with the
  output value and the limit flag of ``forward``, the Mechanism's limits widened by
  ``LIMIT_TOL`` as its bounds), one
  :class:`~ocp.kernels.closure_kernel.SharedFunction` per kinematic structure (the key:
  :func:`ocp.kernels.newton_function.structure_key`) shared in memory by every Mechanism
  of that structure: CasADi's virtual machine first (the serialised function cached on
  disk, :func:`vm_function`), compiled to C and cached on disk
  (:func:`ocp.compiled.compile_lazy`) after ``COMPILE_AFTER`` calls.
  ``RCM_PIN_KERNEL_VM=1`` (or no C compiler) keeps the VM. None for a mechanism the
  kernel does not mirror (fewer closure rows than passive joints, a non-Euclidean model:
  :func:`ocp.kernels.newton_function.supported`).
* ``serial_rhs(plant, controller)``: the compiled right-hand side of a serial ``simulate``
  (:mod:`ocp.kernels.serial_rhs`; ``RCM_PIN_KERNEL_VM=1`` keeps CasADi's VM), or None
  for a pair it does not mirror (:func:`rcm_pin.control.backends.compiled_unsupported`).
* ``closed_rhs(plant, controller)``: the compiled right-hand side of a closed ``simulate``
  (:mod:`ocp.kernels.closed_rhs`), or None for a pair it does not mirror
  (:func:`rcm_pin.control.closed_backend.closed_unsupported`, closure rows of less than
  full rank).
* ``serial_branches(mech)``: every checked branch of a six- or four-DOF RCM pose in one call
  (:mod:`ocp.kernels.branches_function`, :mod:`ocp.kernels.branches_kernel`), or None
  for a mechanism it does not mirror.
"""

from __future__ import annotations

import hashlib
import os
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING

import casadi as ca
import numpy as np

from ocp.kernels.closure_kernel import COMPILE_AFTER, ClosureNewtonKernel, SharedFunction
from ocp.kernels.newton_function import build, structure_key, supported
from ocp.kernels.serial_rhs import SerialRHSKernel, serial_rhs
from rcm_pin.analysis.branch_check import LIMIT_TOL
from rcm_pin.model.mechanism import Mechanism

if TYPE_CHECKING:
    from ocp.kernels.branches_kernel import SerialBranchesKernel
    from ocp.kernels.closed_rhs import ClosedRHSKernel

#: Unrolled Newton iterations per call of the compiled function.
CHUNK = 4
#: Set to 1 to run the kernels in CasADi's virtual machine (no C compilation).
VM_ENV = "RCM_PIN_KERNEL_VM"


def vm_function(mech: Mechanism, key: str) -> ca.Function:
    """The SX Newton function of ``mech`` (key: its :func:`structure_key`), from the disk
    cache of :func:`ocp.compiled.cache_dir` (:func:`cached_function`)."""
    name = f"closure_newton_{key[:12]}"
    return cached_function(name, key, lambda: build(mech, CHUNK, name))


def cached_function(name: str, key: str, make: Callable[[], ca.Function]) -> ca.Function:
    """The SX function ``name`` determined by ``key``, from the disk cache of
    :func:`ocp.compiled.cache_dir` (a serialised ``casadi.Function``, loaded in
    milliseconds where building the graph takes 0.05–0.3 s) once its size and checksum
    match their record (:mod:`ocp.so_cache`), else ``make()`` and saved there (a temporary
    name, renamed; a read-only cache keeps the built function)."""
    from ocp import so_cache
    from ocp.compiled import cache_dir

    digest = hashlib.sha256(f"{key}|{ca.__version__}".encode()).hexdigest()[:20]  # type: ignore[attr-defined]
    path = cache_dir() / f"{name}_{digest}.casadi"
    if so_cache.usable(path):
        try:
            return ca.Function.load(str(path))
        except RuntimeError:  # verified yet not loadable (another CasADi): build again
            pass
    fun = make()
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        fun.save(str(tmp))
        so_cache.publish(tmp, path)
    except (OSError, RuntimeError):  # a read-only cache: the function is still good
        pass
    return fun


def _vm_only() -> bool:
    """Whether ``$RCM_PIN_KERNEL_VM`` keeps the kernels in CasADi's VM."""
    return os.environ.get(VM_ENV, "") not in ("", "0")


class CasadiKernels:
    """The kernel provider (module docstring)."""

    name = "casadi"

    def __init__(self) -> None:
        self._shared: dict[str, SharedFunction] = {}
        self._lock = threading.Lock()

    def shared_function(self, mech: Mechanism) -> SharedFunction:
        """The Newton function of ``mech``'s kinematic structure (built on first use: the
        VM, compiled after ``COMPILE_AFTER`` calls unless ``$RCM_PIN_KERNEL_VM`` is set)."""
        key = structure_key(mech, CHUNK)
        with self._lock:
            shared = self._shared.get(key)
            if shared is None:
                vm_only = _vm_only()
                fun = vm_function(mech, key)
                shared = self._shared[key] = SharedFunction(
                    fun, key, None if vm_only else COMPILE_AFTER
                )
        return shared

    def newton_function(self, mech: Mechanism, vm: bool = False) -> ca.Function:
        """The VM (``vm``) or the compiled Newton function of ``mech``'s structure."""
        shared = self.shared_function(mech)
        if vm:
            return build(mech, CHUNK, shared.function.name())
        return shared.compile()

    def closure_newton(self, mech: Mechanism) -> ClosureNewtonKernel | None:
        """The closure Newton kernel of ``mech``, or None where it does not mirror numpy
        (or where its residual is not Pinocchio's: :func:`same_residual`)."""
        if not supported(mech):
            return None
        shared = self.shared_function(mech)
        if not same_residual(mech, shared.function):
            return None
        bounds = np.concatenate([mech.lower - LIMIT_TOL, mech.upper + LIMIT_TOL])
        return ClosureNewtonKernel(shared, CHUNK, bounds)

    def serial_rhs(self, plant: Mechanism, controller: object) -> SerialRHSKernel | None:
        """The compiled right-hand side of ``plant`` under ``controller``, or None where
        it does not mirror the Python hot path (:mod:`ocp.kernels.serial_rhs`)."""
        return serial_rhs(plant, controller, vm=_vm_only())

    def closed_rhs(self, plant: Mechanism, controller: object) -> ClosedRHSKernel | None:
        """The compiled right-hand side of a closed ``plant`` under ``controller``, or None
        where it does not mirror the Python hot path (:mod:`ocp.kernels.closed_rhs`;
        imported on the first request, 15–20 ms that the closure Newton's first call
        does not pay)."""
        from ocp.kernels.closed_rhs import closed_rhs

        return closed_rhs(plant, controller, vm=_vm_only())

    def serial_branches(self, mech: Mechanism) -> SerialBranchesKernel | None:
        """Every checked branch of a six- or four-DOF RCM pose in one call, or None for a mechanism
        it does not mirror (:mod:`ocp.kernels.branches_function`; imported on the first
        request). One function per kinematic structure, VM first, compiled after
        :data:`~ocp.kernels.branches_kernel.COMPILE_AFTER` calls."""
        from ocp.kernels import branches_function as bf
        from ocp.kernels.branches_kernel import COMPILE_AFTER as AFTER
        from ocp.kernels.branches_kernel import SerialBranchesKernel

        if not bf.supported(mech):
            return None
        key = "serial_branches|" + bf.structure_key(mech)
        with self._lock:
            shared = self._shared.get(key)
            if shared is None:
                name = f"rcm_branches_{key[-12:]}"
                fun = cached_function(name, key, lambda: bf.build(mech, name))
                shared = SharedFunction(fun, key, None if _vm_only() else AFTER)
                self._shared[key] = shared
        return SerialBranchesKernel(shared, mech.lower, mech.upper)


def same_residual(mech: Mechanism, fun: ca.Function, tol: float = 1e-9) -> bool:
    """Whether ``fun``'s residual norm equals Pinocchio's (to ``tol`` relative) at a seeded
    random configuration (|q| ≤ 0.5): a guard against a structure its key missed. With
    ``max_step`` = 0 the iterates stay at q, so ``info[0]`` is |e(q)|."""
    loops = mech.loops
    assert loops is not None
    q = np.random.default_rng(0).uniform(-0.5, 0.5, mech.model.nq)
    rho = float(fun(q, q[loops.drive_q], 0.0, np.zeros(2 * q.size))[2][0])
    rho_pin = float(np.linalg.norm(mech.closure_residual(q)))
    return abs(rho - rho_pin) <= tol * max(rho_pin, 1e-3)


#: The entry point's object.
provider = CasadiKernels()

__all__ = [
    "CHUNK",
    "VM_ENV",
    "CasadiKernels",
    "cached_function",
    "provider",
    "same_residual",
    "vm_function",
]
