"""Control: one computed-torque law (:mod:`.computed_torque`) for a tool frame or a loop
output, its task kinematics (:mod:`.task`), references (:mod:`.references`) and one
``simulate`` (:mod:`.simulate`) for serial and closed mechanisms, with plots
(:mod:`.plots`) and the linear error dynamics it is checked against (:mod:`.linear`)."""

from rcm_pin.control.computed_torque import ComputedTorque, DriveSwitching, Gains, drive_limits
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
