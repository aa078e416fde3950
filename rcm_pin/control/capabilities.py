"""Capabilities the control layer consumes, each with its one resolver and default.

A family provides an implementation of a capability or nothing (``Family.capabilities``):

* :class:`TaskModel` (:func:`task_model`): the kinematics of a control task; default
  :class:`FrameJacobianTask`, Pinocchio's frame Jacobian route. A family's model subclasses
  it and calls ``super()`` where it has no closed form (another task, frame or size).
* :class:`ScenarioSource` (:func:`scenario_source`): the family's named simulation
  scenarios and the conditions that end a simulation; default :class:`DefaultScenarios`
  (none: :func:`rcm_pin.control.scenario.scenarios` adds ``home_circle`` for every
  mechanism, and no stop events).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
import pinocchio as pin

from rcm_pin.model.loops import LWA
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output

if TYPE_CHECKING:
    from rcm_pin.control.scenario import Scenario


#: g(t, q, v) of a stop condition: the run stops where it crosses 0.
EventFunction = Callable[[float, np.ndarray, np.ndarray], float]
#: What ``simulate(events=...)`` takes: (description, g); a :class:`StopEvent` is one.
StopCondition = tuple[str, EventFunction]


class StopEvent(NamedTuple):
    """A family's simulation stop condition: the run stops where ``g(t, q, v)`` crosses 0.

    ``q``, ``v``: the plant's Mechanism coordinates and velocities, serial or closed (a
    closed plant's full q), so an event applies to every plant of the family.
    """

    description: str
    g: EventFunction


@dataclass(frozen=True)
class TaskKinematics:
    """Kinematics of a task (output coordinates) over some coordinates.

    Attributes:
        joints: coordinate indices the task depends on (the others do not move it).
        position: q (n,) -> task value (dim,).
        jacobian: q -> ∂x/∂q_joints (dim, len(joints)).
        bias: (q, q̇) -> J̇ q̇ (dim,).
        inverse: task value -> q_joints of the principal branch (None: not available).
        batch: (q (N, n), q̇ (N, nv)) -> (x (N, dim), J (N, dim, len(joints)), J̇ q̇
            (N, dim)) vectorised over states, the same values as the three one-state
            functions (None: they are called per state).
        closed_form: the family's closed form (False: Pinocchio's frame Jacobian route).
    """

    joints: np.ndarray
    position: Callable[[np.ndarray], np.ndarray]
    jacobian: Callable[[np.ndarray], np.ndarray]
    bias: Callable[[np.ndarray, np.ndarray], np.ndarray]
    inverse: Callable[[np.ndarray], np.ndarray] | None = None
    batch: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]] | None = (
        None
    )
    closed_form: bool = False


class TaskModel(ABC):
    """The kinematics of a control task of one mechanism."""

    @abstractmethod
    def kinematics(self, mech: Mechanism, task: Output) -> TaskKinematics:
        """x, J, J̇ q̇ (and where known the inverse) of ``task`` on ``mech``."""


def pinocchio_task(mech: Mechanism, task: Output) -> TaskKinematics:
    """Task kinematics of any serial mechanism from Pinocchio:

    x = frame position rows,   J = LOCAL_WORLD_ALIGNED frame Jacobian rows,
    J̇ q̇ = classical frame acceleration at q̈ = 0.
    """
    model, fid, rows = mech.model, task.frame_id, task.rows

    def position(q: np.ndarray) -> np.ndarray:
        pin.forwardKinematics(model, mech.data, mech.to_pin(q))
        return task.value(pin.updateFramePlacement(model, mech.data, fid))

    def jacobian(q: np.ndarray) -> np.ndarray:
        pin.computeJointJacobians(model, mech.data, mech.to_pin(q))
        jac = pin.getFrameJacobian(model, mech.data, fid, LWA)
        return np.asarray(jac)[rows][:, mech.v_index]

    def bias(q: np.ndarray, v: np.ndarray) -> np.ndarray:
        data = mech.data
        pin.forwardKinematics(model, data, mech.to_pin(q), mech.v_pin(v), np.zeros(model.nv))
        pin.updateFramePlacements(model, data)
        acc = pin.getFrameClassicalAcceleration(model, data, fid, LWA).vector
        return np.asarray(acc)[rows]

    return TaskKinematics(np.arange(mech.nv), position, jacobian, bias, None)


class FrameJacobianTask(TaskModel):
    """The default: :func:`pinocchio_task` (any serial mechanism, any vector task)."""

    def kinematics(self, mech: Mechanism, task: Output) -> TaskKinematics:
        return pinocchio_task(mech, task)


FRAME_JACOBIAN_TASK = FrameJacobianTask()


class ScenarioSource(ABC):
    """A family's simulation scenarios and the conditions that end its simulations."""

    @abstractmethod
    def scenarios(self, mech: Mechanism) -> Mapping[str, Scenario]:
        """Named scenarios (:class:`rcm_pin.control.scenario.Scenario`), in order."""

    @abstractmethod
    def stop_events(self, mech: Mechanism) -> tuple[StopEvent, ...]:
        """Conditions that end a simulation of ``mech`` (leaving the regular region)."""


class DefaultScenarios(ScenarioSource):
    """The default: no family scenarios, no stop events."""

    def scenarios(self, mech: Mechanism) -> Mapping[str, Scenario]:
        return {}

    def stop_events(self, mech: Mechanism) -> tuple[StopEvent, ...]:
        return ()


DEFAULT_SCENARIOS = DefaultScenarios()


def task_model(mech: Mechanism) -> TaskModel:
    """The family's :class:`TaskModel`, else :class:`FrameJacobianTask`."""
    return mech.family.capability(TaskModel) or FRAME_JACOBIAN_TASK  # type: ignore[type-abstract]


def scenario_source(mech: Mechanism) -> ScenarioSource:
    """The family's :class:`ScenarioSource`, else :class:`DefaultScenarios`."""
    return mech.family.capability(ScenarioSource) or DEFAULT_SCENARIOS  # type: ignore[type-abstract]


__all__ = [
    "DefaultScenarios",
    "FrameJacobianTask",
    "ScenarioSource",
    "StopCondition",
    "StopEvent",
    "TaskKinematics",
    "TaskModel",
    "pinocchio_task",
    "scenario_source",
    "task_model",
]
