"""Symbolic rigid-body dynamics on a joint tree with mimic couplings.

Every joint has one scalar variable; with ``G`` the mimic coupling (``theta_dot = G v``)
the dynamics of the independent coordinates are the projection of the tree's:

    tau = G^T tau_tree(theta, G v, G a) + armature * a          (RNEA)
    M   = G^T M_tree(theta) G + diag(armature)                  (CRBA)
    qdd = M^{-1} (tau - b),   b = RNEA(q, v, 0)                 (forward dynamics)

which is what Pinocchio computes on a model parsed with ``mimic=True``. Spatial vectors
are pairs of 3-vectors expressed in the joint frame: motions ``(v, w)``, forces ``(f, n)``.
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np
import pinocchio as pin

from ocp.joints import JointSpec
from ocp.kinematics import Pose, Sym, local_placements, skew

Vec6 = tuple[Sym, Sym]


def motion_inv(m: Pose, x: Vec6) -> Vec6:
    """Motion in the parent frame -> child frame ``m = liMi``: ``liMi^{-1} . x``."""
    r, p = m
    return ca.mtimes(r.T, x[0] - ca.cross(p, x[1])), ca.mtimes(r.T, x[1])


def force_act(m: Pose, f: Vec6) -> Vec6:
    """Force in the child frame -> parent frame: ``liMi . f``."""
    r, p = m
    lin = ca.mtimes(r, f[0])
    return lin, ca.mtimes(r, f[1]) + ca.cross(p, lin)


def motion_cross(a: Vec6, b: Vec6) -> Vec6:
    """``a x b`` for motions."""
    return ca.cross(a[1], b[0]) + ca.cross(a[0], b[1]), ca.cross(a[1], b[1])


def force_cross(a: Vec6, f: Vec6) -> Vec6:
    """``a x* f`` (motion acting on force)."""
    return ca.cross(a[1], f[0]), ca.cross(a[1], f[1]) + ca.cross(a[0], f[0])


def inertia_apply(s: JointSpec, x: Vec6) -> Vec6:
    """Spatial inertia of the body of joint ``s`` applied to motion ``x``."""
    c = ca.DM(s.lever)
    lin = s.mass * (x[0] - ca.cross(c, x[1]))
    return lin, ca.mtimes(ca.DM(s.inertia), x[1]) + ca.cross(c, lin)


def subspace(s: JointSpec) -> Vec6:
    """Motion subspace ``S`` (constant in the joint frame)."""
    a, z = ca.DM(s.axis), ca.DM.zeros(3, 1)
    return (a, z) if s.kind == "prismatic" else (z, a)


def _scaled(x: Vec6, k: Sym) -> Vec6:
    return x[0] * k, x[1] * k


def _add(a: Vec6, b: Vec6) -> Vec6:
    return a[0] + b[0], a[1] + b[1]


def _dot(a: Vec6, b: Vec6) -> Sym:
    return ca.dot(a[0], b[0]) + ca.dot(a[1], b[1])


def rnea(
    specs: tuple[JointSpec, ...], armature: np.ndarray, gravity: np.ndarray, q: Sym, v: Sym, a: Sym
) -> Sym:
    """Inverse dynamics ``tau(q, v, a)`` (nv x 1), gravity ``gravity`` (3,) in world."""
    sym = type(q)
    nv = v.shape[0]
    li = local_placements(specs, q)
    vel: dict[int, Vec6] = {0: (sym.zeros(3, 1), sym.zeros(3, 1))}
    acc: dict[int, Vec6] = {0: (ca.DM(-gravity), sym.zeros(3, 1))}
    force: dict[int, Vec6] = {}
    for s, m in zip(specs, li):
        sj = subspace(s)
        vj = _scaled(sj, s.scaling * v[s.idx_v])
        vel[s.index] = _add(motion_inv(m, vel[s.parent]), vj)
        acc[s.index] = _add(
            _add(motion_inv(m, acc[s.parent]), _scaled(sj, s.scaling * a[s.idx_v])),
            motion_cross(vel[s.index], vj),
        )
        force[s.index] = _add(
            inertia_apply(s, acc[s.index]),
            force_cross(vel[s.index], inertia_apply(s, vel[s.index])),
        )
    tau = [sym.zeros(1, 1) for _ in range(nv)]
    for s, m in reversed(list(zip(specs, li))):
        f = force[s.index]
        tau[s.idx_v] = tau[s.idx_v] + s.scaling * _dot(subspace(s), f)
        if s.parent != 0:
            force[s.parent] = _add(force[s.parent], force_act(m, f))
    out = ca.vertcat(*tau) if nv else sym.zeros(0, 1)
    return out + ca.DM(armature) * a if nv else out


def spatial_inertia(s: JointSpec) -> ca.DM:
    """6 x 6 spatial inertia of the body of joint ``s`` (rows/cols: linear, angular)."""
    cx = pin.skew(s.lever)
    top = np.hstack([s.mass * np.eye(3), -s.mass * cx])
    bottom = np.hstack([s.mass * cx, s.inertia - s.mass * cx @ cx])
    return ca.DM(np.vstack([top, bottom]))


def motion_inv_matrix(m: Pose) -> Sym:
    """6 x 6 matrix of :func:`motion_inv`; its transpose is the force transform."""
    r, p = m
    rt = r.T
    return ca.vertcat(ca.horzcat(rt, -ca.mtimes(rt, skew(p))), ca.horzcat(ca.DM.zeros(3, 3), rt))


def crba(specs: tuple[JointSpec, ...], armature: np.ndarray, q: Sym, nv: int) -> Sym:
    """Joint-space mass matrix (nv x nv, symmetric) by composite rigid bodies.

    Composite inertias ``Ic_i = I_i + sum_c X_c^T Ic_c X_c`` are summed leaves first; for
    each joint i the force ``F = Ic_i S_i`` is carried to the root and gives, at joint i
    itself, the diagonal term ``S_i^T F`` and at every strict ancestor j the term
    ``M[j, i] = S_j^T F`` (and its transpose), all scaled by the mimic multipliers and added
    into the primaries' entries (``G^T M_tree G``).
    """
    sym = type(q)
    li = dict(zip((s.index for s in specs), local_placements(specs, q)))
    xm = {i: motion_inv_matrix(m) for i, m in li.items()}
    by_id = {s.index: s for s in specs}
    ic: dict[int, Sym] = {s.index: spatial_inertia(s) for s in specs}
    for s in reversed(specs):
        if s.parent != 0:
            ic[s.parent] = ic[s.parent] + ca.mtimes([xm[s.index].T, ic[s.index], xm[s.index]])
    diag = sym.zeros(nv, nv)
    strict = sym.zeros(nv, nv)
    for s in specs:
        f = s.scaling * ca.mtimes(ic[s.index], _svec(s))
        diag[s.idx_v, s.idx_v] += s.scaling * ca.dot(_svec(s), f)
        j = s.index
        while by_id[j].parent != 0:
            f = ca.mtimes(xm[j].T, f)
            j = by_id[j].parent
            sj = by_id[j]
            strict[sj.idx_v, s.idx_v] += sj.scaling * ca.dot(_svec(sj), f)
    return strict + strict.T + diag + ca.diag(ca.DM(armature))


def _svec(s: JointSpec) -> Any:
    return ca.vertcat(*subspace(s))


def cholesky_solve(m: Sym, rhs: Sym) -> Sym:
    """``m^{-1} rhs`` by an unrolled symbolic Cholesky factorisation (m symmetric p.d.)."""
    n = m.shape[0]
    low: list[list[Any]] = [[None] * n for _ in range(n)]
    for j in range(n):
        d = m[j, j] - sum((low[j][k] ** 2 for k in range(j)), ca.DM(0))
        low[j][j] = ca.sqrt(d)
        for i in range(j + 1, n):
            acc = m[i, j] - sum((low[i][k] * low[j][k] for k in range(j)), ca.DM(0))
            low[i][j] = acc / low[j][j]
    y: list[Any] = []
    for i in range(n):
        y.append((rhs[i, :] - sum((low[i][k] * y[k] for k in range(i)), ca.DM(0))) / low[i][i])
    x: list[Any] = [None] * n
    for i in reversed(range(n)):
        x[i] = (y[i] - sum((low[k][i] * x[k] for k in range(i + 1, n)), ca.DM(0))) / low[i][i]
    return ca.vertcat(*x) if n else rhs


__all__ = ["cholesky_solve", "crba", "rnea"]
