"""Control: one computed-torque law (:mod:`.computed_torque`) for a tool frame or a loop
output, its task kinematics (:mod:`.task`), references (:mod:`.references`) and one
``simulate`` (:mod:`.simulate`) for serial and closed mechanisms, with plots
(:mod:`.plots`) and the linear error dynamics it is checked against (:mod:`.linear`)."""

from __future__ import annotations

import sys
import types
from typing import TYPE_CHECKING

from rcm_pin.lazy import lazy_exports

if TYPE_CHECKING:
    from rcm_pin.control.computed_torque import (
        ComputedTorque,
        DriveSwitching,
        Gains,
        drive_limits,
    )
    from rcm_pin.control.linear import error_response, linear_error
    from rcm_pin.control.references import (
        TRAJECTORIES,
        CartesianTrajectory,
        CircleWithAngle,
        QuinticPath,
        get_trajectory,
    )
    from rcm_pin.control.result import SimulationResult
    from rcm_pin.control.simulate import simulate

#: The re-exports, imported on first access (PEP 562): the families import
#: :mod:`.references` at start-up, which must not load the whole control layer.
_LAZY = {
    "TRAJECTORIES": "references",
    "CartesianTrajectory": "references",
    "CircleWithAngle": "references",
    "ComputedTorque": "computed_torque",
    "DriveSwitching": "computed_torque",
    "Gains": "computed_torque",
    "QuinticPath": "references",
    "SimulationResult": "result",
    "drive_limits": "computed_torque",
    "error_response": "linear",
    "get_trajectory": "references",
    "linear_error": "linear",
    "simulate": "simulate",
}


__getattr__, __dir__ = lazy_exports(__name__, _LAZY)


class _Package(types.ModuleType):
    """``rcm_pin.control.simulate`` is the function, as with the eager re-export: the
    import system sets a loaded submodule as an attribute of its package, which would
    otherwise shadow the function of the same name."""

    def __setattr__(self, name: str, value: object) -> None:
        if name == "simulate" and isinstance(value, types.ModuleType):
            value = value.simulate
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package

__all__ = [
    "TRAJECTORIES",
    "CartesianTrajectory",
    "CircleWithAngle",
    "ComputedTorque",
    "DriveSwitching",
    "Gains",
    "QuinticPath",
    "SimulationResult",
    "drive_limits",
    "error_response",
    "get_trajectory",
    "linear_error",
    "simulate",
]
