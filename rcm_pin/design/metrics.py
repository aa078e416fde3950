"""The design metrics of a family: its MetricSource, else none.

:func:`metric_source` returns the family's :class:`~rcm_pin.interfaces.design.MetricSource`
(listed in ``Family.capabilities``), else :class:`NoMetrics` (a study refuses the family).
"""

from __future__ import annotations

from rcm_pin.interfaces.design import DesignMetric, MetricSource
from rcm_pin.model.family import Family


class NoMetrics(MetricSource):
    """The default: no metrics (``rcm-pin sweep`` says the family has none)."""

    def metrics(self) -> dict[str, DesignMetric]:
        return {}


NO_METRICS = NoMetrics()


def metric_source(family: Family) -> MetricSource:
    """The family's :class:`MetricSource`, else :class:`NoMetrics`."""
    return family.capability(MetricSource) or NO_METRICS  # type: ignore[type-abstract]


__all__ = ["NoMetrics", "metric_source"]
