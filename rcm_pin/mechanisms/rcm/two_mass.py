"""The two-mass dynamic model of paper 000 (Fig. 3): three DOF q1..q3.

Mass m moves with the tool centre :math:`p = q_3 e_4`, mass :math:`m_d` sits on the
output axis at the fixed distance L from A, :math:`p_d = L e_4 = p\\,L/q_3`, with
:math:`e_4 = [\\sin q_2, -\\sin q_1\\cos q_2, \\cos q_1\\cos q_2]` and the reduced mass
:math:`m_d = m_{int} + m_{init}/3 + m_{out}/3` of links 11, 9 and 2.

As :math:`\\partial e_4/\\partial q_1 = E_1`, :math:`\\partial e_4/\\partial q_2 = E_2`,
:math:`e_4, E_1/\\cos q_2, E_2` are orthonormal and the Lagrangian is

.. math::

    T = \\tfrac12 m \\dot q_3^2 + \\tfrac12 I(q_3)\\,(\\cos^2 q_2\\,\\dot q_1^2 + \\dot q_2^2),
    \\quad I = m q_3^2 + m_d L^2, \\qquad V = -(m q_3 + m_d L)\\, g\\cdot e_4 .

Lagrange's equations give the generalized (drive) forces (:func:`generalized_forces`)

.. math::

    Q_1 &= I c_2^2 \\ddot q_1 + 2 m q_3 \\dot q_3 c_2^2 \\dot q_1
           - 2 I s_2 c_2 \\dot q_1 \\dot q_2 - (m q_3 + m_d L)\\, g\\cdot E_1,\\\\
    Q_2 &= I \\ddot q_2 + 2 m q_3 \\dot q_3 \\dot q_2 + I s_2 c_2 \\dot q_1^2
           - (m q_3 + m_d L)\\, g\\cdot E_2,\\\\
    Q_3 &= m \\ddot q_3 - m q_3 (c_2^2 \\dot q_1^2 + \\dot q_2^2) - m\\, g\\cdot e_4 .

The same model as a Pinocchio mechanism is the catalogue entry ``rcm_two_mass``
(``xacro/rcm_two_mass.urdf.xacro``: point masses on the output link and the prismatic
body); ``tests/test_two_mass.py`` checks both routes agree.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rcm_pin.errors import InvalidInputError
from rcm_pin.model.mechanism import Mechanism


def reduced_mass(m_int: float, m_init: float, m_out: float) -> float:
    """Paper 000's reduced mass of links 11, 9, 2: m_d = m_int + m_init/3 + m_out/3 [kg]."""
    return m_int + m_init / 3.0 + m_out / 3.0


@dataclass(frozen=True)
class TwoMassParams:
    """Parameters of the two-mass model.

    Attributes:
        m: mass at the tool centre [kg].
        m_d: reduced mass on the output axis [kg].
        L: distance of m_d from A [m].
        g: gravity acceleration in the world frame [m/s²].
    """

    m: float = 0.4
    m_d: float = 0.2
    L: float = 0.2
    g: tuple[float, float, float] = (0.0, 0.0, -9.81)

    @classmethod
    def of(cls, mech: Mechanism) -> TwoMassParams:
        """Read m, m_d, L and gravity from a loaded ``rcm_two_mass`` mechanism."""
        inertias = mech.model.inertias
        g = mech.model.gravity.linear
        return cls(
            m=float(inertias[3].mass),
            m_d=float(inertias[2].mass),
            L=float(inertias[2].lever[2]),
            g=(float(g[0]), float(g[1]), float(g[2])),
        )


def two_mass_args(m: float = 0.4, m_d: float = 0.2, L: float = 0.2) -> dict[str, float]:
    """xacro arguments of ``rcm_two_mass`` for m, m_d, L given directly.

    m_d is passed as ``m_int`` (``m_init = m_out = 0``): ``load("rcm_two_mass",
    **two_mass_args(0.4, 0.2, 0.2), q3_upper=0.3)``.
    """
    return {"m": m, "m_int": m_d, "m_init": 0.0, "m_out": 0.0, "L": L}


def _axes(q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, float]:
    s1, c1, s2, c2 = np.sin(q[0]), np.cos(q[0]), np.sin(q[1]), np.cos(q[1])
    e4 = np.array([s2, -s1 * c2, c1 * c2])
    E1 = np.array([0.0, -c1 * c2, -s1 * c2])
    E2 = np.array([c2, s1 * s2, -c1 * s2])
    return e4, E1, E2, s2, c2


def _check(x: np.ndarray, name: str) -> np.ndarray:
    arr = np.asarray(x, dtype=float)
    if arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise InvalidInputError(f"{name} must be 3 finite numbers (q1, q2, q3); got {x!r}")
    return arr


def mass_matrix(params: TwoMassParams, q: np.ndarray) -> np.ndarray:
    """M(q) = diag(I cos² q2, I, m), I = m q3² + m_d L² (3, 3) [kg·m², kg]."""
    q = _check(q, "q")
    inertia = params.m * q[2] ** 2 + params.m_d * params.L**2
    return np.diag([inertia * np.cos(q[1]) ** 2, inertia, params.m])


def generalized_forces(
    params: TwoMassParams, q: np.ndarray, v: np.ndarray, a: np.ndarray
) -> np.ndarray:
    """Closed-form d'Alembert–Lagrange generalized forces Q1..Q3 (module docstring).

    Args:
        params: model parameters.
        q: (q1, q2, q3) [rad, rad, m].
        v: velocities [rad/s, rad/s, m/s].
        a: accelerations [rad/s², rad/s², m/s²].

    Returns:
        (Q1, Q2, Q3) [N·m, N·m, N].

    Raises:
        InvalidInputError: an argument is not 3 finite numbers.
    """
    q, v, a = _check(q, "q"), _check(v, "v"), _check(a, "a")
    m, m_d, L = params.m, params.m_d, params.L
    g = np.asarray(params.g, dtype=float)
    e4, E1, E2, s2, c2 = _axes(q)
    inertia = m * q[2] ** 2 + m_d * L**2
    lever = m * q[2] + m_d * L
    q1d, q2d, q3d = v
    Q1 = (
        inertia * c2**2 * a[0]
        + 2.0 * m * q[2] * q3d * c2**2 * q1d
        - 2.0 * inertia * s2 * c2 * q1d * q2d
        - lever * g @ E1
    )
    Q2 = inertia * a[1] + 2.0 * m * q[2] * q3d * q2d + inertia * s2 * c2 * q1d**2 - lever * g @ E2
    Q3 = m * a[2] - m * q[2] * (c2**2 * q1d**2 + q2d**2) - m * g @ e4
    return np.array([Q1, Q2, Q3])


def dalembert_forces(
    params: TwoMassParams, q: np.ndarray, v: np.ndarray, a: np.ndarray
) -> np.ndarray:
    """Q by the paper's d'Alembert–Lagrange route: Q = Jᵀ(m(p̈ − g)) + J_dᵀ(m_d(p̈_d − g)).

    The point accelerations are computed from p = q3 e4 and p_d = L e4 by the chain rule
    (the second-derivative terms written out), independently of the Lagrangian above.
    The paper prints p̈_d = p̈ L/q3 − 2 ṗ L q̇3/q3² + 2 p L q̈3/q3³; the correct last
    terms are + 2 p L q̇3²/q3³ − p L q̈3/q3² (used here through p_d = L e4).
    """
    q, v, a = _check(q, "q"), _check(v, "v"), _check(a, "a")
    g = np.asarray(params.g, dtype=float)
    e4, E1, E2, s2, c2 = _axes(q)
    s1, c1 = np.sin(q[0]), np.cos(q[0])
    E11 = np.array([0.0, s1 * c2, -c1 * c2])
    E12 = np.array([0.0, c1 * s2, s1 * s2])
    E22 = -e4
    e4d = E1 * v[0] + E2 * v[1]
    e4dd = E1 * a[0] + E2 * a[1] + E11 * v[0] ** 2 + 2 * E12 * v[0] * v[1] + E22 * v[1] ** 2
    p_dd = a[2] * e4 + 2 * v[2] * e4d + q[2] * e4dd
    pd_dd = params.L * e4dd
    J = np.column_stack([q[2] * E1, q[2] * E2, e4])
    Jd = np.column_stack([params.L * E1, params.L * E2, np.zeros(3)])
    return np.asarray(J.T @ (params.m * (p_dd - g)) + Jd.T @ (params.m_d * (pd_dd - g)))
