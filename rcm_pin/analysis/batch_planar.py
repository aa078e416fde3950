"""Vectorised Newton on the closure residual of a planar tree, for many poses at once.

The planar kinematics is extracted once from the ``pin.Model`` (joint placements, frame
placements: a translation (x, y) and a rotation θ about the plane normal each), so this is
not a hand-written closed form but the same tree evaluated with numpy on arrays of N
configurations::

    θ_j = θ_parent(j) + θ⁰_j + q_j            world angle of joint j's body [rad]
    p_j = p_parent(j) + R(θ_parent(j)) t⁰_j    world position of joint j [m]
    p_f = p_j(f) + R(θ_j(f)) t_f               frame f on the body of joint j(f)
    ∂p_f/∂q_i = n × (p_f − p_i)               for every ancestor i of j(f)

The residual is the world-frame in-plane difference p_a − p_b of each closure (same zero set
as the LOCAL residual of :mod:`rcm_pin.model.loops`; it differs by the rotation R(θ_a)),
and the batched Newton solves (N, m, m) systems with ``np.linalg.solve``.

A vectorised speed twin of :func:`rcm_pin.model.newton.solve_passive` (one numpy pass for
N poses instead of N Pinocchio Newton runs; ``benchmarks/bench_closed_loop.py``): from the
same drives and starts both reach the same configuration
(``tests/test_closed_loop_position.py::test_batched_newton_is_the_pinocchio_newton``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError
from rcm_pin.model.constraints import plane_normal
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.rotations import wrap_angle as wrap


def _planar(m: pin.SE3) -> tuple[float, float, float]:
    return (
        float(m.translation[0]),
        float(m.translation[1]),
        float(np.arctan2(m.rotation[1, 0], m.rotation[0, 0])),
    )


@dataclass(frozen=True)
class PlanarTree:
    """Planar data of a revolute tree: parents, joint placements (x, y, θ), closure frames."""

    parents: np.ndarray  # (n,) parent joint index in 0..n-1, −1 for the base
    joint_xyt: np.ndarray  # (n, 3)
    q_index: np.ndarray  # (n,) idx_q of each joint
    ancestors: np.ndarray  # (n, n) bool: ancestors[j, i] = joint i is j or an ancestor of j
    frames: np.ndarray  # (2c, 4): parent joint (0-based), x, y, θ for a_1, b_1, a_2, b_2, ...
    out_frame: np.ndarray  # (4,) same for the output frame

    @classmethod
    def from_mechanism(cls, mech: Mechanism) -> PlanarTree:
        """Extract the planar tree (a tree in the xy plane with 3d closures).

        Raises:
            InvalidInputError: a non-planar mechanism.
        """
        model = mech.model
        normal = plane_normal(model)
        loops = mech.require_loops()
        if (
            normal is None
            or abs(abs(normal[2]) - 1.0) > 1e-12
            or mech.coupling.has_mimic
            or any(c.kind != "3d" for c in loops.closures)
        ):
            raise InvalidInputError(
                f"{mech.name}: batched Newton needs a planar xy tree of revolute joints with 3d "
                "closures and no mimic joints"
            )
        n = model.njoints - 1
        parents = np.array([model.parents[j] - 1 for j in range(1, n + 1)])
        xyt = np.array([_planar(model.jointPlacements[j]) for j in range(1, n + 1)])
        anc = np.zeros((n, n), dtype=bool)
        for j in range(n):
            i = j
            while i >= 0:
                anc[j, i] = True
                i = parents[i]

        def frame_row(fid: int) -> list[float]:
            f = model.frames[fid]
            return [f.parentJoint - 1, *_planar(f.placement)]

        rows = [frame_row(f) for c in loops.closures for f in (c.frame_a_id, c.frame_b_id)]
        return cls(
            parents=parents,
            joint_xyt=xyt,
            q_index=np.array([model.joints[j].idx_q for j in range(1, n + 1)]),
            ancestors=anc,
            frames=np.array(rows),
            out_frame=np.array(frame_row(loops.output.frame_id)),
        )

    def _joints_t(self, qt: np.ndarray) -> tuple[list, list, list]:
        """Joint x, y and body angle, one contiguous (N,) array per joint (qt is (nq, N))."""
        xs: list[np.ndarray] = []
        ys: list[np.ndarray] = []
        angs: list[np.ndarray] = []
        for j, p in enumerate(self.parents):  # Pinocchio orders parents before children
            x0, y0, t0 = self.joint_xyt[j]
            qj = qt[self.q_index[j]]
            if p < 0:
                xs.append(np.full(qt.shape[1], x0))
                ys.append(np.full(qt.shape[1], y0))
                angs.append(qj + t0)
            else:
                c, s = np.cos(angs[p]), np.sin(angs[p])
                xs.append(xs[p] + c * x0 - s * y0)
                ys.append(ys[p] + s * x0 + c * y0)
                angs.append(angs[p] + (t0 + qj) if t0 else angs[p] + qj)
        return xs, ys, angs

    def _frame_t(self, xs: list, ys: list, angs: list, row: np.ndarray) -> tuple:
        j = int(row[0])
        if row[1] == 0.0 and row[2] == 0.0:
            return xs[j], ys[j]
        c, s = np.cos(angs[j]), np.sin(angs[j])
        return xs[j] + c * row[1] - s * row[2], ys[j] + s * row[1] + c * row[2]

    def residual_jacobian(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """World residual (N, m) and Jacobian (N, m, nq) of every closure."""
        qt = np.ascontiguousarray(q.T)
        xs, ys, angs = self._joints_t(qt)
        n_rows = self.frames.shape[0]
        res = np.zeros((n_rows, q.shape[0]))
        jac = np.zeros((n_rows, q.shape[1], q.shape[0]))
        for k in range(n_rows):
            sign = 1.0 if k % 2 == 0 else -1.0
            r = 2 * (k // 2)
            fx, fy = self._frame_t(xs, ys, angs, self.frames[k])
            res[r] += sign * fx
            res[r + 1] += sign * fy
            for i in np.flatnonzero(self.ancestors[int(self.frames[k, 0])]):
                col = self.q_index[i]
                jac[r, col] -= sign * (fy - ys[i])
                jac[r + 1, col] += sign * (fx - xs[i])
        return res.T, jac.transpose(2, 0, 1)

    def output(self, q: np.ndarray) -> np.ndarray:
        """Output (x, y, θ) (N, 3) of the output frame."""
        xs, ys, angs = self._joints_t(np.ascontiguousarray(q.T))
        fx, fy = self._frame_t(xs, ys, angs, self.out_frame)
        theta = angs[int(self.out_frame[0])] + self.out_frame[3]
        return np.column_stack([fx, fy, wrap(theta)])


def batch_solve_passive(
    mech: Mechanism,
    tree: PlanarTree,
    q_drives: np.ndarray,
    q_guess: np.ndarray,
    tol: float = 1e-13,
    max_iter: int = 30,
    max_step: float = 0.5,
) -> tuple[np.ndarray, np.ndarray]:
    """Newton for N poses at once: e(q_a, q_p) = 0 with the drives fixed.

    Args:
        mech: mechanism (partition).
        tree: its planar tree.
        q_drives: (N, k) drive angles [rad].
        q_guess: (N, n) starting configurations [rad].
        tol: residual norm target [m].
        max_iter: iteration cap.
        max_step: step clip per iteration [rad].

    Returns:
        (q (N, n), residual norm (N,) [m]); unconverged poses keep their last iterate.
    """
    q = np.array(q_guess, dtype=float)
    loops = mech.require_loops()
    q[:, loops.drive_q] = q_drives
    ip = loops.passive_q
    eye = np.eye(len(ip))
    norms = np.full(q.shape[0], np.inf)
    for _ in range(max_iter + 1):
        res, jac = tree.residual_jacobian(q)
        norms = np.sqrt(np.einsum("ij,ij->i", res, res))
        todo = norms >= tol
        if not todo.any():
            break
        if todo.mean() < 0.5:  # few stragglers: iterate on them only
            sub, sub_norms = batch_solve_passive(
                mech, tree, q_drives[todo], q[todo], tol, max_iter, max_step
            )
            q[todo], norms[todo] = sub, sub_norms
            break
        jp = jac[:, :, ip]
        try:
            step = -np.linalg.solve(jp, res[..., None])[..., 0]
        except np.linalg.LinAlgError:  # an exactly singular pose: regularise the batch
            step = -np.linalg.solve(jp + 1e-12 * eye, res[..., None])[..., 0]
        step[~todo] = 0.0
        peak = np.max(np.abs(step), axis=1, keepdims=True)
        step *= np.minimum(1.0, max_step / np.maximum(peak, 1e-300))
        q[:, ip] += step
    q[:, ip] = wrap(q[:, ip])
    return q, norms
