"""Generic planar-linkage math shared by the mechanism families (pure numpy, no names).

* :mod:`.fourbar`: the planar four-bar O1–A–B–O2 in closed form: positions, Grashof class,
  dead centres, transmission angle, time ratio (:class:`FourBar`, :func:`performance`);
* :mod:`.synthesis`: the four-bar from the two extreme rocker positions, every real root
  (:func:`synthesize`).

This layer sits between :mod:`rcm_pin.mechanisms` and :mod:`rcm_pin.control`: families use
it; it knows no mechanism, URDF or Pinocchio model.
"""

from __future__ import annotations

from rcm_pin.linkage.fourbar import FourBar, Performance, performance
from rcm_pin.linkage.synthesis import Root, synthesize

__all__ = ["FourBar", "Performance", "Root", "performance", "synthesize"]
