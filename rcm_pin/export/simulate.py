"""A scenario of ``rcm-pin simulate`` with MuJoCo as the plant (``--engine mujoco``).

The mechanism is exported (:func:`rcm_pin.export.to_mjcf`, its solver settings), started
at the scenario's start state, and driven by the same computed-torque law as the
Pinocchio run (:func:`rcm_pin.control.scenario.controller`, on rcm-pin's model), held
constant over each control period (zero-order hold, default 1 ms) and applied as
generalised forces (``qfrc_applied``) on the independent joints. The result is compared
with the Pinocchio run of the same scenario at its samples: the largest joint difference
and the largest equality residual of MuJoCo's run.
"""

from __future__ import annotations

import tempfile
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from rcm_pin.errors import InvalidInputError, require
from rcm_pin.export import check
from rcm_pin.export.mjcf import to_mjcf
from rcm_pin.model.mechanism import Mechanism


@dataclass(frozen=True)
class MujocoRun:
    """A scenario run on MuJoCo.

    Attributes:
        t: control times (N,) [s].
        q: coordinates at those times (N, n) [rad, m].
        timestep: MuJoCo's timestep [s].
        control_period: the zero-order hold of the law [s].
        max_equality_residual: largest |efc_pos| of the equalities over the run [m, rad].
        max_difference: largest |q_MuJoCo − q_Pinocchio| at the Pinocchio run's samples
            [rad, m] (None when not compared).
    """

    t: np.ndarray
    q: np.ndarray
    timestep: float
    control_period: float
    max_equality_residual: float
    max_difference: float | None

    def summary(self) -> dict[str, Any]:
        """JSON-able summary."""
        return {
            "engine": "mujoco",
            "duration": float(self.t[-1]),
            "timestep": self.timestep,
            "control_period": self.control_period,
            "max_equality_residual": self.max_equality_residual,
            "max_difference_from_pinocchio": self.max_difference,
        }


def _state(mj: check.MujocoModel, mech: Mechanism) -> tuple[np.ndarray, np.ndarray]:
    """rcm-pin coordinates and velocities of MuJoCo's state."""
    model, full = mech.model, mech.model_full
    q_pin, v_pin = np.zeros(model.nq), np.zeros(model.nv)
    for j in range(1, model.njoints):
        jm = model.joints[j]
        if jm.shortname() == "JointModelMimic" or jm.nv != 1:
            continue
        k = full.getJointId(model.names[j]) - 1
        angle = mj.data.qpos[mj.qpos[k]]
        if jm.nq == 2:
            q_pin[jm.idx_q : jm.idx_q + 2] = np.cos(angle), np.sin(angle)
        else:
            q_pin[jm.idx_q] = angle
        v_pin[jm.idx_v] = mj.data.qvel[mj.dof[full.joints[k + 1].idx_v]]
    return mech.from_pin(q_pin), v_pin[mech.v_index]


def simulate_mujoco(
    mech: Mechanism,
    scenario: Any,
    control_period: float = 1e-3,
    compare: Any = None,
    **law: Any,
) -> MujocoRun:
    """Run ``scenario`` (a :class:`rcm_pin.control.scenario.Scenario`) on MuJoCo.

    Args:
        control_period: zero-order hold of the law [s] (a multiple of the timestep).
        compare: a Pinocchio :class:`~rcm_pin.control.result.SimulationResult` of the same
            scenario to compare with (its samples).
        law: options of :func:`rcm_pin.control.scenario.controller`.

    Raises:
        MissingExtraError: MuJoCo is not installed.
        InvalidInputError: a control period that is not positive, or a run that diverges.
    """
    from rcm_pin.control.scenario import controller, start_state

    mujoco = require("mujoco", "mujoco")
    if not (np.isfinite(control_period) and control_period > 0):
        raise InvalidInputError(f"control period {control_period!r}; valid: a positive number")
    from rcm_pin.control.simulate import initial_state

    q0, v0 = start_state(mech, scenario)
    ctrl = controller(mech, scenario, **law)
    q0 = initial_state(mech, ctrl) if q0 is None else q0  # as rcm_pin.control.simulate does
    v0 = np.zeros(mech.nv) if v0 is None else v0
    with tempfile.TemporaryDirectory() as folder, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        export = to_mjcf(mech, Path(folder) / f"{mech.name}.xml")
        plant = export.mechanism
        mj = check.load_mujoco(export.path, plant)
    dt = export.settings.timestep
    hold = max(1, round(control_period / dt))
    check.set_state(mj, plant, mech.to_pin(q0), mech.v_pin(v0))
    eq = mujoco.mjtConstraint.mjCNSTR_EQUALITY
    own = _own_dofs(mj, mech)
    times, qs, worst = [], [], 0.0
    for i in range(round(scenario.duration / (hold * dt)) + 1):
        q, v = _state(mj, mech)
        times.append(i * hold * dt)
        qs.append(q)
        tau = mech.v_pin(ctrl.effort(times[-1], q, v).tau_full)
        mj.data.qfrc_applied[:] = 0.0
        mj.data.qfrc_applied[own[:, 1]] = tau[own[:, 0]]
        mujoco.mj_step(mj.model, mj.data, nstep=hold)
        worst = max(
            worst, float(np.max(np.abs(mj.data.efc_pos[mj.data.efc_type == eq]), initial=0))
        )
        if not np.all(np.isfinite(mj.data.qpos)):
            raise InvalidInputError(f"the MuJoCo run of {mech.name} diverged at {times[-1]:.3g} s")
    t, q_arr = np.array(times), np.array(qs)
    diff = None
    if compare is not None:
        inside = compare.t <= t[-1]
        interp = np.column_stack(
            [np.interp(compare.t[inside], t, q_arr[:, k]) for k in range(q_arr.shape[1])]
        )
        diff = float(np.max(np.abs(interp - compare.q[inside])))
    return MujocoRun(t, q_arr, dt, hold * dt, worst, diff)


def _own_dofs(mj: check.MujocoModel, mech: Mechanism) -> np.ndarray:
    """(pin v index, MuJoCo dof) of every independent one-DOF joint."""
    model, full = mech.model, mech.model_full
    pairs = []
    for j in range(1, model.njoints):
        jm = model.joints[j]
        if jm.shortname() != "JointModelMimic" and jm.nv == 1:
            jf = full.joints[full.getJointId(model.names[j])]
            pairs.append((jm.idx_v, int(mj.dof[jf.idx_v])))
    return np.array(pairs, dtype=int).reshape(-1, 2)


__all__ = ["MujocoRun", "simulate_mujoco"]
