"""The control loop of the programmable RCM: positioning an arm on the trocar, then one
:class:`~rcm_pin.control.rcm_qp.RcmQP` step per reference sample at the control rate."""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Literal

import numpy as np

from rcm_pin.control.rcm_qp import RcmQP
from rcm_pin.errors import SolverError, UnreachablePoseError

#: Step [s] and count of the posture settling at the start of a run (posture gain × dt =
#: 0.1 per step: the null-space error shrinks by 0.9 per step, 1e-13 after 300).
SETTLE_DT = 0.1
SETTLE_STEPS = 300


@dataclass(frozen=True)
class RcmRun:
    """A tracked path at control rate (chain order).

    Attributes:
        t: (N + 1,) sample times [s].
        q: (N + 1, n) configurations.
        p_tip: (N + 1, 3) tip positions [m].
        rcm_error: (N + 1,) distance of p_T from the shaft line [m].
        tip_error: (N + 1,) |p_tip − p_ref| [m].
        step_time: (N,) wall time of each QP step [s].
    """

    t: np.ndarray
    q: np.ndarray
    p_tip: np.ndarray
    rcm_error: np.ndarray
    tip_error: np.ndarray
    step_time: np.ndarray


def position(
    ctrl: RcmQP, q0: np.ndarray, p_target: np.ndarray, *, max_steps: int = 4000,
    dt: float = 0.01, tol: float = 1e-12, settle: bool = False,
) -> np.ndarray:  # fmt: skip
    """Bring the arm from ``q0`` to the tip at ``p_target`` with the shaft through the
    trocar: soft RCM steps of length ``dt`` [s], then hard ones until both errors are
    below ``tol`` [m]. ``settle=True`` then lets the posture pull converge in the
    redundancy (hard steps of :data:`SETTLE_DT`, then a polish without it), so that a
    run started there does not begin with a null-space velocity jump.

    Raises:
        UnreachablePoseError: not reached within ``max_steps`` (trocar or target out of
            reach of the arm from this start, or a joint limit in the way).
    """
    q = np.asarray(q0, dtype=float).copy()
    s = ctrl.state(q)
    err = float(np.linalg.norm(s.p_tip - p_target))
    for _ in range(max_steps):
        hard, pull = s.distance < 1e-6, err > 1e-3  # posture pull only in the gross motion
        try:
            q = q + ctrl.step(q, p_target, hard=hard, dt=dt, posture=pull)
        except SolverError:
            q = q + ctrl.step(q, p_target, hard=False, dt=dt, posture=pull)
        s = ctrl.state(q)
        err = float(np.linalg.norm(s.p_tip - p_target))
        if err < tol and s.distance < tol:
            return _settle(ctrl, q, p_target, tol) if settle and ctrl.posture is not None else q
    raise UnreachablePoseError(
        f"trocar {list(ctrl.tool.trocar)} with the tip at {np.round(p_target, 4).tolist()} "
        f"is not reachable: after {max_steps} steps the RCM distance is {s.distance:.2e} m and "
        f"the tip error {err:.2e} m; valid: a trocar and path the arm reaches within its "
        "joint limits (rcm_pin.studies.rcm_comparison.choose_trocar finds one)"
    )


def _settle(ctrl: RcmQP, q: np.ndarray, p_target: np.ndarray, tol: float) -> np.ndarray:
    for _ in range(SETTLE_STEPS):
        dq = ctrl.step(q, p_target, dt=SETTLE_DT)
        q = q + dq
        if float(np.abs(dq).max()) < 1e-12:
            break
    return position(ctrl, q, p_target, tol=tol)


def track(
    ctrl: RcmQP, q0: np.ndarray, p_ref: np.ndarray, *, method: Literal["qp", "pink"] = "qp"
) -> RcmRun:
    """Follow ``p_ref`` (N + 1, 3) [m] sampled every ``ctrl.dt`` from ``q0`` (which puts
    the tip at ``p_ref[0]`` with the RCM met, e.g. :func:`position`)."""
    p_ref = np.asarray(p_ref, dtype=float)
    n = len(p_ref)
    qs = np.empty((n, ctrl.model.nq))
    tips, rcm, times = np.empty((n, 3)), np.empty(n), np.empty(n - 1)
    q = np.asarray(q0, dtype=float).copy()
    step = ctrl.step if method == "qp" else ctrl.step_pink
    s = ctrl.state(q)
    for k in range(n):
        qs[k], tips[k], rcm[k] = q, s.p_tip, s.distance
        if k == n - 1:
            break
        start = time.perf_counter()
        q = q + step(q, p_ref[k + 1])
        times[k] = time.perf_counter() - start
        s = ctrl.state(q)
    t = np.arange(n) * ctrl.dt
    return RcmRun(t, qs, tips, rcm, np.linalg.norm(tips - p_ref, axis=1), times)


__all__ = ["RcmRun", "position", "track"]
