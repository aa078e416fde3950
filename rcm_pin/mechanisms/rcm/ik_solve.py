"""One pose at a time: the branches inside the joint limits, with worded errors.

Split from :mod:`rcm_pin.mechanisms.rcm.analytic_ik` (one idea per module); re-exported there.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from rcm_pin.errors import InvalidInputError, SingularConfigurationError, UnreachablePoseError
from rcm_pin.mechanisms.rcm.analytic_ik import ik_pose
from rcm_pin.mechanisms.rcm.closed_form import WristType
from rcm_pin.mechanisms.rcm.ik_solutions import Degeneracy, _violation
from rcm_pin.rotations import FloatArray, rot_x, rot_y

PI = np.pi


def _singular_message(code: Degeneracy, T: FloatArray, q: FloatArray, wrist: WristType) -> str:
    if code == Degeneracy.TOOL_AT_RCM:
        return (
            f"pose is singular ({code.name}): the tool centre is at the RCM point A "
            f"(|p| = {np.linalg.norm(T[:3, 3]):.3g} m <= pos_tol), q3 = 0 and q1, q2 and "
            "the wrist are not determined; valid poses have |p| > pos_tol"
        )
    if code == Degeneracy.AXIS_ALONG_BASE:
        return (
            f"pose is singular ({code.name}): the output axis e4 lies along the base "
            f"axis x (cos q2 = 0, q2 = {q[1]:+.6f} rad), so q1 is not determined (q1 "
            "only shifts the roll); valid poses have e4 off the x axis"
        )
    rw = (rot_x(q[0]) @ rot_y(q[1])).T @ T[:3, :3]
    phi = np.arctan2(-rw[0, 1], rw[1, 1])  # R_w = Rz(phi)·Ry(q5)
    if wrist == "zyz":
        comb = "q4 + q6" if q[4] < PI / 2 else "q4 - q6"
    else:
        comb = "q4 - q6" if q[4] > 0 else "q4 + q6"
    return (
        f"pose is singular ({code.name}): the wrist axes are aligned (q5 = {q[4]:+.6f} "
        f"rad), only {comb} = {phi:+.6f} rad is determined (branch 0: q1 = {q[0]:+.6f}, "
        f"q2 = {q[1]:+.6f} rad); valid poses keep the tool axis off the q4 axis"
    )


def solve_pose(
    T: ArrayLike,
    lower: ArrayLike | None = None,
    upper: ArrayLike | None = None,
    wrist_type: WristType = "zyz",
    **tols: float,
) -> list[FloatArray]:
    """IK solutions of one pose that lie within the joint limits.

    Args:
        T: One tool pose ``(4, 4)`` or ``(3, 4)``.
        lower: Lower limits ``(n,)`` (n = 6, or 4 with ``wrist_type=None``); None = −inf.
        upper: Upper limits ``(n,)``; None = +inf. Angles may be shifted by ±2π to fit.
        wrist_type: ``"zyz"``, ``"rpy"`` or ``None`` (4-DOF).
        **tols: Tolerances passed to :func:`ik_pose` / :func:`ik_pose_4dof`.

    Returns:
        The solutions, arrays ``(n,)``, in branch order.

    Raises:
        InvalidInputError: Not a single pose, NaN / infinite entries.
        NotARotationError: R too far from SO(3).
        SingularConfigurationError: Degenerate pose (names the degeneracy and what is valid).
        UnreachablePoseError: No branch within the limits (lists limits, closest branch).
    """
    a = np.asarray(T, dtype=np.float64)
    if a.shape not in ((4, 4), (3, 4)):
        raise InvalidInputError(f"T must have shape (4, 4) or (3, 4), got {a.shape}")
    sol = ik_pose(a, wrist_type, **tols)  # type: ignore[arg-type]
    code = Degeneracy(int(sol.degenerate[0]))
    if code != Degeneracy.NONE:
        raise SingularConfigurationError(_singular_message(code, a, sol.q[0, 0], wrist_type))
    nq = sol.q.shape[-1]
    lo = np.full(nq, -np.inf) if lower is None else np.asarray(lower, float)
    up = np.full(nq, np.inf) if upper is None else np.asarray(upper, float)
    if lo.shape != (nq,) or up.shape != (nq,):
        raise InvalidInputError(f"limits must have shape ({nq},), got {lo.shape}, {up.shape}")
    qf, ok = sol.fit_limits(lo, up)
    if not ok[0].any():
        viol = _violation(qf[0], lo, up).sum(-1)
        b = int(np.argmin(viol))
        raise UnreachablePoseError(
            f"no IK branch lies within the joint limits lower={np.round(lo, 6).tolist()}, "
            f"upper={np.round(up, 6).tolist()}; closest branch {b}: "
            f"q={np.round(qf[0, b], 6).tolist()} (total violation {viol[b]:.3g})"
        )
    return [qf[0, b].copy() for b in np.flatnonzero(ok[0])]
