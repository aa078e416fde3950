"""Paper 002's four-DOF eye linkage: the family's knowledge.

* :mod:`.closed_form`: every sub-linkage in closed form (pitch four-bar, yaw yoke,
  parallelogram, the Assur group E, F, U), the gaze angles;
* :mod:`.family`: the hooks (closed-form direct and inverse positions, ``home``);
* :mod:`.design`: the paper's design chains computed from its given dimensions (the pitch
  synthesis equations, the yaw crank, the support spacing, the slot length, the lid belt).

The four-bar math is :mod:`rcm_pin.linkage`.
"""

from __future__ import annotations

from rcm_pin.lazy import lazy_modules
from rcm_pin.mechanisms.eye_4dof.design import PAPER, EyeDesign
from rcm_pin.mechanisms.eye_4dof.family import FAMILY, MODES, EyeFamily, geometry

__all__ = ["FAMILY", "MODES", "PAPER", "EyeDesign", "EyeFamily", "geometry"]

# Each module of the family is an attribute of the package, imported on first access
# (``from rcm_pin.mechanisms import <family>`` is the public entry, docs/api.md).
__getattr__, __dir__ = lazy_modules(__name__, ("checks", "closed_form", "design", "family"))
