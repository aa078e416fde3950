"""Constrained dynamics of closed mechanisms and their inverse dynamics.

Equations of motion of the cut-open tree with closure forces λ and drive torques τ::

    M(q) q̈ + b(q, q̇) = Sᵀ τ + J_cᵀ λ               (n equations)  [N·m]
    J_c q̈ + γ(q, q̇) = −2ζω ċ − ω² c                 (m closure rows, Baumgarte-stabilised)

with S the selection of the driven joints, J_c the world-frame closure Jacobian restricted
to each closure's structurally non-zero rows (``Closure.world_rows``: a planar loop keeps
its in-plane rows), c the world residual p_a − p_b (and, for 6d closures, the rotation
difference) and γ = J̇_c q̇ the relative classical acceleration of the closure frames at
q̈ = 0 (Pinocchio ``getFrameClassicalAcceleration``). Forward dynamics solves the KKT
system; :func:`pin_constraint_dynamics` is the second route through
``pin.constraintDynamics`` on the same closures (``pin.RigidConstraintModel``).

Inverse dynamics (computed torque). For a desired output acceleration ẍ_d the joint
acceleration solves the square system [J_c; J_x] q̈ = [−γ − Baumgarte; ẍ_d − J̇_x q̇]
(regular away from type 1), and then [Sᵀ  J_cᵀ] [τ; λ] = M q̈ + b gives the drive
torques; that n × n matrix is singular exactly at the type-2 singularities of the chosen
drive set, where |τ| grows as 1/distance.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from rcm_pin.dynamics.tree import mass_matrix_pin
from rcm_pin.model.constraints import constraint_models
from rcm_pin.model.loops import LWA
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.newton import constraint_rank
from rcm_pin.model.output import Output
from rcm_pin.rotations import MAX_ABS


def _vector(mech: Mechanism, x: object, name: str, n: int) -> np.ndarray:
    """``x`` as a checked float vector (n,): a float64 array of that shape with finite
    entries below :data:`rcm_pin.rotations.MAX_ABS` passes through without a copy (one
    ``math.hypot``, the hot path of the simulations); anything else goes through
    :meth:`Mechanism.check_q`, which raises the typed error (wrong length, NaN, strings)."""
    exact = isinstance(x, np.ndarray) and x.shape == (n,) and x.dtype == np.float64
    if exact and type(x) is np.ndarray and math.hypot(*x) <= MAX_ABS:
        return x
    return mech.check_q(x, name, n)


def _state(mech: Mechanism, q: object, v: object) -> tuple[np.ndarray, np.ndarray]:
    """Checked (q (nq,), v (nv,)) in Pinocchio's order."""
    return _vector(mech, q, "q", mech.model.nq), _vector(mech, v, "v", mech.model.nv)


def world_closure(mech: Mechanism, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, ...]:
    """World closure residual c (m,), Jacobian J_c (m, nv), drift γ = J̇_c v (m,).

    Raises:
        InvalidInputError: q or v of the wrong length, not numeric, NaN or too large.
    """
    q, v = _state(mech, q, v)
    model, data = mech.model, mech.data
    pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    cs, js, gs = [], [], []
    for c in mech.require_loops().closures:
        fa, fb, rows = c.frame_a_id, c.frame_b_id, list(c.world_rows)
        oMa, oMb = data.oMf[fa], data.oMf[fb]
        ja = pin.getFrameJacobian(model, data, fa, LWA)
        jb = pin.getFrameJacobian(model, data, fb, LWA)
        aa = pin.getFrameClassicalAcceleration(model, data, fa, LWA)
        ab = pin.getFrameClassicalAcceleration(model, data, fb, LWA)
        if c.kind == "3d":
            cs.append((oMa.translation - oMb.translation)[rows])
            js.append((ja - jb)[rows])
            gs.append((aa.linear - ab.linear)[rows])
        else:
            err = np.r_[oMa.translation - oMb.translation, pin.log3(oMa.rotation @ oMb.rotation.T)]
            cs.append(err[rows])
            js.append((ja - jb)[rows])
            gs.append((aa.vector - ab.vector)[rows])
    return np.concatenate(cs), np.vstack(js), np.concatenate(gs)


def output_motion(
    mech: Mechanism, q: np.ndarray, v: np.ndarray, output: Output | None = None
) -> tuple[np.ndarray, ...]:
    """Output value x (k,), rate ẋ = J_x v, Jacobian J_x (k, nv) and drift J̇_x v (k,),
    all from one kinematics pass at (q, v)."""
    q, v = _state(mech, q, v)
    model, data = mech.model, mech.data
    out = mech.output if output is None else output
    pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    jx = pin.getFrameJacobian(model, data, out.frame_id, LWA)[out.rows]
    acc = pin.getFrameClassicalAcceleration(model, data, out.frame_id, LWA).vector
    return out.value(data.oMf[out.frame_id]), jx @ v, jx, acc[out.rows]


def output_drift(
    mech: Mechanism, q: np.ndarray, v: np.ndarray, output: Output | None = None
) -> tuple[np.ndarray, ...]:
    """Output rate ẋ = J_x v, Jacobian J_x (k, nv) and drift J̇_x v (k,) of the output frame."""
    return output_motion(mech, q, v, output)[1:]


def forward_dynamics(
    mech: Mechanism,
    q: np.ndarray,
    v: np.ndarray,
    tau_full: np.ndarray,
    baumgarte: tuple[float, float] = (50.0, 1.0),
) -> tuple[np.ndarray, ...]:
    """Constrained forward dynamics (KKT) with Baumgarte stabilisation (ω [rad/s], ζ).

    Args:
        tau_full: generalised joint torques (nv,) [N·m] (Sᵀτ).

    Returns:
        (q̈ (nv,) [rad/s²], closure forces λ (m,) [N]).

    Raises:
        InvalidInputError: q, v or tau_full of the wrong length, not numeric, NaN or too
            large.
    """
    q, v = _state(mech, q, v)
    tau_full = _vector(mech, tau_full, "tau_full", mech.model.nv)
    c, jc, gam = world_closure(mech, q, v)
    m_mat = mass_matrix_pin(mech.model, mech.data, q)
    b = pin.nonLinearEffects(mech.model, mech.data, q, v)
    w, z = baumgarte
    rhs_c = -gam - 2.0 * z * w * (jc @ v) - w * w * c
    n, m = mech.model.nv, len(c)
    # redundant closure rows (over-constrained loops: eye_4dof 11 rows of rank 8) make
    # the KKT matrix singular: solve on an independent set Uᵣᵀ J_c, λ = Uᵣ λᵣ
    basis, rank = np.eye(m), constraint_rank(jc)
    if rank < m:
        basis = np.linalg.svd(jc)[0][:, :rank]
    jr, r = basis.T @ jc, basis.shape[1]
    kkt = np.zeros((n + r, n + r))
    kkt[:n, :n], kkt[:n, n:], kkt[n:, :n] = m_mat, -jr.T, jr
    sol = np.linalg.solve(kkt, np.concatenate([tau_full - b, basis.T @ rhs_c]))
    return sol[:n], basis @ sol[n:]


def pin_constraint_dynamics(
    mech: Mechanism, q: np.ndarray, v: np.ndarray, tau_full: np.ndarray
) -> np.ndarray:
    """q̈ from ``pin.constraintDynamics`` on the mechanism's closures (route 2).

    Planar 3-D contacts are rank deficient (zero out-of-plane rows); the proximal solver
    handles that. Baumgarte terms are zero, so compare on closed configurations.
    """
    q, v = _state(mech, q, v)
    tau_full = _vector(mech, tau_full, "tau_full", mech.model.nv)
    model = mech.model
    data = model.createData()
    cms = pin.StdVec_RigidConstraintModel()
    cdatas = pin.StdVec_RigidConstraintData()
    for cm in constraint_models(model, mech.require_loops()):
        cms.append(cm)
        cdatas.append(cm.createData())
    pin.initConstraintDynamics(model, data, cms, cdatas)
    settings = pin.ProximalSettings(1e-14, 1e-10, 200)
    return pin.constraintDynamics(model, data, q, v, tau_full, cms, cdatas, settings)


def drive_columns(mech: Mechanism, actuated: Sequence[str] | None) -> np.ndarray:
    """v indices of a drive set (default: the mechanism's drives)."""
    loops = mech.require_loops()
    return loops.drive_v if actuated is None else mech.joint_v(actuated)


def inverse_dynamics(
    mech: Mechanism,
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
    q, v = _state(mech, q, v)
    a = _vector(mech, a, "a", mech.model.nv)
    idx = drive_columns(mech, actuated)
    _, jc, _ = world_closure(mech, q, v)
    rhs = pin.rnea(mech.model, mech.data, q, v, a)
    n = mech.model.nv
    mat = np.zeros((n, n))
    mat[idx, np.arange(len(idx))] = 1.0
    mat[:, len(idx) :] = jc.T
    sol = np.linalg.solve(mat, rhs)
    return sol[: len(idx)], sol[len(idx) :]


def acceleration_for_output(
    mech: Mechanism,
    q: np.ndarray,
    v: np.ndarray,
    xdd: np.ndarray,
    baumgarte: tuple[float, float] = (50.0, 1.0),
    output: Output | None = None,
) -> np.ndarray:
    """Joint acceleration q̈ (nv,) that closes the loops and gives output acceleration ẍ_d."""
    q, v = _state(mech, q, v)
    xdd = _vector(mech, xdd, "xdd", len((mech.output if output is None else output).rows))
    c, jc, gam = world_closure(mech, q, v)
    _, jx, drift = output_drift(mech, q, v, output)
    w, z = baumgarte
    rhs = np.concatenate([-gam - 2.0 * z * w * (jc @ v) - w * w * c, xdd - drift])
    return np.linalg.solve(np.vstack([jc, jx]), rhs)


def velocity_for_output(
    mech: Mechanism, q: np.ndarray, xd: np.ndarray, output: Output | None = None
) -> np.ndarray:
    """Joint rates q̇ (nv,) with J_c q̇ = 0 and J_x q̇ = ẋ (regular across type 2; the
    minimum-norm solution where redundant closure rows or a self-motion make the system
    non-square)."""
    q = _vector(mech, q, "q", mech.model.nq)
    xd = _vector(mech, xd, "xd", len((mech.output if output is None else output).rows))
    _, jc, _ = world_closure(mech, q, np.zeros(mech.model.nv))
    _, jx, _ = output_drift(mech, q, np.zeros(mech.model.nv), output)
    a, b = np.vstack([jc, jx]), np.concatenate([np.zeros(len(jc)), xd])
    if a.shape[0] == a.shape[1]:
        return np.linalg.solve(a, b)
    return np.linalg.lstsq(a, b, rcond=None)[0]


__all__ = [
    "acceleration_for_output",
    "drive_columns",
    "forward_dynamics",
    "inverse_dynamics",
    "output_drift",
    "output_motion",
    "pin_constraint_dynamics",
    "velocity_for_output",
    "world_closure",
]
