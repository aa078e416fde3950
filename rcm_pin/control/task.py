"""Task kinematics for the control law: the family's closed form, or Pinocchio.

A task is a subset of a serial mechanism's output coordinates (e.g. the tool position
x, y, z). :func:`task_kinematics` asks the family's
:class:`~rcm_pin.control.capabilities.TaskModel` (the RCM mechanisms' p = q3·e4), else
the default, Pinocchio's frame Jacobian route
(:func:`~rcm_pin.control.capabilities.pinocchio_task`).

Tests check that the two routes agree where both exist.
"""

from __future__ import annotations

from rcm_pin.control.capabilities import TaskKinematics, task_model
from rcm_pin.errors import InvalidInputError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output


def task_output(mech: Mechanism, coords: tuple[str, ...] | None) -> Output:
    """The control task: the given output coordinates, by default the tool position
    (serial) or the loop output (closed).

    Raises:
        InvalidInputError: a ``rotation`` task (the law works on vector coordinates).
    """
    default = ("x", "y", "z") if mech.loops is None else mech.output.coords
    task = mech.output.subset(tuple(coords) if coords is not None else default)
    if "rotation" in task.coords:
        raise InvalidInputError(
            f"task {list(task.coords)}: the computed-torque law tracks vector coordinates; "
            "valid: x, y, z and planar angles rx, ry, rz"
        )
    return task


def task_kinematics(mech: Mechanism, task: Output) -> TaskKinematics:
    """The kinematics of the task by the mechanism's :class:`TaskModel`
    (:func:`~rcm_pin.control.capabilities.task_model`)."""
    return task_model(mech).kinematics(mech, task)


__all__ = ["task_kinematics", "task_output"]
