"""Symbolic forward kinematics and frame Jacobians of a joint tree (CasADi SX or MX).

The math, per joint ``i`` with parent ``lambda(i)``:

    liMi(theta) = jointPlacement_i * X_j(theta)        X_j: rotation about / shift along axis
    oMi         = oMi[lambda(i)] * liMi
    oMf         = oMi[parent(f)] * framePlacement_f

and the frame Jacobian (Pinocchio's LOCAL_WORLD_ALIGNED convention, rows [linear; angular])
sums, over every joint k supporting the frame, ``scaling_k`` times its column

    revolute:  [w_k x (p_f - p_k); w_k],   prismatic: [w_k; 0],   w_k = R_k axis_k

into the column of its primary coordinate ``idx_v``; LOCAL rotates both halves by R_f^T.
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from ocp.joints import FrameSpec, JointSpec

Sym = Any  # casadi.SX or casadi.MX (CasADi's stubs do not mix the two)
Pose = tuple[Sym, Sym]  # (R 3x3, p 3x1)


def skew(a: Sym | np.ndarray) -> Sym:
    """The cross-product matrix ``[a]x`` with ``[a]x b = a x b``."""
    return ca.vertcat(
        ca.horzcat(0, -a[2], a[1]), ca.horzcat(a[2], 0, -a[0]), ca.horzcat(-a[1], a[0], 0)
    )


def axis_rotation(axis: np.ndarray, c: Sym, s: Sym) -> Sym:
    """Rodrigues' rotation about a constant unit ``axis`` from ``c = cos``, ``s = sin``.

    Written as ``c (I - a a^T) + s [a]x + a a^T`` so that aligned axes constant-fold to the
    usual three-entry rotations.
    """
    aat = np.outer(axis, axis)
    return c * ca.DM(np.eye(3) - aat) + s * ca.DM(skew(axis)) + ca.DM(aat)


def joint_variables(specs: tuple[JointSpec, ...], q: Sym) -> list[tuple[Sym, Sym, Sym]]:
    """``(theta, cos theta, sin theta)`` of every joint (``theta`` is ``nan`` for
    continuous joints, whose angle is only defined through the (cos, sin) pair)."""
    out = []
    for s in specs:
        if s.kind == "revolute_unbounded":
            out.append((ca.DM(np.nan), q[s.idx_q], q[s.idx_q + 1]))
        else:
            theta = q[s.idx_q] if s.scaling == 1.0 else s.scaling * q[s.idx_q]
            if s.offset != 0.0:
                theta = theta + s.offset
            out.append((theta, ca.cos(theta), ca.sin(theta)))
    return out


def joint_motion(spec: JointSpec, var: tuple[Sym, Sym, Sym]) -> Pose:
    """``X_j(theta)``: the placement produced by the joint variable alone."""
    theta, c, s = var
    if spec.kind == "prismatic":
        return ca.DM.eye(3), theta * ca.DM(spec.axis)
    return axis_rotation(spec.axis, c, s), ca.DM.zeros(3, 1)


def compose(a: Pose, b: Pose) -> Pose:
    """SE(3) product ``a * b``."""
    return ca.mtimes(a[0], b[0]), a[1] + ca.mtimes(a[0], b[1])


def local_placements(specs: tuple[JointSpec, ...], q: Sym) -> list[Pose]:
    """``liMi`` of every joint, in ``specs`` order."""
    out = []
    for spec, var in zip(specs, joint_variables(specs, q)):
        place = (ca.DM(spec.rotation), ca.DM(spec.translation))
        out.append(compose(place, joint_motion(spec, var)))
    return out


def world_placements(specs: tuple[JointSpec, ...], q: Sym) -> dict[int, Pose]:
    """``oMi`` keyed by Pinocchio joint id (0 = universe = identity)."""
    sym = type(q)
    oMi: dict[int, Pose] = {0: (sym.eye(3), sym.zeros(3, 1))}
    for spec, li in zip(specs, local_placements(specs, q)):
        oMi[spec.index] = compose(oMi[spec.parent], li)
    return oMi


def frame_placement(frame: FrameSpec, oMi: dict[int, Pose]) -> Pose:
    """``oMf`` of one frame."""
    return compose(oMi[frame.parent], (ca.DM(frame.rotation), ca.DM(frame.translation)))


def supports(specs: tuple[JointSpec, ...], joint_id: int) -> list[JointSpec]:
    """Joints on the path from the root to ``joint_id`` (inclusive), root first."""
    by_id = {s.index: s for s in specs}
    chain = []
    while joint_id != 0:
        chain.append(by_id[joint_id])
        joint_id = by_id[joint_id].parent
    return chain[::-1]


def frame_jacobian_world(
    specs: tuple[JointSpec, ...], frame: FrameSpec, nv: int, oMi: dict[int, Pose], p_f: Sym
) -> Sym:
    """6 x nv Jacobian of ``frame`` in LOCAL_WORLD_ALIGNED (rows: linear, angular)."""
    cols: list[Sym] = [type(p_f).zeros(6, 1) for _ in range(nv)]
    for s in supports(specs, frame.parent):
        r_k, p_k = oMi[s.index]
        w = ca.mtimes(r_k, ca.DM(s.axis))
        if s.kind == "prismatic":
            col = ca.vertcat(w, ca.DM.zeros(3, 1))
        else:
            col = ca.vertcat(ca.cross(w, p_f - p_k), w)
        cols[s.idx_v] = cols[s.idx_v] + (col if s.scaling == 1.0 else s.scaling * col)
    return ca.horzcat(*cols) if cols else type(p_f).zeros(6, 0)


def to_local(jac_world: Sym, rot: Sym) -> Sym:
    """LOCAL_WORLD_ALIGNED -> LOCAL: rotate linear and angular rows by ``R^T``."""
    rt = rot.T
    return ca.vertcat(ca.mtimes(rt, jac_world[:3, :]), ca.mtimes(rt, jac_world[3:, :]))


__all__ = [
    "axis_rotation",
    "compose",
    "frame_jacobian_world",
    "frame_placement",
    "joint_motion",
    "joint_variables",
    "local_placements",
    "skew",
    "supports",
    "to_local",
    "world_placements",
]
