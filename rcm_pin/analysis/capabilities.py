"""Capabilities the analysis layer consumes, each with its one resolver and numeric default.

A family provides an implementation of a capability or nothing (``Family.capabilities``);
:func:`position_solver` returns the family's implementation, else :class:`NumericPosition`,
behind the same ABC, so :func:`rcm_pin.forward` and :func:`rcm_pin.inverse` have one path.
A family's solver subclasses :class:`NumericPosition` and calls ``super()`` where it has no
closed form (e.g. an output subset its formulas do not cover).
"""

from __future__ import annotations

import copy
from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np

from rcm_pin.analysis import closed_position as cp
from rcm_pin.analysis.serial_ik import N_STARTS, numeric_inverse
from rcm_pin.model.configurations import mid_range
from rcm_pin.model.family import Branch
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output

SERIAL_CLOSED_FORM = "closed form, checked by Pinocchio forward kinematics"
CLOSED_SEEDS = "closed-form seeds + Newton polish on Pinocchio closures"


@dataclass(frozen=True)
class Branches:
    """Candidate solutions of an inverse problem (polished and checked by the caller).

    Attributes:
        branches: the candidates (closed: seeds of the Newton polish).
        method: how they were found (reported in :class:`PositionResult`).
        closed_form: whether they are distinct by construction (else deduplicated).
    """

    branches: tuple[Branch, ...]
    method: str
    closed_form: bool

    @classmethod
    def of(cls, mech: Mechanism, branches: list[Branch]) -> Branches:
        """A family's closed-form branches, with the method text of its kind."""
        method = SERIAL_CLOSED_FORM if mech.loops is None else CLOSED_SEEDS
        return cls(tuple(branches), method, True)


@dataclass(frozen=True)
class Assemblies:
    """Seeds of the direct problem of a closed mechanism (full q, one per assembly mode)."""

    seeds: tuple[np.ndarray, ...]
    method: str

    @classmethod
    def of(cls, seeds: list[np.ndarray]) -> Assemblies:
        """A family's closed-form assembly modes."""
        return cls(tuple(seeds), "closed-form seeds + Newton on Pinocchio closures")


class PositionSolver(ABC):
    """The position problems' candidates for one mechanism (the generic code polishes them)."""

    @abstractmethod
    def inverse(self, mech: Mechanism, target: np.ndarray, output: Output) -> Branches:
        """Every candidate for an output value (``output`` may be a subset)."""

    @abstractmethod
    def direct(self, mech: Mechanism, drives: np.ndarray) -> Assemblies:
        """Closed mechanisms: seeds of every assembly mode for drive values."""

    @abstractmethod
    def mode_labels(self, mech: Mechanism) -> tuple[str, ...]:
        """Labels of the working modes :meth:`inverse` returns, in order (empty: numbered)."""


class NumericPosition(PositionSolver):
    """The default: multistart bounded least squares (serial), multistart Newton on the
    closures (closed).

    Attributes:
        starts: starts of the multistart (None: :data:`~rcm_pin.analysis.serial_ik.N_STARTS`
            serial, 96 closed); :meth:`with_starts` sets it.
    """

    starts: int | None = None

    def with_starts(self, starts: int) -> NumericPosition:
        """A copy whose numeric multistart has ``starts`` starts."""
        new = copy.copy(self)
        new.starts = starts
        return new

    def inverse(self, mech: Mechanism, target: np.ndarray, output: Output) -> Branches:
        if mech.loops is None:
            found = numeric_inverse(mech, target, output, self.starts or N_STARTS)
            return Branches(tuple(found), "multistart least squares", False)
        seeds = cp.inverse_seeds(
            mech, target, output, **({"n_starts": self.starts} if self.starts else {})
        )
        return Branches(tuple(seeds), "multistart Newton", False)

    def direct(self, mech: Mechanism, drives: np.ndarray) -> Assemblies:
        return Assemblies(tuple(cp.multistart_seeds(mech, drives)), "multistart Newton")

    def mode_labels(self, mech: Mechanism) -> tuple[str, ...]:
        return ()


NUMERIC_POSITION = NumericPosition()


class ReferencePoses(ABC):
    """The configurations analyses start from (no magic keys of ``mech.configurations``)."""

    @abstractmethod
    def regular(self, mech: Mechanism) -> np.ndarray:
        """A regular configuration (off every singularity): singularity maps' base."""

    @abstractmethod
    def accuracy(self, mech: Mechanism) -> np.ndarray:
        """Where ``rcm-pin accuracy`` evaluates without ``--q``."""


class DefaultPoses(ReferencePoses):
    """The default: mid-range of the limits (serial) or ``mech.home`` (closed); accuracy at
    ``mech.home``."""

    def regular(self, mech: Mechanism) -> np.ndarray:
        return mid_range(mech) if mech.loops is None else mech.home

    def accuracy(self, mech: Mechanism) -> np.ndarray:
        return mech.home


DEFAULT_POSES = DefaultPoses()


def reference_poses(mech: Mechanism) -> ReferencePoses:
    """The family's :class:`ReferencePoses`, else :class:`DefaultPoses`."""
    return mech.family.capability(ReferencePoses) or DEFAULT_POSES  # type: ignore[type-abstract]


def position_solver(mech: Mechanism) -> PositionSolver:
    """The family's :class:`PositionSolver`, else :class:`NumericPosition`."""
    return mech.family.capability(PositionSolver) or NUMERIC_POSITION  # type: ignore[type-abstract]


__all__ = [
    "Assemblies",
    "Branches",
    "DefaultPoses",
    "NumericPosition",
    "PositionSolver",
    "ReferencePoses",
    "position_solver",
    "reference_poses",
]
