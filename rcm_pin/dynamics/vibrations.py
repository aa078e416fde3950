"""Natural frequencies of any closed mechanism with its drives as springs (paper 004).

Each drive i is a linear spring of stiffness c_i about the pose (N·m/rad for a revolute
drive, N/m for a prismatic one), V = ½ Σ c_i (q_a,i − q⁰_a,i)². Near the closed configuration
q⁰ every small closed-loop motion is δq = S δq_a with S (nv × k) the tangent basis of the
closure manifold in drive coordinates::

    J_c S = 0,   S[drives] = I   (S[passive] = −J_c,p⁻¹ J_c,a)

so the kinetic energy is ½ δq̇_aᵀ M_q δq̇_a with M_q = Sᵀ M(q⁰) S (M: Pinocchio's mass
matrix of the cut-open tree) and the small free vibrations solve paper 004's frequency
equation

    det(C − ω² M_q) = 0,   C = diag(c_1, …, c_k)

(a symmetric-definite generalised eigenproblem): the frequencies ω_1 ≤ … ≤ ω_k [rad/s] and
M_q-orthonormal mode shapes in drive coordinates. Gravity is left out (the frequency
equation of the paper has only C and A; a gravity preload would add a geometric
stiffness): the spring pose is an equilibrium of the conservative system.

Second route (:func:`linearised_frequencies`): central finite differences of the
constrained forward dynamics (:func:`rcm_pin.dynamics.constrained.forward_dynamics`, the
KKT system with Baumgarte stabilisation, gravity cancelled by adding g(q) to the joint
efforts) about (q⁰, 0) on the full state (q, q̇) (2 nv). The closure manifold's tangent
is invariant under that linearisation, so its 2k eigenvalues ±iω_j are among the 2 nv
ones; the others are the Baumgarte roots −ω_B(ζ_B ± √(ζ_B² − 1)) (real, ζ_B = 2 here).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from rcm_pin.dynamics.constrained import forward_dynamics, world_closure
from rcm_pin.dynamics.tree import mass_matrix_pin
from rcm_pin.errors import InvalidInputError, SingularConfigurationError, SolverError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.newton import constraint_rank

#: Condition number of J_c,p beyond which the pose counts as type-2 singular (no tangent
#: basis in drive coordinates: an output motion with locked drives).
TANGENT_COND = 1e12
#: Baumgarte (ω [rad/s], ζ) of the linearised route: real, distinct constraint roots.
LINEARISE_BAUMGARTE = (50.0, 2.0)
#: Central-difference step [rad, m] of the linearised route (truncation ~h², rounding ~ε/h).
FD_STEP = 1e-5
#: Drive stiffnesses accepted [N·m/rad, N/m]: the two routes agree within (1e-11 at 1e10;
#: at 1e-6 planar_3rrr 3e-4, translational_3ppapa 3e-2, and at 1e-9 the linearisation no
#: longer separates the modes); c·FD_STEP stays ten times below the effort bound 1e6.
STIFFNESS_RANGE = (1e-3, 1e10)


@dataclass(frozen=True)
class Vibrations:
    """Small free vibrations of a closed mechanism about a pose (drives as springs).

    Attributes:
        q: the closed configuration (nq,) [rad, m].
        drives: drive names (k), the order of C, M_q and the mode shapes.
        stiffness: c_i (k,) [N·m/rad or N/m].
        mass: M_q = Sᵀ M S (k × k) [kg·m², kg].
        frequencies: ω_1 ≤ … ≤ ω_k (k,) [rad/s].
        modes: mode shapes (k × k), column j for ω_j, in drive coordinates, M_q-orthonormal
            (φ_jᵀ M_q φ_j = 1), largest entry positive.
        tangent: S (nv × k): the joint motion per unit drive motion.
        output_modes: J_x S φ_j (dim × k), the output's motion of each mode [m, rad].
    """

    q: np.ndarray
    drives: tuple[str, ...]
    stiffness: np.ndarray
    mass: np.ndarray
    frequencies: np.ndarray
    modes: np.ndarray
    tangent: np.ndarray
    output_modes: np.ndarray

    @property
    def frequencies_hz(self) -> np.ndarray:
        """f_j = ω_j / 2π [Hz]."""
        return self.frequencies / (2.0 * np.pi)

    def to_json(self) -> dict[str, Any]:
        """Plain dict (the CLI's ``--json`` document)."""
        return {
            "drives": list(self.drives),
            "stiffness": self.stiffness.tolist(),
            "frequencies": self.frequencies.tolist(),
            "frequencies_hz": self.frequencies_hz.tolist(),
            "modes": [self.modes[:, j].tolist() for j in range(len(self.drives))],
            "output_modes": [self.output_modes[:, j].tolist() for j in range(len(self.drives))],
            "mass": self.mass.tolist(),
            "q": self.q.tolist(),
        }


def stiffness_vector(
    mech: Mechanism, stiffness: float | Sequence[float] | np.ndarray
) -> np.ndarray:
    """c (k,) from one value for every drive or one per drive.

    Raises:
        InvalidInputError: wrong count, or a value outside :data:`STIFFNESS_RANGE`.
    """
    k = mech.require_loops().dof
    c = np.atleast_1d(np.asarray(stiffness, dtype=float)).ravel()
    if c.size == 1:
        c = np.full(k, float(c[0]))
    if c.size != k:
        raise InvalidInputError(
            f"stiffness has {c.size} values; valid: 1 or {k} (one per drive of {mech.name})"
        )
    lo, hi = STIFFNESS_RANGE
    if not np.all((c >= lo) & (c <= hi)):  # NaN fails both
        raise InvalidInputError(
            f"stiffness {c.tolist()} is outside the valid range; valid: {lo:g} to {hi:g} "
            "[N·m/rad, N/m] (above, the spring efforts of the linearisation step exceed the "
            "1e6 effort bound; below, the modes are too slow to separate from the closure "
            "stabilisation)"
        )
    return c


def tangent_basis(mech: Mechanism, q: np.ndarray) -> np.ndarray:
    """S (nv × k) with J_c S = 0 and S[drives] = I at a closed configuration q.

    Raises:
        SingularConfigurationError: J_c,p singular (type-2 singularity of the drive set).
    """
    q = mech.check_q(q)
    loops = mech.require_loops()
    jc = mech.constraint_jacobian(mech.q_pin(q))
    r = constraint_rank(jc)
    if r < jc.shape[0]:  # over-constrained closures: an independent set of rows
        u, _, _ = np.linalg.svd(jc)
        jc = u[:, :r].T @ jc
    jp, ja = jc[:, loops.passive_v], jc[:, loops.drive_v]
    if jp.shape[0] != jp.shape[1] or np.linalg.cond(jp) > TANGENT_COND:
        raise SingularConfigurationError(
            f"{mech.name}: the passive closure Jacobian is singular (type-2 singularity): "
            "the drives as springs do not hold the output; valid: a regular pose"
        )
    s = np.zeros((mech.nv, loops.dof))
    s[loops.drive_v] = np.eye(loops.dof)
    s[loops.passive_v] = -np.linalg.solve(jp, ja)
    return s


def reduced_mass(mech: Mechanism, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(M_q = Sᵀ M S (k × k), S (nv × k)) at a closed configuration q."""
    s = tangent_basis(mech, q)
    m_full = mass_matrix_pin(mech.model, mech.data, mech.q_pin(q))
    m_q = s.T @ m_full @ s
    return 0.5 * (m_q + m_q.T), s


def natural_frequencies(
    mech: Mechanism, q: np.ndarray, stiffness: float | Sequence[float] | np.ndarray
) -> Vibrations:
    """Frequencies and modes from det(C − ω² M_q) = 0 (module docstring).

    Args:
        q: a closed configuration (nq,) [rad, m] (e.g. a solution of ``rcm_pin.inverse``).
        stiffness: c for every drive, or one per drive [N·m/rad, N/m].

    Raises:
        InvalidInputError: malformed q or stiffness.
        SingularConfigurationError: a type-2 singular pose.
    """
    q = mech.check_q(q)
    c = stiffness_vector(mech, stiffness)
    m_q, s = reduced_mass(mech, q)
    import scipy.linalg  # lazy: scipy.linalg takes ~0.1 s to import

    w2, phi = scipy.linalg.eigh(np.diag(c), m_q)
    if np.any(w2 <= 0):
        raise SolverError(f"{mech.name}: M_q is not positive definite (ω² = {w2.tolist()})")
    flip = np.sign(phi[np.argmax(np.abs(phi), axis=0), np.arange(phi.shape[1])])
    phi = phi * flip[None, :]
    jx = mech.output_jacobian(mech.q_pin(q))
    return Vibrations(
        q=q,
        drives=tuple(mech.require_loops().drives),
        stiffness=c,
        mass=m_q,
        frequencies=np.sqrt(w2),
        modes=phi,
        tangent=s,
        output_modes=jx @ s @ phi,
    )


def spring_efforts(mech: Mechanism, q0: np.ndarray, c: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Joint efforts (nv,) of the drive springs −c (q_a − q⁰_a) [N·m, N]."""
    loops = mech.require_loops()
    tau = np.zeros(mech.model.nv)
    tau[loops.drive_v] = -c * (q[loops.drive_q] - q0[loops.drive_q])
    return tau


def spring_dynamics(
    mech: Mechanism,
    q0: np.ndarray,
    c: np.ndarray,
    baumgarte: tuple[float, float],
    gravity: bool = False,
) -> Any:
    """ẏ = f(y) of the free mechanism on its drive springs, y = (q, q̇) (2 nv,).

    Gravity is cancelled (g(q) added to the efforts) unless ``gravity``."""
    n = mech.model.nv
    model, data = mech.model, mech.model.createData()
    zero = np.zeros(n)

    def rhs(y: np.ndarray) -> np.ndarray:
        q, v = y[:n], y[n:]
        tau = spring_efforts(mech, q0, c, q)
        if not gravity:
            tau = tau + pin.rnea(model, data, q, zero, zero)
        return np.concatenate([v, forward_dynamics(mech, q, v, tau, baumgarte)[0]])

    return rhs


def linearised_frequencies(
    mech: Mechanism,
    q: np.ndarray,
    stiffness: float | Sequence[float] | np.ndarray,
    step: float = FD_STEP,
) -> np.ndarray:
    """ω_1 ≤ … ≤ ω_k [rad/s] from the eigenvalues of the finite-difference linearisation of
    the constrained forward dynamics about (q, 0) (module docstring, second route).

    Raises:
        InvalidInputError: dependent closure rows (the KKT matrix is singular).
        SolverError: fewer than k eigenvalue pairs on the imaginary axis (|Re λ| > 1e-5 |λ|).
    """
    q = mech.check_q(q)
    c = stiffness_vector(mech, stiffness)
    k, n = mech.require_loops().dof, mech.model.nv
    _, jc, _ = world_closure(mech, q, np.zeros(n))
    if constraint_rank(jc) < jc.shape[0]:
        raise InvalidInputError(
            f"{mech.name}: its closure rows are dependent (over-constrained loops), so the KKT "
            "forward dynamics that the linearised route differentiates is singular; valid: a "
            "model with independent closures (the frequency equation route works on both)"
        )
    f = spring_dynamics(mech, q, c, LINEARISE_BAUMGARTE)
    y0 = np.concatenate([q, np.zeros(n)])
    jac = np.zeros((2 * n, 2 * n))
    for i in range(2 * n):
        e = np.zeros(2 * n)
        e[i] = step
        jac[:, i] = (f(y0 + e) - f(y0 - e)) / (2.0 * step)
    lam = np.linalg.eigvals(jac)
    upper = lam[lam.imag > 0]
    ratio = np.abs(upper.real) / np.abs(upper)
    pick = upper[np.argsort(ratio)[:k]]
    if len(pick) < k or np.max(np.abs(pick.real) / np.abs(pick)) > 1e-5:
        raise SolverError(
            f"{mech.name}: the linearised dynamics has {int(np.sum(ratio <= 1e-5))} oscillating "
            f"eigenvalue pairs; expected {k}"
        )
    return np.sort(pick.imag)


__all__ = [
    "STIFFNESS_RANGE",
    "Vibrations",
    "linearised_frequencies",
    "natural_frequencies",
    "reduced_mass",
    "spring_dynamics",
    "spring_efforts",
    "stiffness_vector",
    "tangent_basis",
]
