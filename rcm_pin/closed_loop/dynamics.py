"""Constrained dynamics and closed-loop computed torque.

Equations of motion of the cut-open tree with closure forces λ and drive torques τ::

    M(q) q̈ + b(q, q̇) = Sᵀ τ + J_cᵀ λ               (n equations)  [N·m]
    J_c q̈ + γ(q, q̇) = −2ζω ċ − ω² c                 (m closure rows, Baumgarte-stabilised)

with S the selection of the driven joints, J_c the world-frame in-plane closure Jacobian,
c the world residual p_a − p_b and γ = J̇_c q̇ the relative classical acceleration of the
closure points at q̈ = 0 (Pinocchio ``getFrameClassicalAcceleration``). Forward dynamics
solves the KKT system; :func:`pin_constraint_dynamics` is the second route through
``pin.constraintDynamics`` on the same RigidConstraintModels (3-D contacts, proximal solver).

Inverse dynamics (computed torque). For a desired output acceleration ẍ_d (paper 004:
ẍ_d = ẍ_T + γ1 (ẋ_T − ẋ) + γ0 (x_T − x)), the joint acceleration solves the square system
[J_c; J_x] q̈ = [−γ; ẍ_d − J̇_x q̇] (regular away from type 1), and then
[Sᵀ  J_cᵀ] [τ; λ] = M q̈ + b gives the drive torques; that n × n matrix is singular exactly
at the type-2 singularities of the chosen drive set, where |τ| grows as 1/distance.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from rcm_pin.closed_loop.core import ClosedMechanism


def world_closure(mech: ClosedMechanism, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, ...]:
    """World in-plane closure residual c (m,), Jacobian J_c (m, n), drift γ = J̇_c v (m,)."""
    model, data = mech.model, mech.data
    pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    rows = [0, 1] if mech.plane_normal is not None else [0, 1, 2]
    cs, js, gs = [], [], []
    for fa, fb in mech._frame_ids:
        cs.append((data.oMf[fa].translation - data.oMf[fb].translation)[rows])
        ja = pin.getFrameJacobian(model, data, fa, pin.LOCAL_WORLD_ALIGNED)
        jb = pin.getFrameJacobian(model, data, fb, pin.LOCAL_WORLD_ALIGNED)
        js.append((ja - jb)[rows])
        aa = pin.getFrameClassicalAcceleration(model, data, fa, pin.LOCAL_WORLD_ALIGNED).linear
        ab = pin.getFrameClassicalAcceleration(model, data, fb, pin.LOCAL_WORLD_ALIGNED).linear
        gs.append((aa - ab)[rows])
    return np.concatenate(cs), np.vstack(js), np.concatenate(gs)


def output_drift(mech: ClosedMechanism, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, ...]:
    """Output rate ẋ = J_x v, Jacobian J_x (k, n) and drift J̇_x v (k,) of the output frame."""
    model, data = mech.model, mech.data
    pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    fid = mech.output_frame_id
    jx = pin.getFrameJacobian(model, data, fid, pin.LOCAL_WORLD_ALIGNED)[mech.out_rows]
    acc = pin.getFrameClassicalAcceleration(model, data, fid, pin.LOCAL_WORLD_ALIGNED).vector
    return jx @ v, jx, acc[mech.out_rows]


def forward_dynamics(
    mech: ClosedMechanism,
    q: np.ndarray,
    v: np.ndarray,
    tau_full: np.ndarray,
    baumgarte: tuple[float, float] = (50.0, 1.0),
) -> tuple[np.ndarray, ...]:
    """Constrained forward dynamics (KKT) with Baumgarte stabilisation (ω [rad/s], ζ).

    Args:
        tau_full: generalised joint torques (n,) [N·m] (Sᵀτ).

    Returns:
        (q̈ (n,) [rad/s²], closure forces λ (m,) [N]).
    """
    c, jc, gam = world_closure(mech, q, v)
    m_mat = pin.crba(mech.model, mech.data, q)
    m_mat = np.triu(m_mat) + np.triu(m_mat, 1).T
    b = pin.nonLinearEffects(mech.model, mech.data, q, v)
    w, z = baumgarte
    rhs_c = -gam - 2.0 * z * w * (jc @ v) - w * w * c
    n, m = mech.model.nv, len(c)
    kkt = np.zeros((n + m, n + m))
    kkt[:n, :n], kkt[:n, n:], kkt[n:, :n] = m_mat, -jc.T, jc
    sol = np.linalg.solve(kkt, np.concatenate([tau_full - b, rhs_c]))
    return sol[:n], sol[n:]


def pin_constraint_dynamics(
    mech: ClosedMechanism, q: np.ndarray, v: np.ndarray, tau_full: np.ndarray
) -> np.ndarray:
    """q̈ from ``pin.constraintDynamics`` on the mechanism's RigidConstraintModels (route 2).

    The planar 3-D contacts are rank deficient (zero out-of-plane rows); the proximal
    solver handles that. Baumgarte terms are zero, so compare on closed configurations.
    """
    model = mech.model
    data = model.createData()
    cdatas = pin.StdVec_RigidConstraintData()
    for cm in mech.constraint_models:
        cdatas.append(cm.createData())
    pin.initConstraintDynamics(model, data, mech.constraint_models, cdatas)
    settings = pin.ProximalSettings(1e-14, 1e-10, 200)
    return pin.constraintDynamics(
        model, data, q, v, tau_full, mech.constraint_models, cdatas, settings
    )


def inverse_dynamics(
    mech: ClosedMechanism,
    q: np.ndarray,
    v: np.ndarray,
    a: np.ndarray,
    actuated: Sequence[str] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Drive torques for a consistent acceleration a: [Sᵀ J_cᵀ][τ; λ] = M a + b.

    Args:
        actuated: drive set (default: the mechanism's driven joints).

    Returns:
        (τ (k,) [N·m], λ (m,) [N]); τ → ∞ at the type-2 singularities of that drive set.
    """
    idx = mech.joint_indices(actuated) if actuated is not None else mech.idx_driven
    _, jc, _ = world_closure(mech, q, v)
    rhs = pin.rnea(mech.model, mech.data, q, v, a)
    n = mech.model.nv
    mat = np.zeros((n, n))
    mat[idx, np.arange(len(idx))] = 1.0
    mat[:, len(idx) :] = jc.T
    sol = np.linalg.solve(mat, rhs)
    return sol[: len(idx)], sol[len(idx) :]


def acceleration_for_output(
    mech: ClosedMechanism,
    q: np.ndarray,
    v: np.ndarray,
    xdd: np.ndarray,
    baumgarte: tuple[float, float] = (50.0, 1.0),
) -> np.ndarray:
    """Joint acceleration q̈ (n,) that closes the loops and gives output acceleration ẍ_d."""
    c, jc, gam = world_closure(mech, q, v)
    _, jx, drift = output_drift(mech, q, v)
    w, z = baumgarte
    rhs = np.concatenate([-gam - 2.0 * z * w * (jc @ v) - w * w * c, xdd - drift])
    return np.linalg.solve(np.vstack([jc, jx]), rhs)


def velocity_for_output(mech: ClosedMechanism, q: np.ndarray, xd: np.ndarray) -> np.ndarray:
    """Joint rates q̇ (n,) with J_c q̇ = 0 and J_x q̇ = ẋ (regular across type 2)."""
    _, jc, _ = world_closure(mech, q, np.zeros(mech.model.nv))
    _, jx, _ = output_drift(mech, q, np.zeros(mech.model.nv))
    return np.linalg.solve(np.vstack([jc, jx]), np.concatenate([np.zeros(len(jc)), xd]))
