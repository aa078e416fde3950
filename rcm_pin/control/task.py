"""Task kinematics for the control law: the family's closed form, or Pinocchio.

A task is a subset of a serial mechanism's output coordinates (e.g. the tool position
x, y, z). :func:`task_kinematics` returns the family's closed form when it has one (the
RCM mechanisms' p = q3·e4) and otherwise the Pinocchio route:

    x = frame position rows,   J = LOCAL_WORLD_ALIGNED frame Jacobian rows,
    J̇ q̇ = classical frame acceleration at q̈ = 0.

Tests check that the two routes agree where both exist.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError
from rcm_pin.model.family import TaskKinematics
from rcm_pin.model.loops import LWA
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output


def pinocchio_task(mech: Mechanism, task: Output) -> TaskKinematics:
    """Task kinematics of any serial mechanism from Pinocchio (module docstring)."""
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
    """The family's closed form of the task, else :func:`pinocchio_task`."""
    return mech.family.task_kinematics(mech, task) or pinocchio_task(mech, task)


__all__ = ["pinocchio_task", "task_kinematics", "task_output"]
