"""Velocity problem and singularity classification from Pinocchio's Jacobians.

Along a closed-loop motion J_c q̇ = 0 (constraint Jacobian, m × n) and the output moves with
ẋ = J_x q̇ (output frame Jacobian rows, k × n). Split q̇ = (q̇_a drives, q̇_p passive) and
write both as one linear system in (q̇_p, ẋ)::

    [J_c,p   0 ] [q̇_p]     [J_c,a]
    [J_x,p  −I ] [ ẋ ] = − [J_x,a] q̇_a

Let N (k × (m + k)) be an orthonormal basis of the left null space of the passive columns
[J_c,p; J_x,p] (one row per "leg wrench" in screw language). Multiplying by N eliminates q̇_p:

    A ẋ = −B q̇_a,   A = −N[:, m:],   B = N [J_c,a; J_x,a]

the Angeles–Gosselin form of paper 004 (A, B are defined up to a common invertible left
factor; singular sets and J_out = −A⁻¹B do not depend on it). Rotation output rows are
scaled by the length L = ``mech.loops.length_scale`` before the SVD so that every row is in
[m/rad]; A is converted back to (x, y [m], rz [rad]) afterwards.

Classification with a documented tolerance ``tol`` (default :data:`SINGULAR_TOL`):
    type 1 (loss of output DOF, B singular):  σ_min(B̃)/σ_max(B̃) < tol
    type 2 (uncontrolled output motion, A singular): σ_min(Ã)/σ_max(Ã) < tol
with Ã = −N[:, m:] (dimensionless) and B̃ = B/L, both computed in the scaled coordinates.
With one drive the ratios are 1 by definition; the measures are then |Ã| and |B̃| over
the norm of the scaled drive column (both in [0, 1]).

Over-constrained closures (a parallelogram written as a 4R loop): the rows of J_c are first
reduced to an independent set by a rank-revealing SVD, so m is the rank of J_c.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rcm_pin.errors import InvalidInputError, SingularConfigurationError
from rcm_pin.model.constraints import pin_constraint_jacobian
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.newton import constraint_rank

#: Relative singular-value threshold of the classifier (poses within ~tol·L of a singular
#: curve count as singular). Generic poses sit at 1e-3..1, poses on a curve at < 1e-12.
SINGULAR_TOL = 1e-8


@dataclass(frozen=True)
class VelocityMatrices:
    """A, B of A ẋ = −B q̇_a (k × k) at q, and the scaled singularity measures."""

    A: np.ndarray
    B: np.ndarray
    measure_type1: float
    measure_type2: float

    def output_jacobian(self) -> np.ndarray:
        """Closed-loop output Jacobian J_out = −A⁻¹B (ẋ = J_out q̇_a).

        Raises:
            SingularConfigurationError: A singular (type-2 singularity).
        """
        if self.measure_type2 < SINGULAR_TOL:
            raise SingularConfigurationError(
                f"type-2 singularity (measure {self.measure_type2:.2e} < {SINGULAR_TOL:.0e}): "
                "the output Jacobian −A⁻¹B does not exist"
            )
        return -np.linalg.solve(self.A, self.B)


def _scale(mech: Mechanism) -> np.ndarray:
    """L for the angular output rows, 1 for the translations."""
    loops = mech.require_loops()
    return np.where(loops.output.angular, loops.length_scale, 1.0)


def closure_jacobian(mech: Mechanism, q: np.ndarray) -> np.ndarray:
    """J_c with its rows reduced to an independent set (rank-revealing SVD) where the
    closures are over-constrained; Pinocchio's constraint Jacobian on models without mimic
    joints, the frame-Jacobian route otherwise."""
    if mech.coupling.has_mimic:
        jc = mech.residual_and_jacobian(q)[1]
    else:
        jc = pin_constraint_jacobian(mech.model, mech.require_loops(), q)
    r = constraint_rank(jc)
    if r < jc.shape[0]:
        u, _, _ = np.linalg.svd(jc)
        jc = u[:, :r].T @ jc
    return jc


def velocity_matrices(mech: Mechanism, q: np.ndarray) -> VelocityMatrices:
    """A and B from Pinocchio's constraint and frame Jacobians at a closed configuration q.

    Raises:
        InvalidInputError: q malformed, or the mechanism's mobility (nv − rank J_c) is not
            its number of drives.
    """
    q = mech.check_q(q)
    loops = mech.require_loops()
    jc = closure_jacobian(mech, q)
    s = _scale(mech)
    jx = mech.output_jacobian(q) * s[:, None]
    m, k = jc.shape[0], loops.dof
    if mech.nv - m != k or loops.output.dim != k:
        raise InvalidInputError(
            f"{mech.name}: mobility nv − rank J_c = {mech.nv - m} and {loops.output.dim} output "
            f"coordinates, but {k} drives; A and B need all three equal"
        )
    full = np.vstack([jc, jx])
    passive = full[:, loops.passive_v]
    u, _, _ = np.linalg.svd(passive)
    n_mat = u[:, passive.shape[1] :].T  # (k, m + k): left null space of the passive columns
    a_scaled = -n_mat[:, m:]
    b_mat = n_mat @ full[:, loops.drive_v]
    drive_cols = full[:, loops.drive_v] / loops.length_scale
    m1, m2 = _measures(a_scaled, b_mat / loops.length_scale, drive_cols)
    return VelocityMatrices(A=a_scaled * s[None, :], B=b_mat, measure_type1=m1, measure_type2=m2)


def _measures(
    a_scaled: np.ndarray, b_scaled: np.ndarray, drive_cols: np.ndarray
) -> tuple[float, float]:
    """(type 1, type 2) measures: σ_min/σ_max of B̃ and Ã; with one drive (1 × 1 matrices,
    whose ratio is always 1) the absolute |Ã| (N has orthonormal rows, so |Ã| ≤ 1) and
    |B̃| over the norm of the scaled drive column (a cosine, ≤ 1)."""
    if a_scaled.shape == (1, 1):
        norm = float(np.linalg.norm(drive_cols))
        return (abs(float(b_scaled[0, 0])) / norm if norm > 0 else 0.0, abs(float(a_scaled[0, 0])))
    sa = np.linalg.svd(a_scaled, compute_uv=False)
    sb = np.linalg.svd(b_scaled, compute_uv=False)
    # A matrix that vanishes (to rounding) next to what it is made of is singular: its
    # σ_min/σ_max would be a ratio of rounding errors (e.g. B ≡ 0 where several legs are
    # singular at once). B̃ is made of the drive columns, Ã of orthonormal rows (|Ã| ≤ 1).
    scale_b = float(np.linalg.norm(drive_cols, 2))
    return (
        float(sb[-1] / sb[0]) if sb[0] > SINGULAR_TOL * scale_b else 0.0,
        float(sa[-1] / sa[0]) if sa[0] > SINGULAR_TOL else 0.0,
    )


def passive_velocity(mech: Mechanism, q: np.ndarray, qd_drives: np.ndarray) -> np.ndarray:
    """Full q̇ (n,) for drive rates: q̇_p = −J_c,p⁻¹ J_c,a q̇_a [rad/s].

    Raises:
        SingularConfigurationError: J_c,p singular (type 2).
    """
    loops = mech.require_loops()
    _, jc = mech.residual_and_jacobian(q)
    jp = jc[:, loops.passive_v]
    if np.linalg.cond(jp) > 1.0 / SINGULAR_TOL:
        raise SingularConfigurationError("type-2 singularity: passive rates undetermined")
    qd = np.zeros(mech.model.nv)
    qd[loops.drive_v] = qd_drives
    qd[loops.passive_v] = -np.linalg.lstsq(jp, jc[:, loops.drive_v] @ qd_drives, rcond=None)[0]
    return qd


@dataclass(frozen=True)
class Classification:
    """Singularity class at q: flags, measures and the tolerance used."""

    type1: bool
    type2: bool
    measure_type1: float
    measure_type2: float
    tol: float

    @property
    def label(self) -> str:
        """``regular``, ``type 1``, ``type 2`` or ``type 1+2``."""
        if self.type1 and self.type2:
            return "type 1+2"
        return "type 1" if self.type1 else "type 2" if self.type2 else "regular"


def classify(mech: Mechanism, q: np.ndarray, tol: float = SINGULAR_TOL) -> Classification:
    """Type-1 / type-2 classification from A and B (module docstring)."""
    vm = velocity_matrices(mech, q)
    return Classification(
        vm.measure_type1 < tol, vm.measure_type2 < tol, vm.measure_type1, vm.measure_type2, tol
    )
