"""The check of a serial inverse's branches by Pinocchio forward kinematics, in one pass.

Every candidate of a serial inverse problem is checked by the second route: Pinocchio
forward kinematics of the branch must meet the target within
:data:`BRANCH_TOL` (max |e|, the output error of :meth:`rcm_pin.model.output.Output.error`),
and is flagged against the joint limits (:func:`within_limits`, tolerance
:data:`LIMIT_TOL`). :func:`check_branches` does it for all
branches at once: one validation of the stacked coordinates, one Pinocchio forward
kinematics per branch (no per-branch Python objects around it), then the output values,
the errors, the residuals and the limit flags as array operations over the branches. The
rotation error stays :func:`pinocchio.log3` of R·R_tᵀ per branch (the products batched).

Wherever the pass finds anything wrong (a malformed branch, a branch that misses the
target) it runs :func:`check_branches_reference`, the per-branch route it replaces, which
raises the same typed error with the same message; so what a branch must satisfy to be
returned, and every error, is that route's (tests/test_branch_check.py compares both on
seeded random poses of every serial family to 1e-12).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from rcm_pin.analysis.results import PositionSolution
from rcm_pin.errors import SolverError
from rcm_pin.model.family import Branch
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import _ANGLE, POSE, Output
from rcm_pin.model.output import _FLAT as _P
from rcm_pin.rotations import MAX_ABS, wrap_angle

#: A serial branch is accepted when its forward kinematics meets the target this well.
BRANCH_TOL = 1e-9
#: Joint-limit tolerance of the ``within_limits`` flag [rad, m].
LIMIT_TOL = 1e-12
#: The flattened entries (i·4 + j) of R[i, j], row by row.
_R = (0, 1, 2, 4, 5, 6, 8, 9, 10)


def within_limits(mech: Mechanism, q: np.ndarray, tol: float = LIMIT_TOL) -> bool:
    """Whether every coordinate lies in [lower − tol, upper + tol]."""
    lower, upper = mech.lower.tolist(), mech.upper.tolist()
    return all(lo - tol <= x <= hi + tol for x, lo, hi in zip(q.tolist(), lower, upper))


def placement(mech: Mechanism, q: np.ndarray) -> pin.SE3:
    """World placement of the output frame at Mechanism coordinates q."""
    pin.forwardKinematics(mech.model, mech.data, mech.q_pin(q))
    return pin.updateFramePlacement(mech.model, mech.data, mech.output.frame_id)


def check_branches_reference(
    mech: Mechanism, output: Output, target: np.ndarray, branches: Sequence[Branch]
) -> list[PositionSolution]:
    """The per-branch route: validate, forward kinematics, value, error, limits, one
    branch after the other (the reference of :func:`check_branches`).

    Raises:
        InvalidInputError: a branch that is not a finite (n,) coordinate vector.
        SolverError: a branch whose forward kinematics misses the target by more than
            :data:`BRANCH_TOL`.
    """
    sols = []
    for b in branches:
        q = mech.check_q(b.q, "branch")
        value_q = output.value(placement(mech, q))  # the second route: Pinocchio FK
        res = float(np.max(np.abs(output.error(value_q, target)), initial=0.0))
        if res > BRANCH_TOL:
            raise SolverError(
                f"{mech.name}: branch {b.label} misses the target by {res:.2e} "
                f"(> {BRANCH_TOL:g}) in forward kinematics"
            )
        sols.append(PositionSolution(q, value_q, b.label, res, 0, within_limits(mech, q)))
    return sols


def check_branches(
    mech: Mechanism, output: Output, target: np.ndarray, branches: Sequence[Branch]
) -> list[PositionSolution]:
    """Every branch checked as :func:`check_branches_reference` does, in one pass (module
    docstring): the same solutions, the same typed errors."""
    if not branches:
        return []
    Q = _stacked(mech, branches)
    if Q is None:  # a malformed branch: the reference raises its error
        return check_branches_reference(mech, output, target, branches)
    H, logs = _placements(mech, output, Q, target)
    values = _values(output, H)
    res = np.abs(_errors(output, values, logs, target)).max(axis=1)
    if not (res <= BRANCH_TOL).all():  # a miss (or NaN): the reference's error
        return check_branches_reference(mech, output, target, branches)
    box = (mech.lower - LIMIT_TOL <= Q) & (mech.upper + LIMIT_TOL >= Q)
    inside = np.asarray(box.all(axis=1))
    return [
        PositionSolution(q, v, b.label, r, 0, ok)
        for q, v, b, r, ok in zip(Q, values, branches, res.tolist(), inside.tolist())
    ]


def _stacked(mech: Mechanism, branches: Sequence[Branch]) -> np.ndarray | None:
    """The branches' coordinates (n_branches, nq), or None unless every one is a float64
    (nq,) vector of finite entries within ``MAX_ABS`` (what ``check_q`` accepts)."""
    try:
        Q = np.array([b.q for b in branches])
    except (TypeError, ValueError):  # ragged
        return None
    if Q.dtype != np.float64 or Q.shape != (len(branches), mech.nq):
        return None
    return Q if float(np.abs(Q).max()) <= MAX_ABS else None  # (NaN fails the comparison)


def _placements(
    mech: Mechanism, output: Output, Q: np.ndarray, target: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Pinocchio forward kinematics of every row of Q: the flattened 4×4 placements
    (B, 16) and log₃(R·R_tᵀ) (B, 3) of each for a ``rotation`` output (else (B, 0))."""
    model, data, frame_id = mech.model, mech.data, mech.output.frame_id  # as `placement`
    fk, frame = pin.forwardKinematics, pin.updateFramePlacement
    Qp = Q if mech.identity_order else mech.to_pin(Q)
    hs = []
    for qp in Qp:
        fk(model, data, qp)
        hs.append(frame(model, data, frame_id).homogeneous)
    H = np.array(hs)
    if "rotation" not in output.coords:
        return H.reshape(-1, 16), np.empty((len(H), 0))
    k = _offset(output, "rotation")
    A = H[:, :3, :3] @ target[k : k + 9].reshape(3, 3).T  # R·R_tᵀ, batched
    log3 = pin.log3
    return H.reshape(-1, 16), np.array([log3(a) for a in A])


def _offset(output: Output, token: str) -> int:
    """Index of ``token``'s first entry in a value vector."""
    k = 0
    for c in output.coords:
        if c == token:
            return k
        k += 9 if c == "rotation" else 1
    raise KeyError(token)


def _values(output: Output, H: np.ndarray) -> np.ndarray:
    """Output values (B, size) of flattened placements, as ``Output.value`` of each."""
    index = _INDEX.get(output.coords)
    if index is not None:  # translations and rotations only: one gather
        return H[:, index]
    cols: list[np.ndarray] = []
    for c in output.coords:
        if c in _P:
            cols.append(H[:, _P[c], None])
        elif c == "rotation":
            cols.append(H[:, _R])
        else:
            i, j = _ANGLE[c]
            cols.append(np.arctan2(H[:, i], H[:, j])[:, None])
    return np.concatenate(cols, axis=1)


def _errors(output: Output, values: np.ndarray, logs: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Errors (B, dim) of the values, as ``Output.error`` of each row (``logs``: the
    rotation's, from :func:`_placements`)."""
    if output.coords == POSE:
        return np.concatenate([values[:, :3] - target[:3], logs], axis=1)
    cols: list[np.ndarray] = []
    k = 0
    for c in output.coords:
        if c == "rotation":
            cols.append(logs)
            k += 9
        elif c in _P:
            cols.append(values[:, k, None] - target[k])
            k += 1
        else:
            cols.append(wrap_angle(values[:, k, None] - target[k]))
            k += 1
    return np.concatenate(cols, axis=1)


def _gather(coords: tuple[str, ...]) -> np.ndarray:
    return np.array([i for c in coords for i in ((_P[c],) if c in _P else _R)])


#: Value entries of the flattened placement, per output of translations and rotations.
_INDEX: dict[tuple[str, ...], np.ndarray] = {
    c: _gather(c) for c in (("x", "y", "z", "rotation"), ("x", "y", "z"), ("rotation",))
}


__all__ = [
    "BRANCH_TOL",
    "check_branches",
    "check_branches_reference",
    "placement",
    "within_limits",
]
