"""The kernel kind ``serial_branches``: every checked branch of a serial inverse in one call.

A provider of :mod:`rcm_pin.model.kernels` may answer ``serial_branches(mech)`` with a
:class:`SerialBranches` kernel: for a pose value of ``mech.output`` it returns what the
numpy route of :func:`rcm_pin.inverse` finds (the family's closed-form branches, fitted
into the joint limits, each checked by forward kinematics: output value, residual, limit
flag), as arrays (:class:`BranchArrays`), or None where it cannot reproduce that route (a
degenerate pose, a branch that misses the target, anything not finite); the caller then
runs the numpy route from the same inputs, which raises the typed errors. Kernels are
looked up once per Mechanism (cached with it) and follow the switches of
:mod:`rcm_pin.model.kernels` (``RCM_PIN_NO_KERNELS=1``, :func:`~rcm_pin.model.kernels.disabled`).
"""

from __future__ import annotations

import threading
import weakref
from collections.abc import Sequence
from typing import NamedTuple, Protocol

import numpy as np

from rcm_pin.model import kernels
from rcm_pin.model.mechanism import Mechanism


class BranchArrays(NamedTuple):
    """Every branch of one target, checked: ``q`` (B, n) [rad, m], ``output`` (B, size)
    (the values at q), ``residual`` (B) max |e| [m, rad], ``within_limits`` (B), the
    branch ``labels`` and the ``method`` text of the result."""

    q: np.ndarray
    output: np.ndarray
    residual: list[float]
    within_limits: Sequence[bool]
    labels: tuple[str, ...]
    method: str


class SerialBranches(Protocol):
    """The checked branches of a serial inverse problem for ``mech.output``."""

    def __call__(self, value: np.ndarray) -> BranchArrays | None:
        """The numpy route's branches for an output value ((size,), validated except for
        the test of R: ``inverse`` leaves that to the kernel, which declines an R farther
        from SO(3) than ``rcm_pin.analysis.pose_target.KEEP_TOL`` or with det R ≤ 0, as
        ``plain_pose`` would), or None where the kernel cannot reproduce them (the
        caller runs the numpy route)."""
        ...


_cache: weakref.WeakKeyDictionary[Mechanism, SerialBranches | None] = weakref.WeakKeyDictionary()
_calls: weakref.WeakKeyDictionary[Mechanism, int] = weakref.WeakKeyDictionary()
_lock = threading.Lock()

#: Requests of a Mechanism answered None (its numpy route) before the kernel is looked up:
#: finding and loading it costs 70-80 ms (CasADi, ``ocp.kernels``, the entry points), the
#: numpy route ~70 us more per call than the kernel, so a one-shot ``inverse`` (the CLI, a
#: script) never pays the import and a loop pays it once it has made this many calls.
WARM_CALLS = 100


def serial_branches(mech: Mechanism) -> SerialBranches | None:
    """The branch kernel of ``mech`` (first provider that has one), or None when kernels
    are disabled, none applies, or ``mech`` has made fewer than :data:`WARM_CALLS`
    requests (the numpy route serves them: same results). Then built once and cached;
    :func:`warm` builds it at once."""
    if not kernels.enabled():
        return None
    try:
        return _cache[mech]
    except KeyError:
        pass
    with _lock:
        seen = _calls.get(mech, 0)
        _calls[mech] = seen + 1
    return warm(mech) if seen >= WARM_CALLS else None


def warm(mech: Mechanism) -> SerialBranches | None:
    """Build (or look up) the branch kernel of ``mech`` now; None if none applies."""
    with _lock:
        if mech not in _cache:
            _cache[mech] = _first(mech)
        return _cache[mech]


def _first(mech: Mechanism) -> SerialBranches | None:
    kernel: SerialBranches | None = kernels.first_kernel("serial_branches", "serial branches", mech)
    return kernel


__all__ = ["BranchArrays", "SerialBranches", "serial_branches", "warm"]
