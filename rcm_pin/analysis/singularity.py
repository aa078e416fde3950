"""Singularities of any mechanism from the SVD of its Jacobians.

Serial mechanisms: measures of the tool Jacobian J (task ``"full"``: the 6×n tool
Jacobian [v; ω]; ``"position"``: its 3×n linear rows) from its singular values
σ1 ≥ … ≥ σk, k = min(m, n):

- rank = #{σi > RANK_TOL·σ1} (relative tolerance, documented, :data:`RANK_TOL` = 1e-9;
  the units are mixed [m] and [1], so the measures are for detection, not comparison
  across tasks);
- σ_min = σk, condition number κ = σ1/σk (∞ at rank loss);
- Yoshikawa manipulability w = Π σi = sqrt(det(J·Jᵀ)) for m ≤ n (sqrt(det(Jᵀ·J)) for m > n);
- null-space joint directions: right singular vectors of the zero singular values plus
  the n − m free ones (joint motions that do not move the tool);
- unreachable task directions: left singular vectors of the lost singular values.

Named causes come from the family's :class:`.singularity_model.SingularityModel` (e.g. the
RCM mechanisms' tool centre at A). Closed mechanisms: type 1 / type 2 from A and
B, :mod:`rcm_pin.analysis.loop_velocity`; :func:`analyse_configuration` serves both.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from rcm_pin.analysis.jacobians import tool_jacobian
from rcm_pin.analysis.singularity_model import Cause, singularity_model
from rcm_pin.errors import InvalidInputError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.rotations import FloatArray

#: Relative rank tolerance: σi counts when σi > RANK_TOL·σ1.
RANK_TOL = 1e-9
TASKS = ("full", "position")
MEASURES = ("manipulability", "sigma_min", "inverse_condition")


@dataclass(frozen=True)
class JacobianAnalysis:
    """SVD measures of the tool Jacobian at one configuration.

    Attributes:
        task: ``"full"`` (6×n) or ``"position"`` (3×n).
        singular_values: σ1 ≥ … ≥ σk.
        rank: numerical rank (tolerance RANK_TOL·σ1).
        full_rank: min(m, n).
        sigma_min: σk.
        condition: σ1/σk (inf at rank loss).
        manipulability: Π σi.
        null_space: (n, d) joint directions not moving the tool (orthonormal).
        unreachable: (m, d) task directions the tool cannot move along (orthonormal).
    """

    task: str
    singular_values: FloatArray
    rank: int
    full_rank: int
    sigma_min: float
    condition: float
    manipulability: float
    null_space: FloatArray
    unreachable: FloatArray

    @property
    def singular(self) -> bool:
        """Rank below min(m, n)."""
        return self.rank < self.full_rank

    def to_json(self) -> dict[str, object]:
        """JSON-ready dict."""
        return {
            "task": self.task,
            "rank": self.rank,
            "full_rank": self.full_rank,
            "singular": self.singular,
            "singular_values": self.singular_values.tolist(),
            "sigma_min": self.sigma_min,
            "condition": None if not np.isfinite(self.condition) else self.condition,
            "manipulability": self.manipulability,
            "null_space": self.null_space.T.tolist(),
            "unreachable_directions": self.unreachable.T.tolist(),
        }


def analyse_jacobian(J: ArrayLike, task: str = "full", tol: float = RANK_TOL) -> JacobianAnalysis:
    """SVD measures of a Jacobian (see the module docstring)."""
    J = np.asarray(J, dtype=float)
    m, n = J.shape
    U, s, Vt = np.linalg.svd(J)
    k = min(m, n)
    rank = int(np.sum(s > tol * max(s[0], 1e-300))) if k else 0
    sig_min = float(s[-1]) if k else 0.0
    cond = float(s[0] / s[-1]) if k and rank == k else float("inf")
    return JacobianAnalysis(
        task=task,
        singular_values=s,
        rank=rank,
        full_rank=k,
        sigma_min=sig_min,
        condition=cond,
        manipulability=float(np.prod(s)),
        null_space=Vt[rank:].T.copy(),
        unreachable=U[:, rank:].copy(),
    )


def analyse(
    mech: Mechanism, q: ArrayLike, task: str = "full", tol: float = RANK_TOL
) -> JacobianAnalysis:
    """SVD analysis of the Pinocchio tool Jacobian of any Mechanism.

    Args:
        mech: the mechanism.
        q: coordinates (n,) [rad, m].
        task: ``"full"`` (rows [v; ω]) or ``"position"`` (rows v).
        tol: relative rank tolerance.

    Raises:
        InvalidInputError: unknown task or bad q.
    """
    if task not in TASKS:
        raise InvalidInputError(f"task {task!r}; valid: {', '.join(TASKS)}")
    J = tool_jacobian(mech, q)
    return analyse_jacobian(J if task == "full" else J[:3], task, tol)


def causes(mech: Mechanism, q: ArrayLike) -> list[Cause]:
    """The family's named singularity causes at q (empty when regular or none known)."""
    return list(singularity_model(mech).causes(mech, mech.check_q(q)))


def measure(a: JacobianAnalysis, name: str) -> float:
    """``manipulability``, ``sigma_min`` or ``inverse_condition`` (1/κ, 0 at rank loss)."""
    if name == "manipulability":
        return a.manipulability
    if name == "sigma_min":
        return a.sigma_min
    if name == "inverse_condition":
        return 0.0 if a.singular else float(a.singular_values[-1] / a.singular_values[0])
    raise InvalidInputError(f"measure {name!r}; valid: {', '.join(MEASURES)}")


def grid(
    mech: Mechanism,
    q0: ArrayLike,
    i: int,
    j: int,
    n: int = 41,
    task: str = "full",
    name: str = "manipulability",
    span: tuple[tuple[float, float], tuple[float, float]] | None = None,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Map a measure over coordinates i, j (0-based), the others fixed at q0.

    Args:
        mech: the mechanism.
        q0: base configuration (n,).
        i: first coordinate index (0-based).
        j: second coordinate index (0-based, ≠ i).
        n: points per axis (≥ 2).
        task: ``"full"`` or ``"position"``.
        name: measure (:data:`MEASURES`).
        span: ((lo_i, hi_i), (lo_j, hi_j)); the joint limits when None (an unbounded
            side: ∓π).

    Returns:
        (values of q_i (n,), values of q_j (n,), measure (n, n) indexed [b, a] for
        q_i[a], q_j[b]).
    """
    q0 = mech.check_q(q0)
    if not (0 <= i < mech.nq and 0 <= j < mech.nq and i != j):
        raise InvalidInputError(
            f"grid coordinates {i + 1},{j + 1}; valid: two different numbers in 1..{mech.nq}"
        )
    if n < 2:
        raise InvalidInputError(f"grid size {n}; valid: >= 2")
    if span is None:
        lo = np.where(np.isfinite(mech.lower), mech.lower, -np.pi)  # unbounded: one turn
        hi = np.where(np.isfinite(mech.upper), mech.upper, np.pi)
        span = ((lo[i], hi[i]), (lo[j], hi[j]))
    xs, ys = np.linspace(*span[0], n), np.linspace(*span[1], n)
    out = np.empty((n, n))
    q = q0.copy()
    for b, y in enumerate(ys):
        for a_, x in enumerate(xs):
            q[i], q[j] = x, y
            out[b, a_] = measure(analyse(mech, q, task), name)
    return xs, ys, out


__all__ = [
    "MEASURES",
    "RANK_TOL",
    "TASKS",
    "JacobianAnalysis",
    "analyse",
    "analyse_jacobian",
    "causes",
    "grid",
    "measure",
]
