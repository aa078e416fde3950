"""The closed-plant right-hand side as one named SX ``casadi.Function`` (:func:`build`).

The math of :mod:`ocp.kernels.closed_rhs` (its docstring), written in the order of
:class:`rcm_pin.control.closed_hot_path.ClosedLaw` and
:class:`~rcm_pin.control.closed_hot_path.ClosedPlant`; :func:`structure_key` is the text
that determines it (the compile-cache key).
"""

from __future__ import annotations

import hashlib
from typing import Any

import casadi as ca
import numpy as np

from ocp.closure import log3
from ocp.kernels.digest import source_digest
from ocp.kernels.serial_rhs import _inertias
from ocp.symbolic import SymbolicModel
from rcm_pin.control.computed_torque import ComputedTorque
from rcm_pin.model.loops import Loops
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output

#: Rows of a planar angle: atan2(R[i, j], R[j, j]) (:meth:`rcm_pin.model.output.Output.value`).
_ANGLE = {"rx": (2, 1), "ry": (0, 2), "rz": (1, 0)}
_ROW = {"x": 0, "y": 1, "z": 2}


def closure_rows(sm: SymbolicModel, loops: Loops, q: Any, v: Any) -> tuple[Any, Any, Any]:
    """(c (m,), J_c (m, nv), γ = J̇_c q̇ (m,)) of the closures (module docstring)."""
    cs, js = [], []
    for c in loops.closures:
        rows = list(c.world_rows)
        p_a, r_a = sm.frame_placement(c.frame_a_id)(q)
        p_b, r_b = sm.frame_placement(c.frame_b_id)(q)
        j_ab = sm.frame_jacobian(c.frame_a_id)(q) - sm.frame_jacobian(c.frame_b_id)(q)
        err = p_a - p_b if c.kind == "3d" else ca.vertcat(p_a - p_b, log3(r_a @ r_b.T))
        cs.append(err[rows])
        js.append(j_ab[rows, :])
    c_all, j_c = ca.vertcat(*cs), ca.vertcat(*js)
    return c_all, j_c, ca.jtimes(j_c @ v, q, v)


def task_rows(sm: SymbolicModel, out: Output, q: Any, v: Any) -> tuple[Any, Any, Any]:
    """(x (dim,), J_x (dim, nv), J̇_x q̇ (dim,)) of an output (module docstring)."""
    p, r = sm.frame_placement(out.frame_id)(q)
    x = []
    for c in out.coords:
        if c in _ROW:
            x.append(p[_ROW[c]])
        else:
            i, j = _ANGLE[c]
            x.append(ca.atan2(r[i, j], r[j, j]))
    j_x = sm.frame_jacobian(out.frame_id)(q)[out.rows.tolist(), :]
    return ca.vertcat(*x), j_x, ca.jtimes(j_x @ v, q, v)


def _wrap(angle: Any) -> Any:
    """[−π, π) wrap of :func:`rcm_pin.rotations.wrap_angle` (numpy's float remainder)."""
    two_pi = 2.0 * np.pi
    r = ca.fmod(angle + np.pi, two_pi)
    return ca.if_else(r < 0, r + two_pi, r) - np.pi


def _cholesky(m: Any) -> list[list[Any]]:
    """The lower factor L (rows of SX scalars) of a symmetric positive definite m = L Lᵀ."""
    n = m.shape[0]
    low: list[list[Any]] = [[ca.SX(0)] * n for _ in range(n)]
    for j in range(n):
        low[j][j] = ca.sqrt(m[j, j] - sum((low[j][k] ** 2 for k in range(j)), ca.SX(0)))
        for i in range(j + 1, n):
            acc = m[i, j] - sum((low[i][k] * low[j][k] for k in range(j)), ca.SX(0))
            low[i][j] = acc / low[j][j]
    return low


def _chol_solve(low: list[list[Any]], rhs: Any) -> Any:
    """(L Lᵀ)⁻¹ rhs (rhs: n × p) by forward and back substitution."""
    n = len(low)
    y: list[Any] = []
    for i in range(n):
        y.append((rhs[i, :] - sum((low[i][k] * y[k] for k in range(i)), ca.SX(0))) / low[i][i])
    x: list[Any] = [None] * n
    for i in reversed(range(n)):
        x[i] = (y[i] - sum((low[k][i] * x[k] for k in range(i + 1, n)), ca.SX(0))) / low[i][i]
    return ca.vertcat(*x)


def rank_guard(j_c: Any) -> Any:
    """‖R‖_F ‖R⁻¹‖_F ≥ σ₁/σ_min(J_c) with J_cᵀ = Q R (module docstring)."""
    _, r = ca.qr(j_c.T)
    return ca.norm_fro(r) * ca.norm_fro(ca.solve(r, ca.SX.eye(r.shape[0])))


def build(plant: Mechanism, controller: ComputedTorque, name: str) -> ca.Function:
    """The SX right-hand side (module docstring) of ``plant`` under ``controller``."""
    mech, task = controller.model, controller.task_output
    loops, plant_loops = mech.loops, plant.loops
    assert loops is not None and plant_loops is not None
    n, dim, drive_v = plant.nv, task.dim, [int(i) for i in loops.drive_v]
    k = len(drive_v)
    y, r, p = ca.SX.sym("y", 2 * n), ca.SX.sym("r", 3 * dim), ca.SX.sym("p", 7 + k)
    q, v = y[:n], y[n:]
    x_t, xd_t, xdd_t = r[:dim], r[dim : 2 * dim], r[2 * dim :]
    kpos, kc, ff, w, z, w_p, z_p, tau_max = p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7:]
    # the law on the controller's model
    sm = SymbolicModel(mech.model)
    c, j_c, gam = closure_rows(sm, loops, q, v)
    x, j_x, drift = task_rows(sm, task, q, v)
    e = x_t - x
    for i in np.flatnonzero(task.angular):
        e[int(i)] = ca.if_else(ca.fabs(e[int(i)]) > np.pi, _wrap(e[int(i)]), e[int(i)])
    a_star = ff * xdd_t + kpos * e + kc * (xd_t - j_x @ v)
    rhs_law = ca.vertcat(-gam - 2.0 * z * w * (j_c @ v) - w * w * c, a_star - drift)
    acc = ca.solve(ca.vertcat(j_c, j_x), rhs_law)
    tau = sm.rnea()(q, v, acc)
    select = ca.DM.zeros(n, k)
    for col, row in enumerate(drive_v):
        select[row, col] = 1.0
    raw = ca.solve(ca.horzcat(select, j_c.T), tau)[:k]
    tau_d = ca.fmin(ca.fmax(raw, -tau_max), tau_max)
    tau_full = select @ tau_d
    # the plant's KKT forward dynamics by its Schur complement
    same = plant is mech
    plant_sm = sm if same else SymbolicModel(plant.model)
    c_p, j_p, gam_p = (c, j_c, gam) if same else closure_rows(plant_sm, plant_loops, q, v)
    x_p, j_xp, _ = (x, j_x, None) if same else task_rows(plant_sm, task, q, v)
    mass = plant_sm.mass_matrix()(q)
    b = plant_sm.nonlinear_effects()(q, v)
    rhs_c = -gam_p - 2.0 * z_p * w_p * (j_p @ v) - w_p * w_p * c_p
    low = _cholesky(mass)
    m_inv = _chol_solve(low, ca.horzcat(tau_full - b, j_p.T))  # M⁻¹ [τ − b, J_cᵀ]
    a_free, m_inv_jt = m_inv[:, 0], m_inv[:, 1:]
    schur = j_p @ m_inv_jt
    lam = _chol_solve(_cholesky(schur), rhs_c - j_p @ a_free)
    qdd = a_free + m_inv_jt @ lam
    return ca.Function(
        name,
        [y, r, p],
        [ca.vertcat(v, qdd), tau_d, raw, x_p, j_xp @ v, rank_guard(j_p)],
        ["y", "r", "p"],
        ["ydot", "tau", "raw", "x", "xd", "guard"],
        {"cse": True},
    )


def structure_key(plant: Mechanism, controller: ComputedTorque) -> str:
    """What determines the function: both models, their closures, drives and the task."""
    import pinocchio as pin

    mech, task = controller.model, controller.task_output
    parts = [_SOURCES, str(pin.__version__)]
    for m in (plant, mech):
        loops = m.loops
        assert loops is not None
        parts += [m.model.__str__(), _inertias(m), str(loops.drive_v.tolist())]
        parts += [f"{c.kind}|{c.frame_a_id}|{c.frame_b_id}|{c.world_rows}" for c in loops.closures]
    parts += [str(plant is mech), str(task.frame_id), str(task.coords), str(task.rows.tolist())]
    return hashlib.sha256("\0".join(parts).encode()).hexdigest()


def _sources() -> str:
    """Digest of the code that writes the function (a change rebuilds the cache)."""
    import ocp.closure
    import ocp.dynamics
    import ocp.joints
    import ocp.kinematics
    import ocp.symbolic

    mods = (ocp.closure, ocp.dynamics, ocp.joints, ocp.kinematics, ocp.symbolic)
    return source_digest(__file__, mods)


_SOURCES = _sources()


__all__ = ["build", "closure_rows", "rank_guard", "structure_key", "task_rows"]
