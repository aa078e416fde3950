"""Closed mechanism on Pinocchio: a cut-open tree, its loop closures and the solver core.

Closure model. Each sidecar pair (frame_a, frame_b) becomes a ``pin.RigidConstraintModel``
between the parent joints of the two frames, placements = the frame placements, expressed
in the LOCAL frame of ``a``. Its residual is

    e(q) = R_aᵀ (p_a − p_b)  [m]           (3d, points coincide)
    e(q) = log6(ᵃM_b)        [m, rad]      (6d, frames coincide)

and its Jacobian is Pinocchio's constraint Jacobian (``pin.getConstraintsJacobian``), which
is exact where e = 0 and off by O(|e|) elsewhere, so Newton keeps quadratic convergence.

Planar loops. A 3-D point closure of a loop whose joints all turn about the plane normal n
has an identically zero out-of-plane row (n·(p_a − p_b) ≡ 0 for every q): the 3 × n
Jacobian has rank ≤ 2, and the stacked closures are rank deficient. The mechanism is then
over-constrained on paper only. rcm-pin keeps the two in-plane rows of the LOCAL frame of
``a`` (its z axis is n because every joint turns about n), i.e. a 2-D position closure,
equivalent to a revolute pair about n at the cut point. For a 6-D closure of a planar loop
the in-plane rows are (x, y, rz).

Partition. q = (drives q_a, passive q_p) by the sidecar's ``actuated`` list; the output is the
pose of ``output_frame`` in world coordinates ``output_coords`` (x, y [m], rz [rad]). With m
closure rows and k = dim q_a, the planar mechanisms here have n = m + k joints.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
import pinocchio as pin

from rcm_pin.closed_loop.sidecar import LegSpec
from rcm_pin.errors import InvalidInputError, SolverError, UnknownFrameError

#: Newton stops when the closure residual norm is below this [m].
RESIDUAL_TOL = 1e-13
_ROWS = {
    ("3d", False): (0, 1, 2),
    ("3d", True): (0, 1),
    ("6d", False): tuple(range(6)),
    ("6d", True): (0, 1, 5),
}
_COORD_ROWS = {"x": 0, "y": 1, "z": 2, "rx": 3, "ry": 4, "rz": 5}


def wrap(angle: np.ndarray) -> np.ndarray:
    """Angles wrapped to [−π, π) [rad]."""
    return (np.asarray(angle) + np.pi) % (2.0 * np.pi) - np.pi


@dataclass(frozen=True, eq=False)
class Closure:
    """One loop closure: the Pinocchio constraint and the rows rcm-pin keeps."""

    frame_a: str
    frame_b: str
    kind: str
    rows: tuple[int, ...]
    constraint: pin.RigidConstraintModel


@dataclass(frozen=True, eq=False)
class ClosedMechanism:
    """A closed-loop mechanism: Pinocchio tree + closures + driven/passive/output partition.

    Frozen-ish: the fields never change (``with_drives`` returns a copy), only the cached
    Pinocchio ``data`` buffers are written by the methods, so one object per thread.

    Attributes:
        name: mechanism name.
        model: Pinocchio model of the cut-open tree.
        data: its data (scratch buffers).
        closures: loop closures.
        constraint_models / constraint_datas: Pinocchio constraint vectors.
        driven: names of the driven joints (k of them), in sidecar order.
        passive: the other joints, in Pinocchio q order.
        extra_drives: extra drives that may replace main drives (five-bar).
        output_frame: output body frame; output_coords its coordinates.
        legs: legs for the screw route.
        params: closed-form geometry [m, deg].
        plane_normal: motion-plane normal or None.
        length_scale: characteristic length L [m] that makes rotation rows commensurate
            with translation rows in the singularity measures.
    """

    name: str
    model: pin.Model
    data: pin.Data
    closures: tuple[Closure, ...]
    constraint_models: pin.StdVec_RigidConstraintModel
    constraint_datas: pin.StdVec_RigidConstraintData
    driven: tuple[str, ...]
    passive: tuple[str, ...]
    extra_drives: tuple[str, ...]
    output_frame: str
    output_coords: tuple[str, ...]
    legs: tuple[LegSpec, ...]
    params: Mapping[str, float]
    plane_normal: tuple[float, float, float] | None
    length_scale: float
    idx_driven: np.ndarray = field(init=False, repr=False)
    idx_passive: np.ndarray = field(init=False, repr=False)
    output_frame_id: int = field(init=False, repr=False)
    rows: np.ndarray = field(init=False, repr=False)
    out_rows: np.ndarray = field(init=False, repr=False)
    _frame_ids: tuple[tuple[int, int], ...] = field(init=False, repr=False)
    _all_3d: bool = field(init=False, repr=False)
    _row_index: tuple[np.ndarray, ...] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "idx_driven", self.joint_indices(self.driven))
        object.__setattr__(self, "idx_passive", self.joint_indices(self.passive))
        object.__setattr__(self, "output_frame_id", self.frame_id(self.output_frame))
        offsets = np.cumsum([0] + [c.constraint.residualSize() for c in self.closures])
        rows = [offsets[i] + r for i, c in enumerate(self.closures) for r in c.rows]
        object.__setattr__(self, "rows", np.array(rows, dtype=int))
        ids = tuple((self.frame_id(c.frame_a), self.frame_id(c.frame_b)) for c in self.closures)
        object.__setattr__(self, "_frame_ids", ids)
        object.__setattr__(self, "_all_3d", all(c.kind == "3d" for c in self.closures))
        row_index = tuple(np.array(c.rows, dtype=int) for c in self.closures)
        object.__setattr__(self, "_row_index", row_index)
        object.__setattr__(self, "out_rows", np.array([_COORD_ROWS[c] for c in self.output_coords]))
        if self.n_constraints + self.dof != self.model.nv:
            raise InvalidInputError(
                f"{self.name}: {self.model.nv} joints, {self.n_constraints} closure rows and "
                f"{self.dof} drives do not satisfy n = m + k"
            )

    # ----------------------------------------------------------------- bookkeeping
    @property
    def n_constraints(self) -> int:
        """Number m of kept closure rows."""
        return int(sum(len(c.rows) for c in self.closures))

    @property
    def dof(self) -> int:
        """Number k of drives (= degrees of freedom of a regular configuration)."""
        return len(self.driven)

    def joint_indices(self, names: Sequence[str]) -> np.ndarray:
        """Indices in q (= in v: all joints are 1-DOF revolute) of named joints."""
        out = []
        for name in names:
            if not self.model.existJointName(name):
                valid = ", ".join(self.model.names[1:])
                raise UnknownFrameError(f"joint {name!r} is not in {self.name}; valid: {valid}")
            out.append(self.model.joints[self.model.getJointId(name)].idx_q)
        return np.array(out, dtype=int)

    def frame_id(self, name: str) -> int:
        """Pinocchio frame id of a frame name."""
        if not self.model.existFrame(name):
            raise UnknownFrameError(f"frame {name!r} is not in {self.name}")
        return int(self.model.getFrameId(name))

    def with_drives(self, driven: Sequence[str]) -> ClosedMechanism:
        """Copy with another set of driven joints (e.g. the extra drives of the five-bar)."""
        driven = tuple(driven)
        self.joint_indices(driven)
        passive = tuple(n for n in self.model.names[1:] if n not in driven)
        return replace(self, driven=driven, passive=passive, data=self.model.createData())

    def assemble(self, q_drives: np.ndarray, q_passive: np.ndarray) -> np.ndarray:
        """Full q from drive and passive values [rad]."""
        q = np.zeros(self.model.nq)
        q[self.idx_driven] = q_drives
        q[self.idx_passive] = q_passive
        return q

    def check_q(self, q: np.ndarray, size: int, name: str) -> np.ndarray:
        """Validate a finite 1-D array of a given size.

        Raises:
            InvalidInputError: wrong shape or non-finite entries.
        """
        arr = np.asarray(q, dtype=float)
        if arr.shape != (size,):
            raise InvalidInputError(f"{name} must have shape ({size},), got {arr.shape}")
        if not np.all(np.isfinite(arr)):
            raise InvalidInputError(f"{name} has NaN or infinite entries: {arr.tolist()}")
        return arr

    # ----------------------------------------------------------------- kinematics
    def closure_residual(self, q: np.ndarray) -> np.ndarray:
        """Kept closure rows e(q) (see module docstring) [m, rad]; runs forward kinematics."""
        pin.forwardKinematics(self.model, self.data, q)
        return self._residual_from_data()

    def _residual_from_data(self) -> np.ndarray:
        out = []
        for c in self.closures:
            cm = c.constraint
            oMa = self.data.oMi[cm.joint1_id] * cm.joint1_placement
            oMb = self.data.oMi[cm.joint2_id] * cm.joint2_placement
            if c.kind == "3d":
                err = oMa.rotation.T @ (oMa.translation - oMb.translation)
            else:
                err = -pin.log6(oMa.actInv(oMb)).vector
            out.append(err[list(c.rows)])
        return np.concatenate(out)

    def residual_and_jacobian(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Closure residual e (m,) and constraint Jacobian rows (m, n) [m, m/rad].

        Fast path for 3d closures: e = R_aᵀ(p_a − p_b), J = R_aᵀ(J_a − J_b) from Pinocchio
        frame Jacobians (LOCAL_WORLD_ALIGNED, linear rows). This equals Pinocchio's constraint
        Jacobian wherever e = 0 (tested); 6d closures use :meth:`residual_and_jacobian_pin`.
        """
        if not self._all_3d:
            return self.residual_and_jacobian_pin(q)
        model, data = self.model, self.data
        pin.computeJointJacobians(model, data, q)
        es, js = [], []
        lwa = pin.LOCAL_WORLD_ALIGNED
        for rows, (fa, fb) in zip(self._row_index, self._frame_ids, strict=True):
            oMa = pin.updateFramePlacement(model, data, fa)
            oMb = pin.updateFramePlacement(model, data, fb)
            ja = pin.getFrameJacobian(model, data, fa, lwa)
            jb = pin.getFrameJacobian(model, data, fb, lwa)
            rt = oMa.rotation.T[rows]
            es.append(rt @ (oMa.translation - oMb.translation))
            js.append(rt @ (ja[:3] - jb[:3]))
        return np.concatenate(es), np.vstack(js)

    def residual_and_jacobian_pin(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Residual and ``pin.getConstraintsJacobian`` rows of the RigidConstraintModels."""
        pin.computeJointJacobians(self.model, self.data, q)
        for cm, cd in zip(self.constraint_models, self.constraint_datas, strict=True):
            cm.calc(self.model, self.data, cd)
        jac = pin.getConstraintsJacobian(
            self.model, self.data, self.constraint_models, self.constraint_datas
        )
        return self._residual_from_data(), jac[self.rows]

    def constraint_jacobian(self, q: np.ndarray) -> np.ndarray:
        """Constraint Jacobian J_c (m, n): J_c q̇ = 0 along closed-loop motions [m/rad]."""
        return self.residual_and_jacobian(q)[1]

    def output(self, q: np.ndarray) -> np.ndarray:
        """Output pose (x, y [m], rz [rad]) of the output frame (forward kinematics)."""
        pin.forwardKinematics(self.model, self.data, q)
        oMf = pin.updateFramePlacement(self.model, self.data, self.output_frame_id)
        return self._pose_of(oMf)

    def _pose_of(self, oMf: pin.SE3) -> np.ndarray:
        out = []
        for c in self.output_coords:
            if c in ("x", "y", "z"):
                out.append(oMf.translation[_COORD_ROWS[c]])
            elif c == "rz":
                out.append(np.arctan2(oMf.rotation[1, 0], oMf.rotation[0, 0]))
            else:
                raise InvalidInputError(f"output coordinate {c!r} unsupported; valid: x y z rz")
        return np.array(out)

    def output_jacobian_open(self, q: np.ndarray) -> np.ndarray:
        """Tree Jacobian J_x (k, n) of the output coordinates, LOCAL_WORLD_ALIGNED."""
        pin.computeJointJacobians(self.model, self.data, q)
        pin.updateFramePlacements(self.model, self.data)
        jac = pin.getFrameJacobian(
            self.model, self.data, self.output_frame_id, pin.LOCAL_WORLD_ALIGNED
        )
        return jac[self.out_rows]

    # ----------------------------------------------------------------- solver
    def solve_passive(
        self,
        q_drives: np.ndarray,
        q_guess: np.ndarray,
        max_iter: int = 60,
        max_step: float = 0.5,
    ) -> tuple[np.ndarray, int, float]:
        """Newton / Levenberg–Marquardt on the closure residual with the drives fixed.

        Solves e(q_a, q_p) = 0 for q_p from ``q_guess``: Δq_p = −J_p⁻¹ e, with the step
        clipped to ``max_step`` [rad] (keeps the iterate on the starting branch) and an LM
        step (J_pᵀJ_p + μI)⁻¹J_pᵀe where J_p is ill-conditioned.

        Args:
            q_drives: drive values (k,) [rad].
            q_guess: full starting configuration (n,) [rad].
            max_iter: iteration cap.
            max_step: largest joint step per iteration [rad].

        Returns:
            (q with passive joints wrapped to [−π, π), iterations, final residual norm [m]).

        Raises:
            SolverError: no convergence to RESIDUAL_TOL.
        """
        q = np.array(q_guess, dtype=float)
        q[self.idx_driven] = q_drives
        res = np.inf
        for it in range(max_iter + 1):
            e, jac = self.residual_and_jacobian(q)
            res = math.sqrt(float(e @ e))
            if res < RESIDUAL_TOL:
                q[self.idx_passive] = wrap(q[self.idx_passive])
                return q, it, res
            jp = jac[:, self.idx_passive]
            try:
                step = -np.linalg.solve(jp, e)
                peak = float(np.abs(step).max())  # NaN when the solve blew up
                ok = peak < 1e3
            except np.linalg.LinAlgError:
                ok = False
            if not ok:
                mu = 1e-6 + res
                step = -np.linalg.solve(jp.T @ jp + mu * np.eye(jp.shape[1]), jp.T @ e)
                peak = float(np.abs(step).max())
            if peak > max_step:
                step *= max_step / peak
            q[self.idx_passive] += step
        raise SolverError(
            f"{self.name}: closure Newton did not converge in {max_iter} iterations "
            f"(residual {res:.3e} m > {RESIDUAL_TOL:.0e} m) for drives {np.round(q_drives, 6)}"
        )
