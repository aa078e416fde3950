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
scaled by the length L = ``mech.length_scale`` before the SVD so that every row is in
[m/rad]; A is converted back to (x, y [m], rz [rad]) afterwards.

Classification with a documented tolerance ``tol`` (default :data:`SINGULAR_TOL`):
    type 1 (loss of output DOF, B singular):  σ_min(B̃)/σ_max(B̃) < tol
    type 2 (uncontrolled output motion, A singular): σ_min(Ã)/σ_max(Ã) < tol
with Ã = −N[:, m:] (dimensionless) and B̃ = B/L, both computed in the scaled coordinates.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rcm_pin.closed_loop.core import ClosedMechanism
from rcm_pin.errors import SingularConfigurationError

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


def _scale(mech: ClosedMechanism) -> np.ndarray:
    return np.array([mech.length_scale if c.startswith("r") else 1.0 for c in mech.output_coords])


def velocity_matrices(mech: ClosedMechanism, q: np.ndarray) -> VelocityMatrices:
    """A and B from Pinocchio's constraint and frame Jacobians at a closed configuration q."""
    q = mech.check_q(q, mech.model.nq, "q")
    _, jc = mech.residual_and_jacobian_pin(q)
    s = _scale(mech)
    jx = mech.output_jacobian_open(q) * s[:, None]
    m = mech.n_constraints
    full = np.vstack([jc, jx])
    passive = full[:, mech.idx_passive]
    u, _, _ = np.linalg.svd(passive)
    n_mat = u[:, passive.shape[1] :].T  # (k, m + k): left null space of the passive columns
    a_scaled = -n_mat[:, m:]
    b_mat = n_mat @ full[:, mech.idx_driven]
    sa = np.linalg.svd(a_scaled, compute_uv=False)
    sb = np.linalg.svd(b_mat / mech.length_scale, compute_uv=False)
    return VelocityMatrices(
        A=a_scaled * s[None, :],
        B=b_mat,
        measure_type1=float(sb[-1] / sb[0]),
        measure_type2=float(sa[-1] / sa[0]),
    )


def passive_velocity(mech: ClosedMechanism, q: np.ndarray, qd_drives: np.ndarray) -> np.ndarray:
    """Full q̇ (n,) for drive rates: q̇_p = −J_c,p⁻¹ J_c,a q̇_a [rad/s].

    Raises:
        SingularConfigurationError: J_c,p singular (type 2).
    """
    _, jc = mech.residual_and_jacobian(q)
    jp = jc[:, mech.idx_passive]
    if np.linalg.cond(jp) > 1.0 / SINGULAR_TOL:
        raise SingularConfigurationError("type-2 singularity: passive rates undetermined")
    qd = np.zeros(mech.model.nv)
    qd[mech.idx_driven] = qd_drives
    qd[mech.idx_passive] = -np.linalg.solve(jp, jc[:, mech.idx_driven] @ qd_drives)
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


def classify(mech: ClosedMechanism, q: np.ndarray, tol: float = SINGULAR_TOL) -> Classification:
    """Type-1 / type-2 classification from A and B (module docstring)."""
    vm = velocity_matrices(mech, q)
    return Classification(
        vm.measure_type1 < tol, vm.measure_type2 < tol, vm.measure_type1, vm.measure_type2, tol
    )
