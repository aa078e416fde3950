"""What a mechanism family may know beyond its URDF: named configurations and capabilities.

Generic algorithms (``rcm_pin.analysis``, ``dynamics``, ``control``, ``viz``) never test a
mechanism's name. Each family module in ``rcm_pin.mechanisms`` subclasses :class:`Family`,
names its configurations (``home`` and others; :mod:`rcm_pin.model.configurations` holds
the one default) and lists its implementations of the capabilities the consuming layers
define (``capabilities``: analytic position problems, reference poses, the paper's A and B
matrices and named singularity causes, accuracy tables, workspace figures, task
kinematics, scenarios and stop events, design metrics, mesh folders); each layer's
resolver returns the family's implementation or its numeric default behind the same ABC.

The base class is also the family of a URDF loaded by path that names no family.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, TypeVar

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


class Family:
    """Base family: no named configurations, no capabilities (numeric defaults everywhere)."""

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


__all__ = ["Branch", "Family"]
