"""Screw-theory singularity test of paper 004 (the second route, independent of A and B).

Planar screws in world coordinates. A revolute pair at point r = (r_x, r_y) about the plane
normal has the unit kinematic screw (twist) ξ = (v_x, v_y, ω) = (r_y, −r_x, 1) (velocity of
the body point at the world origin, angular rate). A planar wrench w = (f_x, f_y, m_O)
(force and moment about the origin) is reciprocal to ξ when w ∘ ξ = f_x v_x + f_y v_y + m_O ω = 0.

Twists are taken from Pinocchio: column j of the WORLD joint Jacobian of joint j (rows
v_x, v_y, ω_z). A leg that meets the output body through a planar point closure gets a
virtual revolute pair at the closure frame (what the 2-D point closure is).

* **Type 1** (paper: "degeneracy of the matrix of the kinematic screws of chain i"): the
  3 × n_i matrix [ξ_i1 … ξ_in] of every pair of leg i loses rank (for an RRR leg: A_i, B_i, C_i
  aligned), measured by σ_min/σ_max with positions scaled by 1/L.
* **Type 2** (paper: "loss of rank of the matrix of wrench screws reciprocal to the kinematic
  screws of the passive pairs of each chain"): w_i spans the null space of leg i's passive
  twists under ∘ (for two passive revolutes: a force along B_iC_i); the k × k matrix
  W_ij = w_i ∘ t_j with t_j the unit output twists (translations along x, y; rotation about
  the output point) loses rank. Rows are unit forces, rotation columns are divided by L.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from rcm_pin.closed_loop.core import ClosedMechanism
from rcm_pin.closed_loop.velocity import SINGULAR_TOL


@dataclass(frozen=True)
class ScrewTest:
    """Screw-route result: per-leg type-1 measures, wrench matrix W, type-2 measure."""

    leg_measures: np.ndarray
    wrenches: np.ndarray
    W: np.ndarray
    measure_type1: float
    measure_type2: float
    tol: float

    @property
    def type1(self) -> bool:
        """Some leg's kinematic screws are linearly dependent."""
        return self.measure_type1 < self.tol

    @property
    def type2(self) -> bool:
        """The leg wrenches, seen by the output body, are linearly dependent."""
        return self.measure_type2 < self.tol


def _point_twist(p: np.ndarray) -> np.ndarray:
    return np.array([p[1], -p[0], 1.0])


def leg_twists(mech: ClosedMechanism, q: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """Per leg: (twists (3, n_i) of all its pairs, mask of the passive ones)."""
    model, data = mech.model, mech.data
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    out = []
    driven = set(mech.driven)
    for leg in mech.legs:
        cols, passive = [], []
        for name in leg.joints:
            jid = model.getJointId(name)
            jac = pin.getJointJacobian(model, data, jid, pin.WORLD)
            cols.append(jac[[0, 1, 5], model.joints[jid].idx_v])
            passive.append(name not in driven)
        if leg.closure:
            cols.append(_point_twist(data.oMf[mech.frame_id(leg.closure)].translation))
            passive.append(True)
        out.append((np.array(cols).T, np.array(passive)))
    return out


def output_twists(mech: ClosedMechanism, q: np.ndarray) -> np.ndarray:
    """Unit output twists t_j (3, k): x, y translations, rz rotation about the output point."""
    p = mech.output(q)
    cols = []
    for c in mech.output_coords:
        cols.append(
            {"x": np.array([1.0, 0.0, 0.0]), "y": np.array([0.0, 1.0, 0.0])}.get(c)
            if c != "rz"
            else _point_twist(p[:2])
        )
    return np.array(cols).T


def screw_test(mech: ClosedMechanism, q: np.ndarray, tol: float = SINGULAR_TOL) -> ScrewTest:
    """Both screw criteria of paper 004 at a closed configuration q."""
    q = mech.check_q(q, mech.model.nq, "q")
    length = mech.length_scale
    scale = np.array([1.0 / length, 1.0 / length, 1.0])
    legs = leg_twists(mech, q)
    origin = mech.output(q)[:2]
    leg_measures, wrenches = [], []
    for twists, passive in legs:
        # shift the moment reference to the output point (rank-neutral, better scaled)
        shifted = twists.copy()
        shifted[0] += -origin[1] * twists[2]
        shifted[1] += origin[0] * twists[2]
        sv = np.linalg.svd(shifted * scale[:, None], compute_uv=False)
        leg_measures.append(sv[-1] / sv[0] if sv[0] > 0 else 0.0)
        _, _, vt = np.linalg.svd(twists[:, passive].T)  # reciprocal: w · ξ = 0 for passive ξ
        w = vt[-1]
        wrenches.append(w / np.linalg.norm(w[:2]))
    wr = np.array(wrenches)
    w_mat = wr @ output_twists(mech, q)
    col_scale = np.array([1.0 / length if c == "rz" else 1.0 for c in mech.output_coords])
    sv = np.linalg.svd(w_mat * col_scale[None, :], compute_uv=False)
    return ScrewTest(
        np.array(leg_measures), wr, w_mat, float(min(leg_measures)), float(sv[-1] / sv[0]), tol
    )
