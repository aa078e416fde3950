"""Paper 000's tracking example as an optimal control problem on the six-DOF RCM model.

Reference (``rcm_pin.control.references``, ``paper000``): x = 0.1 + 0.01 sin wt,
y = 0.1 + 0.01 cos wt, z = 0.1 + 0.01 sin wt, w = 10 rad/s, over one period. Its
|p| reaches 0.186 m, beyond the rig's q3 upper limit of 0.12 m: the OCP uses widened
limits (q3 <= 0.25 m; angles keep their +-60 deg, the reference needs q1 in
[-49, -41] deg, q2 in [33, 37] deg). The wrist (q4..q6) does not move the tool centre; it is
held at 0 by a posture cost (feasible case) or locked by its bounds (limited case: with
5 N m drives on its ~1e-5 kg m^2 links it would otherwise act as a reaction wheel).

Exact solution, independent of the OCP: q1..q3 from the analytic inverse kinematics and
its derivatives (``rcm_pin.mechanisms.rcm.point.joint_reference``), efforts by Pinocchio's
RNEA.
On the collocation grid the OCP's zero-cost solution is "analytic IK at the collocation
points + the collocation velocity/acceleration + RNEA" (:func:`discrete_exact`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

import rcm_pin
from ocp.models import require_serial
from ocp.stagewise import Hessian
from ocp.tracking import TrackingOCP, TrackingResult
from rcm_pin.catalog import ENTRIES, get_entry
from rcm_pin.control.references import get_trajectory
from rcm_pin.control.task import task_kinematics
from rcm_pin.errors import InvalidInputError
from rcm_pin.mechanisms.rcm.point import joint_reference, point_ik

#: The mechanism of paper 000's example (the bevel-gear RCM mechanism).
MECHANISM = "rcm_bevel"
OMEGA = 10.0  # [rad/s]
HORIZON = 2.0 * np.pi / OMEGA  # one period [s]
Q3_UPPER = 0.25  # [m], widened from the rig's 0.12 m
WRIST_WEIGHT = 1e2  # posture weight on q4..q6 [1/rad^2] (position weight: 1e6 / m^2)


@dataclass(frozen=True)
class Trajectory:
    """Joint trajectory in Pinocchio order at times ``t``: q, v, a, tau (len(t), n)."""

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    tau: np.ndarray


def reference_position(t: np.ndarray) -> np.ndarray:
    """Tool-centre reference p(t) (..., 3) [m]."""
    return np.asarray(get_trajectory("paper000").position(t))


def limits(mech: rcm_pin.Mechanism, lock_wrist: bool) -> tuple[np.ndarray, np.ndarray]:
    """Joint limits in Pinocchio order: q3 <= 0.25 m, the wrist optionally locked at 0."""
    lo, hi = mech.lower.copy(), mech.upper.copy()
    hi[2] = Q3_UPPER
    if lock_wrist:
        lo[3:], hi[3:] = 0.0, 0.0
    return mech.to_pin(lo), mech.to_pin(hi)


def exact_solution(mech: rcm_pin.Mechanism, t: np.ndarray) -> Trajectory:
    """Analytic IK of the reference (and its derivatives) + Pinocchio inverse dynamics."""
    n, data = mech.nq, mech.model.createData()
    out = np.zeros((4, len(t), n))
    for k, tk in enumerate(np.asarray(t, dtype=float)):
        for i, x in enumerate(joint_reference(get_trajectory("paper000"), float(tk))):
            out[i, k, :3] = x
        q, v, a = (mech.to_pin(out[i, k]) for i in range(3))
        out[3, k] = mech.from_pin(pin.rnea(mech.model, data, q, v, a))
    return Trajectory(np.asarray(t), *(np.array([mech.to_pin(x) for x in o]) for o in out))


def initial_state(mech: rcm_pin.Mechanism) -> np.ndarray:
    """``x_init = (q, v)`` of the exact solution at t = 0."""
    ex = exact_solution(mech, np.zeros(1))
    return np.concatenate([ex.q[0], ex.v[0]])


def discrete_exact(ocp: TrackingOCP, mech: rcm_pin.Mechanism) -> Trajectory:
    """The OCP's zero-cost solution by the analytic route: ``point_ik`` of the reference
    at the collocation points, the collocation polynomials' velocities and accelerations,
    Pinocchio's RNEA."""
    tc, n, d, col = ocp.collocation_times(), mech.nq, ocp.col.degree, ocp.col
    coords = np.zeros((len(tc), n))
    coords[:, :3] = [point_ik(p) for p in reference_position(tc)]
    q = np.array([mech.to_pin(x) for x in coords]).reshape(ocp.N, d, n)
    x0 = initial_state(mech)
    qk, vk = x0[:n], x0[n:]
    vs, acc = np.zeros_like(q), np.zeros_like(q)
    for k in range(ocp.N):
        qall = np.vstack([qk, q[k]])
        vs[k] = col.D.T @ qall / ocp.h
        acc[k] = col.D.T @ np.vstack([vk, vs[k]]) / ocp.h
        qk, vk = col.E @ qall, col.E @ np.vstack([vk, vs[k]])
    data = mech.model.createData()
    qf, vf, af = (x.reshape(-1, n) for x in (q, vs, acc))
    tau = np.array([pin.rnea(mech.model, data, *s) for s in zip(qf, vf, af)])
    return Trajectory(tc, qf, vf, af, tau)


def build(
    name: str = MECHANISM,
    n_intervals: int = 100,
    *,
    degree: int = 3,
    solver: str = "ipopt",
    drive_limits: bool = True,
    lock_wrist: bool = False,
    jit: bool = False,
    hessian: Hessian | None = None,
    compile: bool | str = False,
    reduced: bool = True,
) -> tuple[TrackingOCP, rcm_pin.Mechanism]:
    """The tracking OCP of the tool centre of ``name`` over one period (``jit``,
    ``hessian``, ``compile``, ``reduced``: see :class:`ocp.tracking.TrackingOCP`).

    Raises:
        InvalidInputError: a closed mechanism, or one whose family has no closed-form
            tool centre p = q3·e4 (the exact solution needs it).
    """
    mech = rcm_pin.load(name)
    require_serial(mech, "paper 000's tracking OCP")
    task = mech.output.subset(("x", "y", "z"))
    if not task_kinematics(mech, task).closed_form:
        family = get_entry(MECHANISM).family  # the paper's mechanism
        valid = [e.name for e in ENTRIES if e.family is family]
        raise InvalidInputError(
            f"paper 000's tracking OCP needs the RCM tool centre p = q3·e4 (the analytic "
            f"exact solution); {mech.name} has none; valid: {', '.join(valid)}"
        )
    lo, hi = limits(mech, lock_wrist)
    weights = np.zeros(mech.nq)
    weights[3:] = WRIST_WEIGHT
    ocp = TrackingOCP(
        mech,
        "tool",
        horizon=HORIZON,
        n_intervals=n_intervals,
        degree=degree,
        lower=lo,
        upper=hi,
        drive_limits=drive_limits,
        posture_weights=mech.to_pin(weights),
        solver=solver,  # type: ignore[arg-type]
        jit=jit,
        hessian=hessian,
        compile=compile,
        reduced=reduced,
    )
    return ocp, mech


def solve(
    ocp: TrackingOCP,
    mech: rcm_pin.Mechanism,
    effort_limits: np.ndarray | None = None,
    raise_on_failure: bool = True,
    screen: bool = True,
) -> TrackingResult:
    """Track the paper's reference from the exact initial state (``screen``: see
    :meth:`ocp.tracking.TrackingOCP.solve`)."""
    return ocp.solve(
        reference_position,
        initial_state(mech),
        effort_limits=effort_limits,
        raise_on_failure=raise_on_failure,
        screen=screen,
    )


def peak_efforts(mech: rcm_pin.Mechanism, n: int = 2001) -> np.ndarray:
    """max_t |tau*(t)| of the exact solution (Pinocchio order)."""
    return np.abs(exact_solution(mech, np.linspace(0.0, HORIZON, n)).tau).max(0)


__all__ = [
    "HORIZON",
    "OMEGA",
    "Q3_UPPER",
    "Trajectory",
    "build",
    "discrete_exact",
    "exact_solution",
    "initial_state",
    "limits",
    "peak_efforts",
    "reference_position",
    "solve",
]
