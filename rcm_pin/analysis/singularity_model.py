"""The singularity capability: one resolver, the numeric default behind the same ABC.

A family's :class:`SingularityModel` gives the paper's A and B (dimensionless determinants
for the singular verdicts), named singularity causes and a vectorised workspace map of the
determinants; :func:`singularity_model` returns it, else :class:`NumericSingularity`
(Pinocchio's A and B from the closure Jacobian, no named causes, the inverse problem in
every grid cell). A family's model subclasses the default and overrides what it knows.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np

from rcm_pin.analysis.loop_velocity import velocity_matrices
from rcm_pin.analysis.position import inverse
from rcm_pin.errors import InvalidInputError, RcmPinError
from rcm_pin.model.mechanism import Mechanism


@dataclass(frozen=True)
class Cause:
    """A named singularity of a family at a configuration.

    Attributes:
        name: identifier (e.g. ``tool_centre_at_A``).
        description: what happens.
        condition: the equation of the singular set.
        tasks: the Jacobians it makes rank-deficient (``full``, ``position``).
        rank_loss: rank lost in the full Jacobian (alone).
    """

    name: str
    description: str
    condition: str
    tasks: tuple[str, ...]
    rank_loss: int


@dataclass(frozen=True)
class ABMatrices:
    """A, B of A ẋ = −B q̇_a at a closed configuration.

    Attributes:
        A: (k, k) output matrix.
        B: (k, k) drive matrix.
        paper: from the family's equations, rows and columns scaled so that the
            determinants are dimensionless (−A⁻¹B of the scaled matrices is not the output
            Jacobian); False: Pinocchio's A, B (:func:`.loop_velocity.velocity_matrices`),
            whose determinants carry units and are not reported.
    """

    A: np.ndarray
    B: np.ndarray
    paper: bool

    @property
    def det_A(self) -> float | None:
        """Normalised det A of the paper's matrices (None: Pinocchio's, no verdict)."""
        return float(np.linalg.det(self.A)) if self.paper else None

    @property
    def det_B(self) -> float | None:
        """Normalised det B of the paper's matrices (None: Pinocchio's, no verdict)."""
        return float(np.linalg.det(self.B)) if self.paper else None


@dataclass(frozen=True)
class DetMap:
    """det A and det B (or the numeric measures) of one working mode over an x-y grid.

    Attributes:
        x: (n,) grid abscissae [m].
        y: (n,) grid ordinates [m].
        det_a: det A (n, n) indexed [iy, ix]; NaN outside the workspace.
        det_b: det B (n, n) likewise.
        mode: the working mode's label (or its index as text).
        phi: the fixed orientation [rad] (None: the output has none).
    """

    x: np.ndarray
    y: np.ndarray
    det_a: np.ndarray
    det_b: np.ndarray
    mode: str
    phi: float | None

    def to_dict(self) -> dict[str, object]:
        """The keys of ``rcm-pin singularities --grid`` (closed), in its order."""
        return {
            "x": self.x,
            "y": self.y,
            "det_A": self.det_a,
            "det_B": self.det_b,
            "mode": self.mode,
            "phi": self.phi,
        }


class SingularityModel(ABC):
    """What a family knows about its singularities (the generic code reports them)."""

    @abstractmethod
    def ab_matrices(self, mech: Mechanism, q: np.ndarray) -> ABMatrices:
        """A and B at a closed configuration q."""

    @abstractmethod
    def causes(self, mech: Mechanism, q: np.ndarray) -> tuple[Cause, ...]:
        """Named singularity causes at q (empty: regular or none known)."""

    @abstractmethod
    def workspace_map(self, mech: Mechanism, mode: int, phi: float, n: int) -> DetMap:
        """det A / det B of working mode ``mode`` over an n × n grid of the first two
        output coordinates (the others at ``phi``)."""


class NumericSingularity(SingularityModel):
    """The default: Pinocchio's A and B, no named causes, a map of Pinocchio's measures
    (σ_min/σ_max of A and B) from the inverse problem in every cell."""

    def ab_matrices(self, mech: Mechanism, q: np.ndarray) -> ABMatrices:
        vm = velocity_matrices(mech, q)
        return ABMatrices(vm.A, vm.B, paper=False)

    def causes(self, mech: Mechanism, q: np.ndarray) -> tuple[Cause, ...]:
        return ()

    def workspace_map(self, mech: Mechanism, mode: int, phi: float, n: int) -> DetMap:
        loops = mech.require_loops()
        out = loops.output
        translations = ("x", "y", "z")
        if out.size < 2 or out.coords[0] not in translations or out.coords[1] not in translations:
            raise InvalidInputError(
                f"{mech.name}: a workspace map needs two translation outputs first; it has "
                f"{list(out.coords)}"
            )
        reach = 2.0 * loops.length_scale * max(len(loops.legs), 1)
        x = np.linspace(-reach, reach, n)
        y = np.linspace(-reach, reach, n)
        da, db = np.full((n, n), np.nan), np.full((n, n), np.nan)
        for iy, yy in enumerate(y):
            for ix, xx in enumerate(x):
                target = np.r_[xx, yy, np.full(out.size - 2, phi)]
                try:
                    sols = inverse(mech, target).solutions
                except RcmPinError:
                    continue
                if mode < len(sols):
                    vm = velocity_matrices(mech, sols[mode].q)
                    da[iy, ix], db[iy, ix] = vm.measure_type2, vm.measure_type1
        return DetMap(x, y, da, db, str(mode), phi)


NUMERIC_SINGULARITY = NumericSingularity()


def singularity_model(mech: Mechanism) -> SingularityModel:
    """The family's :class:`SingularityModel`, else :class:`NumericSingularity`."""
    return mech.family.capability(SingularityModel) or NUMERIC_SINGULARITY  # type: ignore[type-abstract]


__all__ = [
    "ABMatrices",
    "Cause",
    "DetMap",
    "NumericSingularity",
    "SingularityModel",
    "singularity_model",
]
