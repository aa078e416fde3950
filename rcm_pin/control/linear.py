"""The linear error dynamics the computed-torque law is checked against (second route).

With a perfect model and no saturation every task coordinate of the error obeys

.. math:: \\ddot e + K_c \\dot e \\pm K_n e = (1 - f)\\,\\ddot x_T(t)

(f = 1 with feed-forward; −K_n with paper 000's printed sign). :func:`error_response` is
the closed form of the homogeneous case in paper 004's form τ²ë + 2ζτė + e = 0;
:func:`linear_error` integrates the forced case numerically.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from rcm_pin.control.computed_torque import Gains
    from rcm_pin.control.references import CartesianTrajectory


def error_response(
    t: np.ndarray, tau: float, zeta: float, e0: np.ndarray, de0: np.ndarray
) -> np.ndarray:
    """Closed-form e(t) (N, k) of τ² ë + 2ζτ ė + e = 0 from e(0) = e0, ė(0) = de0."""
    t = np.asarray(t, dtype=float)[:, None]
    e0, de0 = np.asarray(e0, dtype=float), np.asarray(de0, dtype=float)
    wn, z = 1.0 / tau, zeta
    if abs(z - 1.0) < 1e-9:
        return np.exp(-wn * t) * (e0 + (de0 + wn * e0) * t)
    if z < 1.0:
        wd = wn * np.sqrt(1.0 - z * z)
        return np.exp(-z * wn * t) * (
            e0 * np.cos(wd * t) + (de0 + z * wn * e0) / wd * np.sin(wd * t)
        )
    r = wn * np.sqrt(z * z - 1.0)
    s1, s2 = -z * wn + r, -z * wn - r
    c1 = (de0 - s2 * e0) / (s1 - s2)
    return c1 * np.exp(s1 * t) + (e0 - c1) * np.exp(s2 * t)


def linear_error(
    gains: Gains,
    e0: np.ndarray,
    de0: np.ndarray,
    t: np.ndarray,
    forcing: CartesianTrajectory | None = None,
    printed_sign: bool = False,
) -> np.ndarray:
    """Prediction of the error e = p_t − p by the linear error dynamics.

    .. math:: \\ddot e + K_c \\dot e \\pm K_n e = a_t(t)\\ (\\text{without feed-forward})
              \\text{ or } 0

    Args:
        gains: K_n, K_c.
        e0: initial error (k,) [m].
        de0: initial error rate (k,) [m/s].
        t: increasing output times (N,) [s], t[0] the initial time.
        forcing: the trajectory whose acceleration drives the error (no feed-forward);
            None with feed-forward.
        printed_sign: −K_n instead of K_n (paper 000's printed law).

    Returns:
        e(t) (N, k) [m].
    """
    e0, de0 = np.atleast_1d(np.asarray(e0, float)), np.atleast_1d(np.asarray(de0, float))
    k = e0.size
    kpos = -gains.kn if printed_sign else gains.kn

    def rhs(time: float, y: np.ndarray) -> np.ndarray:
        f = forcing.acceleration(time)[:k] if forcing is not None else 0.0
        return np.concatenate([y[k:], f - gains.kc * y[k:] - kpos * y[:k]])

    from scipy.integrate import solve_ivp  # lazy: scipy.integrate is slow to import

    sol = solve_ivp(
        rhs,
        (t[0], t[-1]),
        np.concatenate([e0, de0]),
        method="DOP853",
        t_eval=t,
        rtol=1e-12,
        atol=1e-14,
    )
    return np.asarray(sol.y[:k].T)


__all__ = ["error_response", "linear_error"]
