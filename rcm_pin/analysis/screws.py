"""Screw-theory singularity test of paper 004 (the second route, independent of A and B).

6-D screws in world axes about the output point O, with linear parts divided by the
length L so that every entry is commensurate. A twist is ξ = (v_O/L, ω): column j of
Pinocchio's WORLD joint Jacobian (velocity of the body point at the world origin v₀, and
ω; mimic joints included, so a parallelogram's crank carries its whole translation),
shifted by v_O = v₀ + ω × O. A wrench w = (f, m_O/L) is reciprocal to ξ when
w·ξ = (f·v_O + m_O·ω)/L = 0.

A leg that meets the output through a cut pair gets the pair's freedoms as virtual twists
at the cut point: a ``3d`` closure (points coincide) is a spherical pair (rotations about
the three axes), a ``6d`` closure a rigid one (none).

* **Type 1** (paper: "degeneracy of the matrix of the kinematic screws of chain i"): the
  twists of every pair of leg i lose rank (below min(6, count)), measured by σ_r/σ₁; for
  an RRR leg A_i, B_i, C_i aligned.
* **Type 2** (paper: "loss of rank of the matrix of wrench screws reciprocal to the
  kinematic screws of the passive pairs of each chain"): each leg's wrenches span the left
  null space of its passive twists; the output has an uncontrolled motion when the matrix
  W·T of every leg's unit wrenches acting on the unit output twists T (translations for
  x, y, z; rotations about O for angles) loses rank, measured by σ_k/σ₁ (with one output,
  σ₁ itself: the largest work of a unit wrench on the unit output twist).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from rcm_pin.analysis.loop_velocity import SINGULAR_TOL
from rcm_pin.model.indices import frame_index
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.newton import RANK_TOL


@dataclass(frozen=True)
class ScrewTest:
    """Screw-route result: per-leg type-1 measures, unit wrenches, W·T, type-2 measure."""

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
        """The leg wrenches, seen by the output, are linearly dependent."""
        return self.measure_type2 < self.tol


def leg_twists(mech: Mechanism, q: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """Per leg: (twists (6, n_i) as (v₀, ω) about the world origin, mask of passive ones)."""
    model, data = mech.model, mech.data
    loops = mech.require_loops()
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    driven = set(loops.drives)
    kinds = {f: c.kind for c in loops.closures for f in (c.frame_a, c.frame_b)}
    out = []
    for leg in loops.legs:
        cols, passive = [], []
        for name in leg.joints:
            jid = model.getJointId(name)
            jac = np.asarray(pin.getJointJacobian(model, data, jid, pin.WORLD))
            cols.append(jac[:, model.joints[jid].idx_v])
            passive.append(name not in driven)
        if leg.closure and kinds.get(leg.closure) == "3d":
            p = data.oMf[frame_index(model, leg.closure)].translation
            for axis in np.eye(3):  # the spherical cut pair: rotations about the cut point
                cols.append(np.r_[np.cross(p, axis), axis])
                passive.append(True)
        out.append((np.array(cols).T, np.array(passive)))
    return out


def about(twists: np.ndarray, origin: np.ndarray, length: float) -> np.ndarray:
    """Twists (v₀, ω) (6, n) as (v_O/L, ω) about ``origin`` (module docstring)."""
    out = np.array(twists, dtype=float)
    out[:3] = (twists[:3] + np.cross(twists[3:].T, origin).T) / length
    return out


def output_twists(mech: Mechanism) -> np.ndarray:
    """Unit output twists T (6, k) about O: a translation per length coordinate, a
    rotation per angle (``rotation``: about x, y and z)."""
    out = []
    for row in mech.require_loops().output.rows:
        t = np.zeros(6)
        t[row] = 1.0
        out.append(t)
    return np.array(out).T


def screw_test(mech: Mechanism, q: np.ndarray, tol: float = SINGULAR_TOL) -> ScrewTest:
    """Both screw criteria of paper 004 at a closed configuration q (module docstring)."""
    q = mech.check_q(q)
    loops = mech.require_loops()
    length = loops.length_scale
    legs = leg_twists(mech, q)
    origin = mech.data.oMf[loops.output.frame_id].translation.copy()
    leg_measures, wrenches = [], []
    for twists, passive in legs:
        xi = about(twists, origin, length)
        sv = np.linalg.svd(xi, compute_uv=False)
        r = min(6, xi.shape[1])
        leg_measures.append(float(sv[r - 1] / sv[0]) if sv[0] > 0 else 0.0)
        u, s, _ = np.linalg.svd(xi[:, passive])
        rank = int(np.sum(s > RANK_TOL * max(float(s[0]), 1e-300))) if s.size else 0
        wrenches += list(u[:, rank:].T)  # unit wrenches w with w·ξ = 0 for passive ξ
    wr = np.array(wrenches).reshape(-1, 6)
    w_mat = wr @ output_twists(mech)
    k = w_mat.shape[1]
    sv = np.linalg.svd(w_mat, compute_uv=False)
    if k == 1:  # one output: the ratio is 1 by definition; unit wrenches on a unit twist
        measure2 = float(sv[0]) if len(sv) else 0.0
    else:
        measure2 = float(sv[k - 1] / sv[0]) if len(sv) >= k and sv[0] > 0 else 0.0
    return ScrewTest(np.array(leg_measures), wr, w_mat, float(min(leg_measures)), measure2, tol)


__all__ = ["ScrewTest", "about", "leg_twists", "output_twists", "screw_test"]
