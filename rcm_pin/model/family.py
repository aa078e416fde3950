"""What a mechanism family may know beyond its URDF: the hooks generic code asks for.

Generic algorithms (``rcm_pin.analysis``, ``dynamics``, ``control``, ``viz``) never test a
mechanism's name. They ask the mechanism's :class:`Family` for a hook; a hook that returns
``None`` means "this family has no closed form here", and the generic numeric route runs.
Each family module in ``rcm_pin.mechanisms`` subclasses :class:`Family` and overrides the
hooks its papers give (the paper's A and B matrices, named singularity causes, ...).
Concerns moved to typed capabilities (position problems, reference poses, task kinematics,
scenarios and stop events, workspace, design metrics, mesh folders) are listed in
:attr:`Family.capabilities` instead, each resolved by the layer that consumes it.

The base class is also the family of a URDF loaded by path that names no family.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np

if TYPE_CHECKING:
    from rcm_pin.model.mechanism import Mechanism


T = TypeVar("T")


@dataclass(frozen=True)
class Branch:
    """One closed-form solution of a position problem.

    Attributes:
        q: Mechanism coordinates (n,) [rad, m] (for closed mechanisms a seed that the
            generic code polishes on Pinocchio's closures).
        label: branch / working-mode label (e.g. ``"+-+"``, ``"branch 3"``).
    """

    q: np.ndarray
    label: str


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


class Family:
    """Base family: no closed forms, every hook answers ``None`` (numeric routes)."""

    name = "generic"
    description = "any URDF: numeric routes only"
    #: Whether the family's mechanisms have loop closures.
    closed = False

    #: The family's implementations of capabilities the consuming layers define (e.g.
    #: ``rcm_pin.analysis.capabilities.PositionSolver``); each layer's resolver takes the
    #: one here or its numeric default. ``model`` knows none of their types.
    capabilities: tuple[object, ...] = ()

    def capability(self, kind: type[T]) -> T | None:
        """The family's implementation of capability ``kind`` (None: the layer's default)."""
        return next((c for c in self.capabilities if isinstance(c, kind)), None)

    # ---------------------------------------------------------------- named poses
    def configurations(self, mech: Mechanism) -> dict[str, np.ndarray]:
        """Named configurations (Mechanism coordinates); ``home`` is the default pose."""
        return {}

    # ------------------------------------------------------- velocity and singularity
    def ab_matrices(self, mech: Mechanism, q: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
        """The paper's A, B (A ẋ = −B q̇_a) at a closed configuration, from its equations,
        rows and columns scaled so that their determinants are dimensionless (for the
        singular verdicts; −A⁻¹B of the scaled matrices is not the output Jacobian)."""
        return None

    def singularity_causes(self, mech: Mechanism, q: np.ndarray) -> list[Cause] | None:
        """Named singularity causes at q (empty list: regular); None: none known."""
        return None

    def singularity_map(self, mech: Mechanism, **options: Any) -> dict[str, Any] | None:
        """A vectorised closed-form map of the singularity measures over the workspace."""
        return None

    # ---------------------------------------------------------------- accuracy
    def accuracy_parameters(self, mech: Mechanism) -> tuple[str, ...]:
        """xacro arguments that enter the kinematics (design-error variables)."""
        return ()

    def accuracy_report(self, mech: Mechanism, q: np.ndarray) -> dict[str, Any] | None:
        """The family's own accuracy table (None: the generic placement sensitivities)."""
        return None


__all__ = ["Branch", "Cause", "Family"]
