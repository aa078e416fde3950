"""Design metrics: one number a family computes for a whole design (one Mechanism).

Design studies (:mod:`rcm_pin.design`) sweep xacro arguments and ask each design's family
for its metrics through its :class:`MetricSource` (resolved by
:func:`rcm_pin.design.metrics.metric_source`; the default has none). A metric is
deterministic (seeded samples only), so a design gives the same figure on any worker.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

if TYPE_CHECKING:
    from rcm_pin.model.mechanism import Mechanism

#: Whether a larger ("max") or a smaller ("min") value is the better design.
Goal = Literal["max", "min"]


@dataclass(frozen=True)
class DesignMetric:
    """One figure of merit of a design.

    Attributes:
        name: identifier used on the command line (``--metric NAME``).
        unit: unit of the value (``"-"`` for ratios).
        goal: ``"max"`` or ``"min"``: the direction an optimiser improves it in.
        description: what it measures and over which poses, with the formula.
        evaluate: Mechanism -> value (a float; vectorised over poses inside).
    """

    name: str
    unit: str
    goal: Goal
    description: str
    evaluate: Callable[[Mechanism], float]


class MetricSource(ABC):
    """A family's figures of merit of a whole design (:mod:`rcm_pin.design` sweeps them)."""

    @abstractmethod
    def metrics(self) -> dict[str, DesignMetric]:
        """The metrics by name (a fresh dict; empty: the family has none)."""


__all__ = ["DesignMetric", "Goal", "MetricSource"]
