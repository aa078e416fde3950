"""Loop closures of a cut-open tree: drives, passive joints, closure residual and Jacobian.

Each closure (frame a, frame b) of the sidecar (:mod:`rcm_pin.model.sidecar`) contributes

    e = R_aᵀ (p_a − p_b)  [m]               (3d: the points coincide)
    e = log₆(ᵃM_b)        [m, rad]          (6d: the frames coincide)

restricted to its kept rows. Jacobians come from Pinocchio frame Jacobians of the (mimic)
model, so mimic joints inside loops are handled by Pinocchio:

    3d:  J = R_aᵀ (J_a − J_b)_lin   (LOCAL_WORLD_ALIGNED, exact where e = 0)
    6d:  J = Jlog₆(ᵃM_b) (J_b^LOCAL − Ad(ᵇM_a) J_a^LOCAL)

The configuration is Pinocchio's q (nq entries, velocities nv): drives are one-DOF joints,
every other joint is passive (revolute, prismatic, continuous or multi-DOF). A second route
to the Jacobian is :func:`rcm_pin.model.constraints.pin_constraint_jacobian` on
``pin.RigidConstraintModel`` s.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError
from rcm_pin.model.indices import frame_index, joint_index
from rcm_pin.model.output import NO_OUTPUT, Output
from rcm_pin.model.sidecar import LegSpec, LoopSpec

__all__ = ["REVOLUTE", "Closure", "Loops", "build_loops", "frame_index", "joint_index"]

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
LOCAL = pin.ReferenceFrame.LOCAL
REVOLUTE = {"JointModelRX", "JointModelRY", "JointModelRZ", "JointModelRevoluteUnaligned"}


@dataclass(frozen=True)
class Closure:
    """One closure: frames a and b, kind (``3d``/``6d``), kept rows, frame ids.

    ``world_rows`` are the rows of the world-frame difference [p_a − p_b] (3d) or
    [p_a − p_b; ω-rows] (6d) that are not structurally zero (a planar loop has no
    out-of-plane row); the constrained dynamics uses them (:mod:`rcm_pin.dynamics.constrained`).
    """

    frame_a: str
    frame_b: str
    kind: str
    rows: tuple[int, ...]
    frame_a_id: int
    frame_b_id: int
    world_rows: tuple[int, ...] = ()


@dataclass(frozen=True, eq=False)
class Loops:
    """Closures and the drive / passive partition of a closed mechanism.

    Attributes:
        closures: the closures, in sidecar order.
        drives: names of the driven joints (k), in sidecar order.
        passive: the other independent joints, in Pinocchio order.
        extra_drives: drives that may replace main ones (e.g. the five-bar's elbows).
        output: the output frame and coordinates.
        legs: legs for the screw-theory route.
        params: closed-form geometry of the family [m, deg].
        length_scale: characteristic length L [m] that makes angular rows commensurate
            with translation rows in the singularity measures.
        drive_q, drive_v: q and v indices of the drives.
        passive_q, passive_v: q and v indices of the passive joints.
        wrap_q: q indices of passive revolute angles (wrapped to [−π, π) after a solve).
        revolute_q: q indices of every revolute angle, drives included.
        euclidean: every joint is one-DOF, so q and v have the same layout.
    """

    closures: tuple[Closure, ...]
    drives: tuple[str, ...]
    passive: tuple[str, ...]
    extra_drives: tuple[str, ...]
    output: Output
    legs: tuple[LegSpec, ...]
    params: Mapping[str, float]
    length_scale: float
    drive_q: np.ndarray
    drive_v: np.ndarray
    passive_q: np.ndarray
    passive_v: np.ndarray
    wrap_q: np.ndarray
    revolute_q: np.ndarray
    euclidean: bool

    @property
    def n_rows(self) -> int:
        """Number m of kept closure rows."""
        return sum(len(c.rows) for c in self.closures)

    @property
    def dof(self) -> int:
        """Number k of drives."""
        return len(self.drives)

    def with_drives(self, model: pin.Model, drives: Sequence[str]) -> Loops:
        """The same loops driven by other joints (e.g. the extra drives)."""
        return build_loops(model, replace(self.spec, actuated=tuple(drives)))

    @property
    def spec(self) -> LoopSpec:
        """The sidecar this was built from (round trip)."""
        from rcm_pin.model.sidecar import KINDS, ClosureSpec

        return LoopSpec(
            closures=tuple(
                ClosureSpec(c.frame_a, c.frame_b, c.kind, tuple(KINDS[c.kind][r] for r in c.rows))
                for c in self.closures
            ),
            actuated=self.drives,
            output_frame=self.output.frame,
            output_coords=self.output.coords,
            extra_actuated=self.extra_drives,
            legs=self.legs,
            params=self.params,
            length_scale=self.length_scale,
        )


def build_loops(model: pin.Model, spec: LoopSpec) -> Loops:
    """Resolve a loop spec against a model (frames, joints, index sets).

    Raises:
        UnknownFrameError: a closure or output frame, drive or leg joint not in the model.
        InvalidInputError: a drive that is not a one-DOF joint, or no drive at all.
    """
    closures = _with_world_rows(
        model,
        tuple(
            Closure(
                c.frame_a,
                c.frame_b,
                c.kind,
                c.row_indices,
                frame_index(model, c.frame_a, "closure frame"),
                frame_index(model, c.frame_b, "closure frame"),
            )
            for c in spec.closures
        ),
    )
    if not spec.actuated:
        raise InvalidInputError("a closed mechanism needs drives; valid: one or more joints")
    drive_ids = [joint_index(model, d, "drive") for d in spec.actuated]
    for name, jid in zip(spec.actuated, drive_ids, strict=True):
        if model.joints[jid].nq != 1 or model.joints[jid].nv != 1:
            raise InvalidInputError(
                f"drive {name!r} is not a one-DOF joint (nq = {model.joints[jid].nq}); "
                "valid: revolute or prismatic joints"
            )
    for leg in spec.legs:
        for j in leg.joints:
            joint_index(model, j, "leg joint")
    independent = [j for j in range(1, model.njoints) if model.joints[j].nq > 0]
    passive_ids = [j for j in independent if j not in drive_ids]
    pq = [model.joints[j].idx_q + k for j in passive_ids for k in range(model.joints[j].nq)]
    pv = [model.joints[j].idx_v + k for j in passive_ids for k in range(model.joints[j].nv)]
    revolute = [j for j in independent if model.joints[j].shortname() in REVOLUTE]
    output = (
        Output(
            spec.output_frame,
            spec.output_coords,
            frame_index(model, spec.output_frame, "output frame"),
        )
        if spec.output_frame
        else NO_OUTPUT
    )
    return Loops(
        closures=closures,
        drives=tuple(spec.actuated),
        passive=tuple(model.names[j] for j in passive_ids),
        extra_drives=tuple(spec.extra_actuated),
        output=output,
        legs=tuple(spec.legs),
        params=dict(spec.params),
        length_scale=spec.length_scale if spec.length_scale is not None else _reach(model),
        drive_q=np.array([model.joints[j].idx_q for j in drive_ids], dtype=int),
        drive_v=np.array([model.joints[j].idx_v for j in drive_ids], dtype=int),
        passive_q=np.array(pq, dtype=int),
        passive_v=np.array(pv, dtype=int),
        wrap_q=np.array([model.joints[j].idx_q for j in revolute if j in passive_ids], dtype=int),
        revolute_q=np.array([model.joints[j].idx_q for j in revolute], dtype=int),
        euclidean=bool(model.nq == model.nv and all(model.joints[j].nq == 1 for j in independent)),
    )


def _with_world_rows(model: pin.Model, closures: tuple[Closure, ...]) -> tuple[Closure, ...]:
    """Closures with their structurally non-zero world rows, probed at a seeded random q."""
    rng = np.random.default_rng(12345)
    lo = np.maximum(
        np.where(np.isfinite(model.lowerPositionLimit), model.lowerPositionLimit, -np.pi), -np.pi
    )
    hi = np.minimum(
        np.where(np.isfinite(model.upperPositionLimit), model.upperPositionLimit, np.pi), np.pi
    )
    q = pin.normalize(model, rng.uniform(lo, hi)) if model.nq else np.zeros(0)
    data = model.createData()
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    out = []
    for c in closures:
        ja = pin.getFrameJacobian(model, data, c.frame_a_id, LWA)
        jb = pin.getFrameJacobian(model, data, c.frame_b_id, LWA)
        jac = (ja - jb)[:3] if c.kind == "3d" else ja - jb
        norms = np.linalg.norm(jac, axis=1)
        keep = tuple(int(i) for i in np.flatnonzero(norms > 1e-12 * max(norms.max(), 1e-300)))
        out.append(replace(c, world_rows=keep))
    return tuple(out)


def _reach(model: pin.Model) -> float:
    """Mean distance of the joint origins from their parents at the neutral pose [m]."""
    lengths = [
        np.linalg.norm(model.jointPlacements[j].translation) for j in range(1, model.njoints)
    ]
    positive = [v for v in lengths if v > 1e-9]
    return float(np.mean(positive)) if positive else 1.0


def residual_from_data(model: pin.Model, data: pin.Data, loops: Loops) -> np.ndarray:
    """Kept closure rows e (m,) from the joint placements in ``data`` [m, rad]."""
    out = []
    for c in loops.closures:
        oMa = pin.updateFramePlacement(model, data, c.frame_a_id)
        oMb = pin.updateFramePlacement(model, data, c.frame_b_id)
        if c.kind == "3d":
            err = oMa.rotation.T @ (oMa.translation - oMb.translation)
        else:
            err = pin.log6(oMa.actInv(oMb)).vector
        out.append(err[list(c.rows)])
    return np.concatenate(out) if out else np.zeros(0)


def closure_residual(model: pin.Model, data: pin.Data, loops: Loops, q: np.ndarray) -> np.ndarray:
    """Kept closure rows e(q) (m,) [m, rad]; runs forward kinematics."""
    pin.forwardKinematics(model, data, q)
    return residual_from_data(model, data, loops)


def residual_and_jacobian(
    model: pin.Model, data: pin.Data, loops: Loops, q: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Closure residual e (m,) and Jacobian J_c (m, nv) (module docstring)."""
    pin.computeJointJacobians(model, data, q)
    es, js = [], []
    for c in loops.closures:
        oMa = pin.updateFramePlacement(model, data, c.frame_a_id)
        oMb = pin.updateFramePlacement(model, data, c.frame_b_id)
        rows = list(c.rows)
        if c.kind == "3d":
            ja = pin.getFrameJacobian(model, data, c.frame_a_id, LWA)
            jb = pin.getFrameJacobian(model, data, c.frame_b_id, LWA)
            rt = oMa.rotation.T[rows]
            es.append(rt @ (oMa.translation - oMb.translation))
            js.append(rt @ (ja[:3] - jb[:3]))
        else:
            aMb = oMa.actInv(oMb)
            ja = pin.getFrameJacobian(model, data, c.frame_a_id, LOCAL)
            jb = pin.getFrameJacobian(model, data, c.frame_b_id, LOCAL)
            jrel = pin.Jlog6(aMb) @ (jb - aMb.inverse().action @ ja)
            es.append(pin.log6(aMb).vector[rows])
            js.append(jrel[rows])
    if not es:
        return np.zeros(0), np.zeros((0, model.nv))
    return np.concatenate(es), np.vstack(js)


__all__ = [
    "REVOLUTE",
    "Closure",
    "Loops",
    "build_loops",
    "closure_residual",
    "frame_index",
    "joint_index",
    "residual_and_jacobian",
    "residual_from_data",
]
