"""The model layer: one :class:`Mechanism` for serial and closed mechanisms.

xacro rendering (:mod:`.render`) with its verified cache (:mod:`.render_cache`), ROS
packages without ROS (:mod:`.packages`) and mesh files (:mod:`.meshes`), the shipped
sources (:mod:`.resources`),
the mimic coupling (:mod:`.coupling`), output coordinates (:mod:`.output`), the
``<rcm_pin>`` element and YAML sidecar (:mod:`.sidecar`), loop closures (:mod:`.loops`)
and their rank-revealing Newton (:mod:`.newton`), family hooks (:mod:`.family`) and the
build from URDF text (:mod:`.build`).
"""

from rcm_pin.model.coupling import Coupling
from rcm_pin.model.family import Branch, Family
from rcm_pin.model.loops import Closure, Loops
from rcm_pin.model.mechanism import Mechanism, RcmSpec
from rcm_pin.model.output import Output

__all__ = [
    "Branch",
    "Closure",
    "Coupling",
    "Family",
    "Loops",
    "Mechanism",
    "Output",
    "RcmSpec",
]
