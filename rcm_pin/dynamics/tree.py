"""Rigid-body dynamics of a :class:`~rcm_pin.model.mechanism.Mechanism` with mimic joints.

Every function takes the *Mechanism coordinate vector* (the papers' q1..qn, e.g.
q1 platform 6, q2 initial link 9, q3 insertion, q4..q6 organ roll and wrist; see
``docs/conventions.md``) and returns generalized forces in the same order
([N·m] for revolute, [N] for prismatic coordinates). The equations of motion are

.. math:: M(q)\\,\\ddot q + b(q, \\dot q) = \\tau, \\qquad b = C(q, \\dot q)\\,\\dot q + g(q),

where the transmissions (mimic joints) are part of the model: with the coupling
:math:`q_{full} = G q + c`, :math:`\\dot q_{full} = G_v \\dot q` of the no-mimic parse,
:math:`M = G_v^T M_{full} G_v` and :math:`\\tau = G_v^T \\tau_{full}` (virtual work).

Pinocchio 4.1 on mimic models (checked in ``tests/test_dynamics.py``): ``rnea``,
``nonLinearEffects``, ``computeGeneralizedGravity`` and ``centerOfMass`` are right;
``crba`` (upper triangle only) only with ``pin.Convention.WORLD`` (the default
accumulates on repeated calls with one Data); ``computeCoriolisMatrix`` is wrong (the
no-mimic projection is used); ``aba``,
``computeKineticEnergy``, ``computePotentialEnergy``, ``computeMechanicalEnergy`` and
``computeAllTerms`` refuse mimic joints. Hence forward dynamics is a Cholesky solve,
:math:`T = \\tfrac12 \\dot q^T M \\dot q` and :math:`V = -m_{tot}\\, g \\cdot c(q)`.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError, SingularConfigurationError
from rcm_pin.lazy import lapack
from rcm_pin.model.mechanism import Mechanism

#: ``pin.crba`` convention: the default (LOCAL) accumulates into its buffers on repeated
#: calls with the same Data on mimic models in Pinocchio 4.1 (only the first call on a
#: fresh Data is right); the WORLD variant is right on every call.
_WORLD = pin.Convention.WORLD


def mass_matrix_pin(model: pin.Model, data: pin.Data, q_pin: np.ndarray) -> np.ndarray:
    """Symmetric joint-space inertia (nv, nv) of a Pinocchio model at its own q.

    ``pin.crba`` fills the upper triangle; on models with mimic joints only the WORLD
    convention is right on repeated calls (see ``_WORLD``), models without take the default.
    """
    if any(model.joints[j].shortname() == "JointModelMimic" for j in range(1, model.njoints)):
        M = np.asarray(pin.crba(model, data, q_pin, _WORLD))
    else:
        M = np.asarray(pin.crba(model, data, q_pin))
    return np.triu(M) + np.triu(M, 1).T


def _pin_v(mech: Mechanism, x: np.ndarray, name: str) -> np.ndarray:
    return mech.v_pin(mech.check_v(x, name))


def _pin_q(mech: Mechanism, q: np.ndarray) -> np.ndarray:
    return mech.to_pin(mech.check_q(q))


def inverse_dynamics(mech: Mechanism, q: np.ndarray, v: np.ndarray, a: np.ndarray) -> np.ndarray:
    """Drive efforts for a motion (recursive Newton–Euler on the mimic model).

    .. math:: \\tau = M(q)\\,\\ddot q + C(q, \\dot q)\\,\\dot q + g(q)

    Args:
        mech: the mechanism.
        q: coordinates (n,) [rad, m].
        v: velocities (n,) [rad/s, m/s].
        a: accelerations (n,) [rad/s², m/s²].

    Returns:
        Efforts (n,) [N·m, N].

    Raises:
        InvalidInputError: wrong shape or non-finite entries.
    """
    tau = pin.rnea(
        mech.model, mech.data, _pin_q(mech, q), _pin_v(mech, v, "v"), _pin_v(mech, a, "a")
    )
    return np.asarray(tau)[mech.v_index].copy()


def mass_matrix(mech: Mechanism, q: np.ndarray) -> np.ndarray:
    """Joint-space inertia matrix M(q) (n, n), symmetric [kg·m², kg·m, kg].

    ``pin.crba`` (WORLD convention, see ``_WORLD``) fills the upper triangle only; the
    result is symmetrised.
    """
    M = np.asarray(pin.crba(mech.model, mech.data, _pin_q(mech, q), _WORLD))
    M = np.triu(M) + np.triu(M, 1).T
    idx = mech.v_index
    return M[np.ix_(idx, idx)]


def nonlinear_effects(mech: Mechanism, q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Bias forces b(q, q̇) = C(q, q̇) q̇ + g(q) (n,) [N·m, N]."""
    b = pin.nonLinearEffects(mech.model, mech.data, _pin_q(mech, q), _pin_v(mech, v, "v"))
    return np.asarray(b)[mech.v_index].copy()


def gravity(mech: Mechanism, q: np.ndarray) -> np.ndarray:
    """Generalized gravity g(q) = ∂V/∂q (n,) [N·m, N] (``model.gravity``, default −9.81 z)."""
    g = pin.computeGeneralizedGravity(mech.model, mech.data, _pin_q(mech, q))
    return np.asarray(g)[mech.v_index].copy()


def coriolis_matrix(mech: Mechanism, q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Coriolis matrix C(q, q̇) with C q̇ + g = b and Ṁ − 2C skew-symmetric (n, n).

    ``pin.computeCoriolisMatrix`` is wrong on mimic models in Pinocchio 4.1 (C q̇ + g ≠ b
    by up to 4e-2 N·m on ``rcm_bevel``); as the coupling is constant (Ġ_v = 0),
    :math:`C = G_v^T C_{full}(G q + c, G_v \\dot q)\\, G_v` is used instead.
    """
    c = mech.coupling
    qp, vp = _pin_q(mech, q), _pin_v(mech, v, "v")
    model_full = mech.model_full
    Cf = np.asarray(
        pin.computeCoriolisMatrix(model_full, mech.data_full, c.q_full(qp), c.v_full(vp))
    )
    idx = mech.v_index
    return (c.Gv.T @ Cf @ c.Gv)[np.ix_(idx, idx)]


def forward_dynamics(mech: Mechanism, q: np.ndarray, v: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """Accelerations q̈ = M⁻¹(τ − b) by a Cholesky solve (``pin.aba`` refuses mimic joints).

    Args:
        mech: the mechanism.
        q: coordinates (n,) [rad, m].
        v: velocities (n,) [rad/s, m/s].
        tau: drive efforts (n,) [N·m, N].

    Returns:
        Accelerations (n,) [rad/s², m/s²].

    Raises:
        InvalidInputError: wrong shape or non-finite entries.
        SingularConfigurationError: M(q) is not positive definite.
    """
    tau = mech.check_v(tau, "tau")
    M = mass_matrix(mech, q)
    b = nonlinear_effects(mech, q, v)
    return solve_mass(M, tau - b)


def solve_mass(M: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Solve M x = rhs by Cholesky (LAPACK ``dposv``: ``potrf`` + ``potrs``, as scipy's
    ``cho_factor`` / ``cho_solve``, in one call; reads the lower triangle).

    Raises:
        SingularConfigurationError: M is not positive definite.
    """
    x, info = lapack("dposv")(M, rhs, lower=1)[1:]
    if info != 0:
        raise SingularConfigurationError(
            f"mass matrix is not positive definite (eigenvalues {np.linalg.eigvalsh(M)}); "
            "valid: a configuration where every coordinate moves some mass"
        )
    return np.asarray(x)


def solve_mass_upper(M: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Solve M x = rhs reading only the upper triangle of M (``pin.crba``'s output, no
    symmetrisation needed): LAPACK ``dposv`` on the upper triangle.

    Raises:
        SingularConfigurationError: M is not positive definite.
    """
    x, info = lapack("dposv")(M, rhs, lower=0)[1:]
    if info != 0:
        return solve_mass(np.triu(M) + np.triu(M, 1).T, rhs)  # raises with the eigenvalues
    return np.asarray(x)


def kinetic_energy(mech: Mechanism, q: np.ndarray, v: np.ndarray) -> float:
    """Kinetic energy T = ½ q̇ᵀ M(q) q̇ [J]."""
    v = mech.check_v(v, "v")
    return float(0.5 * v @ mass_matrix(mech, q) @ v)


def potential_energy(mech: Mechanism, q: np.ndarray) -> float:
    """Gravitational potential energy V = −m_tot g·c(q) [J] (zero at the world origin)."""
    model, data = mech.model, mech.data
    com = pin.centerOfMass(model, data, _pin_q(mech, q))
    return float(-data.mass[0] * model.gravity.linear @ com)


def total_energy(mech: Mechanism, q: np.ndarray, v: np.ndarray) -> float:
    """T + V [J]."""
    return kinetic_energy(mech, q, v) + potential_energy(mech, q)


def with_gravity(mech: Mechanism, g: np.ndarray | None = None) -> Mechanism:
    """A copy of ``mech`` with another gravity vector (None: zero gravity).

    Args:
        mech: the mechanism (left unchanged).
        g: gravity acceleration in the world frame (3,) [m/s²]; None for no gravity.

    Raises:
        InvalidInputError: g is not 3 finite numbers.
    """
    vec = np.zeros(3) if g is None else np.asarray(g, dtype=float)
    if vec.shape != (3,) or not np.all(np.isfinite(vec)):
        raise InvalidInputError(f"gravity {g!r} is invalid; valid: 3 finite numbers [m/s^2]")
    model, model_full = pin.Model(mech.model), pin.Model(mech.model_full)
    model.gravity.linear = vec
    model_full.gravity.linear = vec
    return mech.with_models(model, model_full)


def full_inverse_dynamics(
    mech: Mechanism, q: np.ndarray, v: np.ndarray, a: np.ndarray
) -> np.ndarray:
    """The independent route: RNEA of the no-mimic parse projected, G_vᵀ τ_full (n,)."""
    c = mech.coupling
    idx = mech.v_index
    qp = _pin_q(mech, q)
    vp, ap = _pin_v(mech, v, "v"), _pin_v(mech, a, "a")
    model_full = mech.model_full
    tau_full = pin.rnea(
        model_full, model_full.createData(), c.q_full(qp), c.v_full(vp), c.v_full(ap)
    )
    return (c.Gv.T @ np.asarray(tau_full))[idx]


def full_mass_matrix(mech: Mechanism, q: np.ndarray) -> np.ndarray:
    """The independent route: G_vᵀ M_full(G q + c) G_v (n, n)."""
    c = mech.coupling
    idx = mech.v_index
    model_full = mech.model_full
    Mf = np.asarray(pin.crba(model_full, mech.data_full, c.q_full(_pin_q(mech, q))))
    Mf = np.triu(Mf) + np.triu(Mf, 1).T
    M = c.Gv.T @ Mf @ c.Gv
    return M[np.ix_(idx, idx)]
