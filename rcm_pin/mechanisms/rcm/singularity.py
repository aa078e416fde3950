"""Named singularities of the RCM mechanisms and paper 003's claims, decided by rank.

The position block [q3 ∂e4/∂q1, q3 ∂e4/∂q2, e4] of the tool Jacobian has orthogonal
columns of norms |q3 cos q2|, |q3|, 1, and the 6×6 Jacobian is block-triangular, so
det J = q3²·cos q2·d_w with d_w = sin q5 (``zyz``) or −cos q5 (``rpy``). The causes: the
tool centre at A (q3 = 0), the output axis along the base axis e1 (cos q2 = 0: q1 spins
the axis about itself), the wrist axes aligned (e6 ∥ e4: at sin q5 = 0 for ``zyz``, at
cos q5 = 0 for ``rpy`` where R·x = ∓e4). q1 = ±π/2 is not a singularity: only the arcsin
form of the published inverse solution loses q1 there.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from rcm_pin.analysis.singularity import RANK_TOL, TASKS, analyse
from rcm_pin.analysis.singularity_model import Cause
from rcm_pin.errors import InvalidInputError
from rcm_pin.mechanisms.rcm.closed_form import wrist_type
from rcm_pin.model.mechanism import Mechanism


def classify(mech: Mechanism, q: ArrayLike, tol: float = RANK_TOL) -> list[Cause]:
    """Named singularity causes of an RCM mechanism at q (empty when regular).

    Thresholds mirror the SVD rank: |q3| ≤ tol, |cos q2| ≤ tol, |sin q5| ≤ tol (``zyz``),
    |cos q5| ≤ tol (``rpy``).

    Raises:
        InvalidInputError: not an RCM mechanism.
    """
    if mech.rcm_frame_id < 0:
        raise InvalidInputError(
            f"classify needs an RCM mechanism, got {mech.name}; valid: rcm_bevel, "
            "rcm_bevel_4dof, rcm_belt (use analyse() for any mechanism)"
        )
    q = mech.check_q(q)
    out: list[Cause] = []
    four = mech.nq == 4
    if abs(q[2]) <= tol:
        out.append(
            Cause(
                "tool_centre_at_A",
                "tool centre at the remote centre A: q1, q2 only turn the tool about A, "
                "it cannot translate across the output axis",
                "q3 = 0",
                ("position",) if four else ("full", "position"),
                0 if four else 2,
            )
        )
    if abs(np.cos(q[1])) <= tol:
        out.append(
            Cause(
                "output_axis_along_base_axis",
                "output axis e4 along the platform axis e1: q1 spins the axis about itself",
                "cos q2 = 0",
                ("full", "position"),
                1,
            )
        )
    wt = wrist_type(mech)
    if wt == "zyz" and abs(np.sin(q[4])) <= tol:
        out.append(
            Cause(
                "wrist_axes_aligned",
                "wrist axes e6 and e4 aligned: q4 and q6 turn the tool about the same axis",
                "sin q5 = 0",
                ("full",),
                1,
            )
        )
    if wt == "rpy" and abs(np.cos(q[4])) <= tol:
        out.append(
            Cause(
                "wrist_axes_aligned",
                "wrist axes e6 and e4 aligned (e6 = R x = -+e4): q4 and q6 turn the tool about "
                "the same axis",
                "cos q5 = 0",
                ("full",),
                1,
            )
        )
    return out


def is_singular_closed_form(mech: Mechanism, q: ArrayLike, task: str = "full") -> bool:
    """Whether :func:`classify` finds a cause affecting ``task``."""
    return any(task in c.tasks for c in classify(mech, q))


def paper_claims(mech: Mechanism, q_ref: ArrayLike | None = None) -> list[dict[str, object]]:
    """Verdicts on paper 003's claimed singularities (q3 = 0, q1 = ±π/2, q2 = ±π/2), by rank.

    Each claim sets one coordinate of a regular reference configuration q_ref (default:
    q = (0.3, 0.2, 0.08, 0.1, 0.5, 0.2), truncated to n) and compares the ranks of the full
    and position Jacobians with those at q_ref.

    Returns:
        One dict per claim: claim, q, ranks, verdict, explanation.
    """
    base = np.array([0.3, 0.2, 0.08, 0.1, 0.5, 0.2])[: mech.nq] if q_ref is None else q_ref
    base = mech.check_q(base)
    ref = {t: analyse(mech, base, t).rank for t in TASKS}
    claims = [("q3 = 0", 2, 0.0), ("q1 = +pi/2", 0, np.pi / 2), ("q1 = -pi/2", 0, -np.pi / 2)]
    claims += [("q2 = +pi/2", 1, np.pi / 2), ("q2 = -pi/2", 1, -np.pi / 2)]
    out = []
    for claim, k, val in claims:
        q = base.copy()
        q[k] = val
        ranks = {t: analyse(mech, q, t).rank for t in TASKS}
        lost = {t: ref[t] - ranks[t] for t in TASKS}
        singular = any(v > 0 for v in lost.values())
        causes = [c.name for c in classify(mech, q)]
        if singular:
            why = f"rank drops (full {ref['full']}->{ranks['full']}, position " + (
                f"{ref['position']}->{ranks['position']}); cause: {', '.join(causes)}"
            )
        else:
            why = (
                "Jacobian keeps full rank: an artefact of the arcsin form "
                "q1 = arcsin(-y/(q3 cos q2)) (arcsin's derivative is infinite at +-1); "
                "q1 = atan2(-y, z) is regular there"
            )
        out.append(
            {
                "claim": claim,
                "q": q.tolist(),
                "rank_full": ranks["full"],
                "rank_position": ranks["position"],
                "rank_full_regular": ref["full"],
                "rank_position_regular": ref["position"],
                "verdict": "mechanism singularity" if singular else "not a singularity",
                "explanation": why,
            }
        )
    return out


__all__ = ["classify", "is_singular_closed_form", "paper_claims"]
