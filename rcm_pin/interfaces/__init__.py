"""What upper layers ask of a family: capability ABCs the families implement.

The design layer and the viewer sit above :mod:`rcm_pin.mechanisms` and consume what a
family knows; the families cannot import them. Each module here is such a consumer's
port: the ABC and its frozen result types (nothing else, no default), one module per
consumer. The consumer owns the resolver and the default behind the same ABC:

* :mod:`.design`: :class:`~rcm_pin.interfaces.design.MetricSource` and
  :class:`~rcm_pin.interfaces.design.DesignMetric`, resolved by
  :func:`rcm_pin.design.metrics.metric_source`;
* :mod:`.viz`: :class:`~rcm_pin.interfaces.viz.Assets`, resolved by
  :func:`rcm_pin.viz.assets.assets`.

A family lists its implementations in ``Family.capabilities``.
"""
