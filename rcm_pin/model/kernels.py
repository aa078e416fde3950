"""Optional fast kernels for the generic layers, found through entry points.

The generic layers never import the CasADi layer ``ocp`` (import-linter contract); a
faster implementation of one of their hot loops comes in by dependency inversion: a
*provider* (:class:`KernelProvider`) registered in the entry-point group
:data:`GROUP` (``[project.entry-points."rcm_pin.kernels"]`` in pyproject.toml; ``ocp``
registers ``casadi = "ocp.kernels:provider"``) is loaded lazily on the first request and
asked for a kernel per :class:`~rcm_pin.model.mechanism.Mechanism`; the answer (a kernel
or None) is cached per Mechanism (a ``WeakKeyDictionary``: it goes with the Mechanism).
A kernel is requested on a Mechanism's first solve and used from then on, so a result
never depends on how many solves came before it (the provider keeps its costs small:
:mod:`ocp.kernels` starts in CasADi's virtual machine and compiles only a structure that
is used). :func:`warm` builds at once (benchmarks, tests).

Kernels never change a result: a kernel answers only where it reproduces the numpy route
(to rounding) and returns None elsewhere, and the caller then runs the numpy route from
the same inputs, so every solution, iteration count and typed error stays as it was.
A provider that fails to load or to build a kernel is skipped with a
:class:`KernelWarning` (the numpy route then serves).

Kernel kinds:

* :meth:`KernelProvider.closure_newton` -> :class:`ClosureNewton`: the drives-fixed
  Newton of :func:`rcm_pin.model.newton.solve_passive` (used by
  :func:`rcm_pin.analysis.closed_position.solve_drives`), and the same solve with the
  output value and the limit flag (used by ``rcm_pin.forward(q_guess=)``; the kind's
  protocol and outcomes: :mod:`rcm_pin.model.newton_kernel`).
* :meth:`KernelProvider.serial_rhs` -> :class:`SerialRHS`: the whole right-hand side of a
  serial :func:`rcm_pin.control.simulate.simulate` (plant + computed-torque law), cached
  per (plant, controller) pair by :func:`serial_rhs`. The one kind that does not promise
  the numpy route's result: it equals the hot path's right-hand side to rounding, which
  changes the integrator's step sequence and so the trajectory at the integration
  tolerance; ``simulate`` uses it only on request (``backend="compiled"``).
* :meth:`KernelProvider.closed_rhs` -> :class:`ClosedRHS`: the same for a closed plant
  (closed computed-torque law + KKT forward dynamics), cached per (plant, controller)
  pair by :func:`closed_rhs`; bound to a run's Baumgarte numbers, a call returns None
  where it declines (a near rank loss of the closure rows) and the caller runs the
  Python route for that call.
* ``serial_branches`` -> :class:`~rcm_pin.model.serial_branches.SerialBranches`: every
  checked branch of a serial inverse in one call (used by :func:`rcm_pin.inverse`; the
  accessor and its per-Mechanism cache live in :mod:`rcm_pin.model.serial_branches`).

Switches: the environment variable :data:`DISABLE_ENV` (``RCM_PIN_NO_KERNELS=1``, read
at import), :func:`set_enabled` and the context manager :func:`disabled` (tests compare
both routes with it).
"""

from __future__ import annotations

import os
import threading
import warnings
import weakref
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any, Protocol, TypeVar

import numpy as np

from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.newton_kernel import ClosureNewton, ForwardOutcome, NewtonOutcome

#: Entry-point group of the providers.
GROUP = "rcm_pin.kernels"
#: Environment variable that disables every kernel (any value but "" and "0").
DISABLE_ENV = "RCM_PIN_NO_KERNELS"


class KernelWarning(UserWarning):
    """A provider could not be loaded or could not build a kernel (numpy serves)."""


class SerialRHS(Protocol):
    """y' = (q̇, q̈) of a serial plant under a controller, the reference as input."""

    def __call__(self, y: np.ndarray, r: np.ndarray | list[float]) -> np.ndarray:
        """y' (n + nv,) at y = (q, q̇) with the reference r = (x_T, ẋ_T, ẍ_T) (3 dim,):
        a new array [rad/s, m/s; rad/s², m/s²]."""
        ...


class BoundClosedRHS(Protocol):
    """One run's closed right-hand side (:meth:`ClosedRHS.bind`)."""

    def __call__(self, y: np.ndarray, r: np.ndarray | list[float]) -> np.ndarray | None:
        """y' (2 nv,) at y = (q, q̇) with r = (x_T, ẋ_T, ẍ_T), or None (declined)."""
        ...

    def outputs(self, y: np.ndarray, r: np.ndarray | list[float]) -> tuple[np.ndarray, ...]:
        """(y', clipped drive efforts, unclipped ones, the plant's task x, ẋ, rank guard)."""
        ...


class ClosedRHS(Protocol):
    """y' = (q̇, q̈) of a closed plant under a controller, the reference as input."""

    def bind(self, baumgarte: tuple[float, float]) -> BoundClosedRHS:
        """The right-hand side of one run with the plant's Baumgarte (ω [rad/s], ζ)."""
        ...


class KernelProvider(Protocol):
    """What an entry point of :data:`GROUP` names."""

    def closure_newton(self, mech: Mechanism) -> ClosureNewton | None:
        """A closure Newton kernel for ``mech``, or None (not supported)."""
        ...

    def serial_rhs(self, plant: Mechanism, controller: object) -> SerialRHS | None:
        """A right-hand side kernel of ``plant`` under ``controller`` (a
        ``ComputedTorque``), or None (not supported). Optional: a provider without
        this method has no such kernel."""
        ...

    def closed_rhs(self, plant: Mechanism, controller: object) -> ClosedRHS | None:
        """A closed right-hand side kernel of ``plant`` under ``controller``, or None.
        Optional, as :meth:`serial_rhs`."""
        ...


_enabled = os.environ.get(DISABLE_ENV, "") in ("", "0")
_providers: tuple[KernelProvider, ...] | None = None
#: per Mechanism: its kernel, or None (no provider has one)
_newton: weakref.WeakKeyDictionary[Mechanism, ClosureNewton | None] = weakref.WeakKeyDictionary()
_lock = threading.RLock()


def enabled() -> bool:
    """Whether kernels are used."""
    return _enabled


def set_enabled(flag: bool) -> bool:
    """Use kernels (True) or the numpy routes only (False); returns the previous setting."""
    global _enabled
    previous, _enabled = _enabled, bool(flag)
    return previous


@contextmanager
def disabled() -> Iterator[None]:
    """The numpy routes only, inside the ``with`` block."""
    previous = set_enabled(False)
    try:
        yield
    finally:
        set_enabled(previous)


def providers() -> tuple[KernelProvider, ...]:
    """The providers of :data:`GROUP`, loaded once (sorted by entry-point name)."""
    global _providers
    with _lock:
        if _providers is None:
            # importlib.metadata takes ~25 ms to import: only on the first request
            from importlib.metadata import entry_points

            loaded = []
            for ep in sorted(entry_points(group=GROUP), key=lambda e: e.name):
                try:
                    loaded.append(ep.load())
                except Exception as exc:  # an optional accelerator: numpy serves
                    msg = f"kernel provider {ep.value!r} not loaded: {exc}"
                    warnings.warn(msg, KernelWarning, stacklevel=2)
            _providers = tuple(loaded)
        return _providers


def closure_newton(mech: Mechanism) -> ClosureNewton | None:
    """The closure Newton kernel of ``mech`` (first provider that has one), or None when
    kernels are disabled or none applies. Built on the first request, then cached."""
    if not _enabled:
        return None
    try:
        return _newton[mech]
    except KeyError:
        return warm(mech)


def warm(mech: Mechanism) -> ClosureNewton | None:
    """Build (or look up) the closure Newton kernel of ``mech`` now; None if none applies."""
    with _lock:
        if mech not in _newton:
            _newton[mech] = _first_kernel(mech)
        return _newton[mech]


def _first_kernel(mech: Mechanism) -> ClosureNewton | None:
    kernel: ClosureNewton | None = first_kernel("closure_newton", "closure Newton", mech)
    return kernel


def first_kernel(kind: str, label: str, mech: Mechanism, *args: object, stacklevel: int = 4) -> Any:
    """The first provider's answer to ``kind(mech, *args)`` that is not None, or None.
    Providers without that method are skipped; one that raises is skipped with a
    :class:`KernelWarning` ``"<mech.name>: <label> kernel not built: <error>"``
    (``stacklevel`` as ``warnings.warn``'s, counted from this function)."""
    for p in providers():
        build = getattr(p, kind, None)
        if build is None:
            continue
        try:
            kernel = build(mech, *args)
        except Exception as exc:  # an optional accelerator: numpy serves
            msg = f"{mech.name}: {label} kernel not built: {exc}"
            warnings.warn(msg, KernelWarning, stacklevel=stacklevel)
            continue
        if kernel is not None:
            return kernel
    return None


#: per plant, per controller: the right-hand side kernel, or None
_serial: weakref.WeakKeyDictionary[Mechanism, weakref.WeakKeyDictionary[object, SerialRHS | None]]
_serial = weakref.WeakKeyDictionary()


_K = TypeVar("_K")
#: per plant, per controller: the closed right-hand side kernel, or None
_closed: weakref.WeakKeyDictionary[Mechanism, weakref.WeakKeyDictionary[object, ClosedRHS | None]]
_closed = weakref.WeakKeyDictionary()


def serial_rhs(plant: Mechanism, controller: object) -> SerialRHS | None:
    """The right-hand side kernel of ``plant`` under ``controller`` (first provider that
    has one), or None when kernels are disabled or none applies. Built on the first
    request (compiled, or loaded from the disk cache), then cached per pair."""
    return _pair_kernel(_serial, "serial_rhs", plant, controller)


def closed_rhs(plant: Mechanism, controller: object) -> ClosedRHS | None:
    """The closed right-hand side kernel of ``plant`` under ``controller``, as
    :func:`serial_rhs`."""
    return _pair_kernel(_closed, "closed_rhs", plant, controller)


def _pair_kernel(
    cache: weakref.WeakKeyDictionary[Mechanism, weakref.WeakKeyDictionary[object, _K | None]],
    kind: str,
    plant: Mechanism,
    controller: object,
) -> _K | None:
    if not _enabled:
        return None
    with _lock:
        per_plant = cache.setdefault(plant, weakref.WeakKeyDictionary())
        if controller not in per_plant:
            per_plant[controller] = _first_pair_kernel(kind, plant, controller)
        return per_plant[controller]


def _first_pair_kernel(kind: str, plant: Mechanism, controller: object) -> Any:
    label = f"{kind.split('_')[0]} right-hand side"  # the Python hot path serves
    return first_kernel(kind, label, plant, controller, stacklevel=5)


__all__ = [
    "DISABLE_ENV",
    "GROUP",
    "BoundClosedRHS",
    "ClosedRHS",
    "ClosureNewton",
    "ForwardOutcome",
    "KernelProvider",
    "KernelWarning",
    "NewtonOutcome",
    "SerialRHS",
    "closed_rhs",
    "closure_newton",
    "disabled",
    "enabled",
    "first_kernel",
    "providers",
    "serial_rhs",
    "set_enabled",
    "warm",
]
