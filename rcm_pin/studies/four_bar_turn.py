"""A one-drive planar loop driven through a full crank turn on Pinocchio (second route).

The closed form of :mod:`rcm_pin.linkage` is checked against what the Pinocchio model of the
loop does: continuation on its closures (:func:`~rcm_pin.analysis.closed_position.
direct_position_path`) through θ ∈ [θ0, θ0 + 2π], the output angle ψ from the forward
kinematics of the output frame, and each extreme refined where the output rate
dψ/dθ = ω_z(q̇(θ)) (closure Jacobians, :func:`~rcm_pin.analysis.loop_velocity.
passive_velocity`) changes sign, by Brent's method on that rate (each evaluation a
continuation from the nearest sample), so the extremes are exact to the closure tolerance,
not to the grid. :func:`simulate` does it for a :class:`~rcm_pin.linkage.fourbar.FourBar`
on the catalogue's planar four-bar with its lengths (paper 002's pitch drive).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin
from scipy.optimize import brentq

from rcm_pin.analysis.closed_position import direct_position_path
from rcm_pin.analysis.loop_velocity import passive_velocity
from rcm_pin.catalog import load
from rcm_pin.linkage.fourbar import FourBar
from rcm_pin.model.mechanism import Mechanism


@dataclass(frozen=True)
class CrankTurn:
    """What Pinocchio measures over one crank turn (angles [rad]).

    Attributes:
        theta: sampled crank angles (n,); psi: output angle at each (n,).
        extremes: (θ, ψ) of each refined extreme, in crank order.
        psi_min, psi_max: the smallest and largest output angle.
        stroke: crank arc counter-clockwise from the ψ_min extreme to the ψ_max one.
        time_ratio: max / min of stroke and 2π − stroke.
        max_closure_residual: largest closure residual norm over the samples [m].
    """

    theta: np.ndarray
    psi: np.ndarray
    extremes: tuple[tuple[float, float], ...]
    psi_min: float
    psi_max: float
    stroke: float
    time_ratio: float
    max_closure_residual: float


def _rate(mech: Mechanism, q: np.ndarray) -> float:
    """dψ/dθ [rad/rad]: the output frame's ω_z for a unit crank rate."""
    qd = passive_velocity(mech, q, np.ones(1))
    pin.computeJointJacobians(mech.model, mech.data, q)
    pin.updateFramePlacements(mech.model, mech.data)
    jac = pin.getFrameJacobian(mech.model, mech.data, mech.output.frame_id, pin.LOCAL_WORLD_ALIGNED)
    return float(np.asarray(jac)[5] @ qd)


def crank_turn(mech: Mechanism, q_start: np.ndarray, n: int = 721) -> CrankTurn:
    """Drive the single drive of ``mech`` through a full turn from ``q_start``'s value.

    Args:
        mech: a closed mechanism with one revolute drive and a planar angle output (rz).
        q_start: a closed configuration on the circuit to follow.
        n: samples of the turn (the extremes are refined between them).

    Returns:
        The :class:`CrankTurn`.
    """
    loops = mech.require_loops()
    theta0 = float(q_start[loops.drive_q[0]])
    theta = theta0 + np.linspace(0.0, 2.0 * math.pi, n)
    qs = direct_position_path(mech, theta[:, None], q_start)
    psi = np.unwrap([float(mech.output_value(q)[0]) for q in qs])
    residual = max(float(np.linalg.norm(mech.closure_residual(q))) for q in qs)
    rates = np.array([_rate(mech, q) for q in qs])
    extremes = []
    for i in np.flatnonzero(np.sign(rates[:-1]) != np.sign(rates[1:])):
        q_seed = qs[i]

        def follow(t: float, q_seed: np.ndarray = q_seed, t0: float = theta[i]) -> np.ndarray:
            # continuation from the sample, not a bare Newton jump: near a type-2 pose a
            # Newton solve from the sample may land on the other circuit
            return direct_position_path(mech, np.array([[t0], [t]]), q_seed)[-1]

        t_star = brentq(
            lambda t: _rate(mech, follow(t)), theta[i], theta[i + 1], xtol=1e-15, rtol=1e-15
        )
        q_star = follow(t_star)
        psi_star = float(mech.output_value(q_star)[0])
        psi_star += 2.0 * math.pi * round((psi[i] - psi_star) / (2.0 * math.pi))
        extremes.append((float(t_star), psi_star))
    lo = min(extremes, key=lambda e: e[1])
    hi = max(extremes, key=lambda e: e[1])
    stroke = (hi[0] - lo[0]) % (2.0 * math.pi)
    ratio = max(stroke, 2.0 * math.pi - stroke) / min(stroke, 2.0 * math.pi - stroke)
    return CrankTurn(theta, psi, tuple(extremes), lo[1], hi[1], stroke, ratio, residual)


def pitch_model(g: FourBar) -> Mechanism:
    """The catalogue's planar four-bar with these lengths."""
    return load("four_bar", frame=g.l0, crank=g.l1, coupler=g.l2, rocker=g.l3)


def simulate(g: FourBar, n: int = 361) -> tuple[Mechanism, CrankTurn]:
    """The Pinocchio loop of ``g`` driven through a full crank turn from ``home``."""
    m = pitch_model(g)
    return m, crank_turn(m, m.home, n)


__all__ = ["CrankTurn", "crank_turn", "pitch_model", "simulate"]
