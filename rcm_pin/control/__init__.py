"""Control: one computed-torque law (:mod:`.computed_torque`) for a tool frame or a loop
output, its task kinematics (:mod:`.task`), references (:mod:`.references`) and one
``simulate`` (:mod:`.simulate`) for serial and closed mechanisms, with plots
(:mod:`.plots`), the linear error dynamics it is checked against (:mod:`.linear`), the
capabilities (:mod:`.capabilities`), scenarios (:mod:`.scenario`) and the programmable-RCM
task and loop (:mod:`.rcm_task`, :mod:`.rcm_loop`). The re-exports are the public API of the
layer (``docs/api.md``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from rcm_pin.lazy import keep_functions, lazy_exports

if TYPE_CHECKING:
    from rcm_pin.control.capabilities import (
        DefaultScenarios,
        FrameJacobianTask,
        ScenarioSource,
        StopCondition,
        StopEvent,
        TaskKinematics,
        TaskModel,
        pinocchio_task,
        scenario_source,
        task_model,
    )
    from rcm_pin.control.computed_torque import (
        ComputedTorque,
        DriveSwitching,
        Gains,
        drive_limits,
    )
    from rcm_pin.control.linear import (
        error_response,
        linear_error,
    )
    from rcm_pin.control.plots import (
        plot_deviation,
        plot_efforts,
        plot_phase,
    )
    from rcm_pin.control.rcm_loop import (
        RcmRun,
        track,
    )
    from rcm_pin.control.rcm_task import (
        RcmState,
        RcmTool,
        line_distance,
        make_tool,
        rcm_state,
        trocar_point,
        update_kinematics,
    )
    from rcm_pin.control.references import (
        TRAJECTORIES,
        CartesianTrajectory,
        CircleWithAngle,
        QuinticPath,
        get_trajectory,
    )
    from rcm_pin.control.result import (
        SimulationResult,
    )
    from rcm_pin.control.scenario import (
        Scenario,
        home_circle,
        scenarios,
    )
    from rcm_pin.control.scenario import (
        run as run_scenario,
    )
    from rcm_pin.control.simulate import (
        simulate,
    )
    from rcm_pin.control.simulation_options import SimulationOptions

#: The re-exports, imported on first access (PEP 562): the families import
#: :mod:`.references` at start-up, which must not load the whole control layer.
_LAZY = {
    "CartesianTrajectory": "references",
    "CircleWithAngle": "references",
    "ComputedTorque": "computed_torque",
    "DefaultScenarios": "capabilities",
    "DriveSwitching": "computed_torque",
    "FrameJacobianTask": "capabilities",
    "Gains": "computed_torque",
    "QuinticPath": "references",
    "RcmRun": "rcm_loop",
    "RcmState": "rcm_task",
    "RcmTool": "rcm_task",
    "Scenario": "scenario",
    "ScenarioSource": "capabilities",
    "SimulationOptions": "simulation_options",
    "SimulationResult": "result",
    "StopCondition": "capabilities",
    "StopEvent": "capabilities",
    "TRAJECTORIES": "references",
    "TaskKinematics": "capabilities",
    "TaskModel": "capabilities",
    "drive_limits": "computed_torque",
    "error_response": "linear",
    "get_trajectory": "references",
    "home_circle": "scenario",
    "line_distance": "rcm_task",
    "linear_error": "linear",
    "make_tool": "rcm_task",
    "pinocchio_task": "capabilities",
    "plot_deviation": "plots",
    "plot_efforts": "plots",
    "plot_phase": "plots",
    "rcm_state": "rcm_task",
    "run_scenario": "scenario:run",
    "scenario_source": "capabilities",
    "scenarios": "scenario",
    "simulate": "simulate",
    "task_model": "capabilities",
    "track": "rcm_loop",
    "trocar_point": "rcm_task",
    "update_kinematics": "rcm_task",
}


__getattr__, __dir__ = lazy_exports(__name__, _LAZY)


# ``rcm_pin.control.simulate`` is the function, as with an eager re-export.
keep_functions(__name__, {"simulate"})

__all__ = [
    "TRAJECTORIES",
    "CartesianTrajectory",
    "CircleWithAngle",
    "ComputedTorque",
    "DefaultScenarios",
    "DriveSwitching",
    "FrameJacobianTask",
    "Gains",
    "QuinticPath",
    "RcmRun",
    "RcmState",
    "RcmTool",
    "Scenario",
    "ScenarioSource",
    "SimulationOptions",
    "SimulationResult",
    "StopCondition",
    "StopEvent",
    "TaskKinematics",
    "TaskModel",
    "drive_limits",
    "error_response",
    "get_trajectory",
    "home_circle",
    "line_distance",
    "linear_error",
    "make_tool",
    "pinocchio_task",
    "plot_deviation",
    "plot_efforts",
    "plot_phase",
    "rcm_state",
    "run_scenario",
    "scenario_source",
    "scenarios",
    "simulate",
    "task_model",
    "track",
    "trocar_point",
    "update_kinematics",
]
