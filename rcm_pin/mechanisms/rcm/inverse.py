"""Analytic inverse kinematics of a loaded RCM :class:`~rcm_pin.model.mechanism.Mechanism`.

A thin layer over :mod:`rcm_pin.mechanisms.rcm.analytic_ik` (pure numpy, every branch) that
picks the wrist convention and the joint limits from the loaded model.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from rcm_pin.errors import InvalidInputError, SingularConfigurationError, UnknownMechanismError
from rcm_pin.mechanisms.rcm.analytic_ik import Degeneracy, ik_pose, ik_pose_4dof, ik_position
from rcm_pin.mechanisms.rcm.closed_form import wrist_type
from rcm_pin.mechanisms.rcm.ik_solve import solve_pose
from rcm_pin.model.mechanism import Mechanism


@dataclass(frozen=True)
class IKResult:
    """Every analytic branch for one tool pose.

    Attributes:
        q: branches, shape (n_branches, nq), in the Mechanism coordinate order; angles
            shifted by ±2π into the limits where that helps.
        within_limits: (n_branches,) which branches respect the joint limits.
        projection_distance: Frobenius distance of the target rotation from SO(3) (the
            target was projected onto the nearest rotation).
    """

    q: np.ndarray
    within_limits: np.ndarray
    projection_distance: float

    @property
    def feasible(self) -> list[np.ndarray]:
        """The branches inside the joint limits."""
        return [q for q, ok in zip(self.q, self.within_limits) if ok]


def _check_rcm(mech: Mechanism) -> None:
    if mech.rcm is None or mech.family.name != "rcm" or mech.nq not in (3, 4, 6):
        raise UnknownMechanismError(
            f"analytic IK is defined for the RCM mechanisms; {mech.name} is not one; "
            "valid: rcm_bevel, rcm_bevel_4dof, rcm_belt (or use ocp.ik for any arm)"
        )


def solve_ik(mech: Mechanism, T: ArrayLike) -> IKResult:
    """All analytic IK branches of a tool pose, flagged by the joint limits.

    Args:
        mech: an RCM mechanism (six-DOF: full pose; four-DOF: the tool z axis must lie
            along the output axis, q4 from the tool x axis).
        T: tool pose (4, 4) or (3, 4) [m]; the rotation is projected onto SO(3) when it
            is orthonormal within :data:`rcm_pin.rotations.ROTATION_TOL`.

    Returns:
        :class:`IKResult` with every branch (4 for four-DOF, 8 for six-DOF).

    Raises:
        SingularConfigurationError: degenerate pose (tool centre at A, output axis along
            the base axis, wrist axes aligned): no branch is picked arbitrarily.
        NotARotationError, InvalidInputError, UnreachablePoseError: see
            :mod:`rcm_pin.mechanisms.rcm.analytic_ik`.
    """
    _check_rcm(mech)
    a = np.asarray(T, dtype=float)
    if a.shape not in {(4, 4), (3, 4)}:
        raise InvalidInputError(f"T has shape {a.shape}; valid: (4, 4) or (3, 4)")
    sol = ik_pose(a, wrist_type(mech)) if mech.nq == 6 else ik_pose_4dof(a)
    if int(sol.degenerate[0]) != Degeneracy.NONE:
        if mech.nq == 6:
            solve_pose(a, wrist_type=wrist_type(mech))  # raises, wording the degeneracy
        raise SingularConfigurationError(
            f"pose is singular ({Degeneracy(int(sol.degenerate[0])).name}); "
            "valid poses keep the tool centre off A and the output axis off the base axis"
        )
    q, ok = sol.fit_limits(mech.lower, mech.upper)
    return IKResult(q=q[0].copy(), within_limits=ok[0].copy(),
                    projection_distance=float(sol.projection_distance[0]))  # fmt: skip


def solve_ik_within_limits(mech: Mechanism, T: ArrayLike) -> list[np.ndarray]:
    """The branches inside the joint limits.

    Raises:
        UnreachablePoseError: no branch inside the limits (the message lists the limits
            and the closest branch).
    """
    _check_rcm(mech)
    return solve_pose(
        T, mech.lower, mech.upper, wrist_type=wrist_type(mech) if mech.nq == 6 else None
    )


def solve_ik_position(mech: Mechanism, p: ArrayLike) -> IKResult:
    """Tool-centre position only: every (q1, q2, q3) branch (q4..qn are free).

    Args:
        mech: an RCM mechanism.
        p: tool-centre position (3,) [m].

    Returns:
        :class:`IKResult` whose ``q`` has shape (4, 3) and ``within_limits`` checks
        q1..q3 only.

    Raises:
        SingularConfigurationError: p at A (q1, q2 undetermined) or on the base axis x
            (q1 undetermined).
    """
    _check_rcm(mech)
    sol = ik_position(np.asarray(p, dtype=float))
    code = int(sol.degenerate[0])
    if code != Degeneracy.NONE:
        raise SingularConfigurationError(
            f"position is singular ({Degeneracy(code).name}); valid positions are off A "
            "and off the base axis x"
        )
    q, ok = sol.fit_limits(mech.lower[:3], mech.upper[:3])
    return IKResult(q=q[0].copy(), within_limits=ok[0].copy(), projection_distance=0.0)
