"""An exported MJCF file loaded in MuJoCo and compared with rcm-pin (the ``mujoco`` extra).

* :func:`tree_error`: MuJoCo's mass matrix (``mj_fullM``) and bias (``qfrc_bias``) of the
  no-mimic tree projected through the coupling (M = G_vᵀ M_full G_v, b = G_vᵀ b_full) against
  rcm-pin's mimic model;
* :func:`rigid_limit_error`: MuJoCo's M, bias, equality Jacobian ``efc_J`` and J̇v solved as a
  rigid KKT system, against rcm-pin's constrained forward dynamics. MuJoCo puts −J̇v into
  ``efc_aref = −B·efc_vel − K·imp·efc_pos − J̇v``, so −J̇v = aref + B·vel + K·imp·pos
  (``efc_KBIP``): a comparison without it is off by 1e-3 to 100 % of q̈;
* :func:`free_motion_drift`: the largest equality residual ``|efc_pos|`` of a free motion.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError, require
from rcm_pin.model.mechanism import Mechanism


@dataclass(frozen=True)
class MujocoModel:
    """A loaded MJCF file and the index maps from rcm-pin's no-mimic model.

    Attributes:
        model: ``mujoco.MjModel``.
        data: ``mujoco.MjData``.
        qpos: (n_joints,) MuJoCo qpos address of each one-DOF joint of the no-mimic model,
            in Pinocchio's joint order.
        dof: (nv_full,) MuJoCo dof address of each Pinocchio v index of the no-mimic model.
    """

    model: Any
    data: Any
    qpos: np.ndarray
    dof: np.ndarray


def load_mujoco(path: str | os.PathLike[str], mech: Mechanism) -> MujocoModel:
    """Load an MJCF file written by :func:`rcm_pin.export.to_mjcf` for ``mech``.

    Raises:
        MissingExtraError: MuJoCo is not installed (``pip install 'rcm-pin[mujoco]'``).
        InvalidInputError: MuJoCo refuses the file, or warns while loading it, or a joint of
            the mechanism is not in it.
    """
    mujoco = require("mujoco", "mujoco")
    try:
        model = mujoco.MjModel.from_xml_path(str(path))
    except ValueError as exc:
        raise InvalidInputError(f"MuJoCo refuses {str(path)!r}: {exc}") from None
    data = mujoco.MjData(model)
    full = mech.model_full
    qpos, dof = [], np.zeros(full.nv, dtype=int)
    for j in range(1, full.njoints):
        jid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, full.names[j])
        if jid < 0:
            raise InvalidInputError(f"joint {full.names[j]!r} is not in {str(path)!r}")
        qpos.append(int(model.jnt_qposadr[jid]))
        dof[full.joints[j].idx_v] = int(model.jnt_dofadr[jid])
    mujoco.mj_forward(model, data)
    if any(w.number for w in data.warning):
        raise InvalidInputError(f"MuJoCo warns on {str(path)!r}: {list(data.warning)}")
    return MujocoModel(model, data, np.array(qpos, dtype=int), dof)


def set_state(mj: MujocoModel, mech: Mechanism, q_pin: np.ndarray, v_pin: np.ndarray) -> None:
    """MuJoCo's qpos, qvel of rcm-pin's mimic-model state (q_full = G q + offset)."""
    full = mech.model_full
    qf, vf = mech.coupling.q_full(q_pin), mech.coupling.v_full(v_pin)
    for k, j in enumerate(range(1, full.njoints)):
        jm = full.joints[j]
        angle = qf[jm.idx_q] if jm.nq == 1 else np.arctan2(qf[jm.idx_q + 1], qf[jm.idx_q])
        mj.data.qpos[mj.qpos[k]] = angle
    mj.data.qvel[:] = 0.0
    mj.data.qvel[mj.dof] = vf


def _dense_m(mj: MujocoModel) -> np.ndarray:
    """MuJoCo's mass matrix in Pinocchio's no-mimic v order."""
    mujoco = require("mujoco", "mujoco")
    m_mat = np.zeros((mj.model.nv, mj.model.nv))
    if hasattr(mj.data, "qM"):  # MuJoCo 3: mj_fullM(m, dst, qM)
        mujoco.mj_fullM(mj.model, m_mat, mj.data.qM)
    else:  # MuJoCo 4: mj_fullM(m, d, dst)
        mujoco.mj_fullM(mj.model, mj.data, m_mat)
    return m_mat[np.ix_(mj.dof, mj.dof)]


def tree_error(mj: MujocoModel, mech: Mechanism, q_pin: np.ndarray, v_pin: np.ndarray) -> float:
    """max(|ΔM|/|M|, |Δb|/|b|) (Frobenius / 2-norms) of MuJoCo projected through the
    coupling against rcm-pin's mass matrix and nonlinear effects at (q, v)."""
    mujoco = require("mujoco", "mujoco")
    set_state(mj, mech, q_pin, v_pin)
    mujoco.mj_forward(mj.model, mj.data)
    gv = mech.coupling.Gv
    m_mj = gv.T @ _dense_m(mj) @ gv
    b_mj = gv.T @ mj.data.qfrc_bias[mj.dof]
    data = mech.model.createData()
    m_pin = pin.crba(mech.model, data, q_pin)
    m_pin = np.triu(m_pin) + np.triu(m_pin, 1).T
    b_pin = pin.nonLinearEffects(mech.model, data, q_pin, v_pin)
    em = np.linalg.norm(m_mj - m_pin) / np.linalg.norm(m_pin)
    eb = np.linalg.norm(b_mj - b_pin) / max(float(np.linalg.norm(b_pin)), 1e-300)
    return float(max(em, eb))


def rigid_acceleration(
    mj: MujocoModel,
    mech: Mechanism,
    q_pin: np.ndarray,
    v_pin: np.ndarray,
    tau: np.ndarray,
    jdot: bool = True,
) -> np.ndarray:
    """q̈ of the no-mimic tree (Pinocchio v order) from MuJoCo's M, bias, ``efc_J`` of the
    equality rows and −J̇v (module docstring), solved rigidly; τ (nv,) [N·m] on the mimic
    model's joints. ``jdot=False`` leaves −J̇v out (to show what it costs)."""
    mujoco = require("mujoco", "mujoco")
    set_state(mj, mech, q_pin, v_pin)
    mujoco.mj_forward(mj.model, mj.data)
    d = mj.data
    eq = np.flatnonzero(d.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY)
    jac = d.efc_J.reshape(d.nefc, mj.model.nv)[eq][:, mj.dof]
    kbip = d.efc_KBIP[eq]
    rhs = d.efc_aref[eq] + kbip[:, 1] * d.efc_vel[eq] + kbip[:, 0] * kbip[:, 2] * d.efc_pos[eq]
    norms = np.linalg.norm(jac, axis=1)
    keep = norms > 1e-12 * max(norms.max(initial=0.0), 1e-300)
    jac, rhs = jac[keep], rhs[keep] if jdot else np.zeros(int(keep.sum()))
    n, m = jac.shape[1], jac.shape[0]
    tau_full = np.zeros(n)  # τ on each independent joint's own dof, none on mimic joints
    model, full = mech.model, mech.model_full
    for j in range(1, model.njoints):
        jm, jf = model.joints[j], full.joints[full.getJointId(model.names[j])]
        if jm.nv == 1 and jm.shortname() != "JointModelMimic":
            tau_full[jf.idx_v] = tau[jm.idx_v]
    kkt = np.zeros((n + m, n + m))
    kkt[:n, :n], kkt[:n, n:], kkt[n:, :n] = _dense_m(mj), -jac.T, jac
    sol = np.linalg.lstsq(kkt, np.r_[tau_full - d.qfrc_bias[mj.dof], rhs], rcond=None)[0]
    return sol[:n]


def rigid_limit_error(
    mj: MujocoModel, mech: Mechanism, q_pin: np.ndarray, v_pin: np.ndarray, tau: np.ndarray
) -> float:
    """|q̈_MuJoCo − G_v q̈_rcm-pin| / |G_v q̈_rcm-pin| at a closed state (J_c v = 0), MuJoCo's
    rigid limit against :func:`rcm_pin.dynamics.constrained_forward_dynamics` (serial
    mechanisms: tree forward dynamics M⁻¹(τ − b)); redundant closure rows (eye_4dof,
    translational_3ppapa_loops) included: the KKT solve keeps an independent set."""
    acc_mj = rigid_acceleration(mj, mech, q_pin, v_pin, tau)
    if mech.loops is not None:
        from rcm_pin.dynamics.constrained import forward_dynamics

        acc = forward_dynamics(mech, q_pin, v_pin, tau)[0]
    else:
        data = mech.model.createData()
        m_pin = pin.crba(mech.model, data, q_pin)
        m_pin = np.triu(m_pin) + np.triu(m_pin, 1).T
        acc = np.linalg.solve(m_pin, tau - pin.nonLinearEffects(mech.model, data, q_pin, v_pin))
    ref = mech.coupling.v_full(acc)
    return float(np.linalg.norm(acc_mj - ref) / max(float(np.linalg.norm(ref)), 1e-300))


def free_motion_drift(
    mj: MujocoModel, mech: Mechanism, q_pin: np.ndarray, v_pin: np.ndarray, duration: float = 0.2
) -> float:
    """Largest equality residual max |efc_pos| [m or rad] over a free motion (no drive
    torque) of ``duration`` [s] from (q, v) with the file's solver settings."""
    mujoco = require("mujoco", "mujoco")
    set_state(mj, mech, q_pin, v_pin)
    mj.data.ctrl[:] = 0.0
    mj.data.time = 0.0
    worst = 0.0
    eq_type = mujoco.mjtConstraint.mjCNSTR_EQUALITY
    for _ in range(round(duration / mj.model.opt.timestep)):
        mujoco.mj_step(mj.model, mj.data)
        d = mj.data
        rows = d.efc_pos[d.efc_type == eq_type]
        worst = max(worst, float(np.max(np.abs(rows), initial=0.0)))
    if not np.all(np.isfinite(mj.data.qpos)):
        raise InvalidInputError(f"the free motion of {mech.name} diverged in MuJoCo")
    return worst


def random_states(
    mech: Mechanism, rng: np.random.Generator, n: int = 3
) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Seeded states (q, v, τ) of Pinocchio's model for the export checks: serial q inside
    the limits cut to ±2 [rad, m]; closed, assembled configurations near home (drives
    ±0.05 off) with J_c v = 0; |v| = 1, τ standard normal [N·m, N]."""
    from rcm_pin.analysis.position import forward
    from rcm_pin.dynamics.constrained import world_closure

    out = []
    home = mech.to_pin(mech.home)
    for k in range(n):
        if mech.loops is None:
            q = mech.to_pin(rng.uniform(np.maximum(mech.lower, -2), np.minimum(mech.upper, 2)))
            v = rng.normal(size=mech.model.nv)
        else:
            q = home
            if k:
                drives = home[mech.loops.drive_q] + rng.uniform(-0.05, 0.05, mech.loops.dof)
                sols = forward(mech, drives, q_guess=home).solutions
                q = sols[0].q if sols else home
            jac = world_closure(mech, q, np.zeros(mech.model.nv))[1]
            basis = np.linalg.svd(jac)[2][np.linalg.matrix_rank(jac) :]
            v = basis.T @ rng.normal(size=len(basis))
        out.append((q, v / np.linalg.norm(v), rng.normal(size=mech.model.nv)))
    return out


__all__ = [
    "MujocoModel",
    "free_motion_drift",
    "load_mujoco",
    "random_states",
    "rigid_acceleration",
    "rigid_limit_error",
    "set_state",
    "tree_error",
]
