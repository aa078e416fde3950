"""Position problems of closed mechanisms: inverse, direct (all modes), continuation.

Every solve ends with a Newton polish on Pinocchio's closure residual and is accepted only
with |e(q)| < 1e-12 m. Closed forms (:mod:`.planar_3rrr`, :mod:`.five_bar`) provide the
seeds that make "every mode" exhaustive; :func:`direct_position_multistart` is the purely
numeric route (random starts, deduplicated) that tests compare against them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from rcm_pin.closed_loop import five_bar as fb
from rcm_pin.closed_loop import planar_3rrr as p3
from rcm_pin.closed_loop.core import ClosedMechanism, wrap
from rcm_pin.errors import SolverError, UnreachablePoseError

#: A solve is accepted below this closure residual [m].
ACCEPT_TOL = 1e-12


@dataclass(frozen=True)
class PositionSolution:
    """One configuration: full q [rad], output pose, mode label, residual [m], iterations."""

    q: np.ndarray
    pose: np.ndarray
    mode: str
    residual: float
    iterations: int

    def to_json(self) -> dict[str, Any]:
        """Plain dict."""
        return {
            "q": self.q.tolist(),
            "pose": self.pose.tolist(),
            "mode": self.mode,
            "residual": self.residual,
            "iterations": self.iterations,
        }


@dataclass(frozen=True)
class PositionResult:
    """Solutions of a position problem (``kind`` = "direct" or "inverse")."""

    mechanism: str
    kind: str
    given: np.ndarray
    joint_names: tuple[str, ...]
    solutions: tuple[PositionSolution, ...]
    method: str

    @property
    def count(self) -> int:
        """Number of distinct modes found."""
        return len(self.solutions)

    def to_json(self) -> dict[str, Any]:
        """Plain dict for the CLI and the report."""
        return {
            "mechanism": self.mechanism,
            "kind": self.kind,
            "given": self.given.tolist(),
            "joint_names": list(self.joint_names),
            "method": self.method,
            "count": self.count,
            "solutions": [s.to_json() for s in self.solutions],
        }


def _same(qa: np.ndarray, qb: np.ndarray, tol: float = 1e-7) -> bool:
    return float(np.max(np.abs(wrap(qa - qb)))) < tol


def _dedupe(sols: list[PositionSolution]) -> list[PositionSolution]:
    out: list[PositionSolution] = []
    for s in sols:
        if not any(_same(s.q, o.q) for o in out):
            out.append(s)
    return out


def closed_form_inverse(mech: ClosedMechanism, pose: np.ndarray) -> list[tuple[str, np.ndarray]]:
    """Working modes (label, full q) from the mechanism's closed form."""
    if mech.name.startswith("planar_3rrr"):
        g = p3.Geometry3RRR.from_params(mech.params)
        qs, ok = p3.inverse_position(g, pose)
        if not ok:
            return []
        return [
            (f"{w:03b}".replace("0", "+").replace("1", "-"), p3.full_q(g, pose, qs[w]))
            for w in range(8)
        ]
    g5 = fb.GeometryFiveBar.from_params(mech.params)
    qs, ok = fb.inverse_position(g5, pose)
    if not ok:
        return []
    return [
        (f"{w:02b}".replace("0", "+").replace("1", "-"), fb.full_q(g5, pose, qs[w]))
        for w in range(4)
    ]


def closed_form_direct(mech: ClosedMechanism, q_drives: np.ndarray) -> list[np.ndarray]:
    """Assembly modes (full q) from the closed form (3-RRR sextic, five-bar circles)."""
    if mech.name.startswith("planar_3rrr"):
        g = p3.Geometry3RRR.from_params(mech.params)
        return [p3.full_q(g, pose, q_drives) for pose in p3.direct_position(g, q_drives)]
    g5 = fb.GeometryFiveBar.from_params(mech.params)
    return [fb.full_q(g5, p, q_drives) for p in fb.direct_position(g5, q_drives)]


def polish_inverse(
    mech: ClosedMechanism, pose: np.ndarray, q0: np.ndarray, max_iter: int = 20
) -> tuple[np.ndarray, int, float]:
    """Newton on [e(q); x(q) − pose] = 0 over all joints (square: m + k = n)."""
    q = np.array(q0, dtype=float)
    for it in range(max_iter + 1):
        e, jc = mech.residual_and_jacobian(q)
        dx = mech.output(q) - pose
        if "rz" in mech.output_coords:
            i = mech.output_coords.index("rz")
            dx[i] = wrap(dx[i])
        r = np.concatenate([e, dx])
        if np.linalg.norm(e) < ACCEPT_TOL * 0.1 and np.max(np.abs(dx)) < 1e-14:
            return wrap(q), it, float(np.linalg.norm(e))
        jac = np.vstack([jc, mech.output_jacobian_open(q)])
        q -= np.linalg.lstsq(jac, r, rcond=None)[0]
    return wrap(q), max_iter, float(np.linalg.norm(mech.closure_residual(q)))


def inverse_position(mech: ClosedMechanism, pose: np.ndarray) -> PositionResult:
    """Every working mode for an output pose (3-RRR: (x, y, φ), 8 modes; five-bar: (x, y), 4).

    Raises:
        InvalidInputError: pose of the wrong shape or not finite.
        UnreachablePoseError: some leg cannot reach its platform point.
    """
    pose = mech.check_q(pose, mech.dof, "pose")
    seeds = closed_form_inverse(mech, pose)
    if not seeds:
        raise UnreachablePoseError(
            f"{mech.name}: pose {pose.tolist()} is outside the workspace "
            "(a leg cannot reach its platform point: |l1 − l2| ≤ |A_i C_i| ≤ l1 + l2 fails)"
        )
    sols = []
    for label, q0 in seeds:
        q, it, res = polish_inverse(mech, pose, q0)
        if res >= ACCEPT_TOL:
            raise SolverError(f"{mech.name}: inverse polish residual {res:.2e} m for {label}")
        sols.append(PositionSolution(q, mech.output(q), label, res, it))
    return PositionResult(
        mech.name,
        "inverse",
        pose,
        mech.model.names[1:],
        tuple(sols),
        "closed form + Newton polish on Pinocchio closures",
    )


def direct_position(
    mech: ClosedMechanism,
    q_drives: np.ndarray,
    all_modes: bool = False,
    q_guess: np.ndarray | None = None,
) -> PositionResult:
    """Direct position problem: drives -> passive joints and output pose.

    Args:
        mech: mechanism.
        q_drives: drive angles (k,) [rad].
        all_modes: every assembly mode (closed-form seeds, Newton-polished), else one.
        q_guess: starting configuration (n,) for the single-mode solve (the branch followed);
            default: the first closed-form assembly mode.

    Raises:
        InvalidInputError: bad shape or non-finite drives.
        UnreachablePoseError: the drives admit no assembly (the loop cannot close).
        SolverError: Newton failed from ``q_guess``.
    """
    q_drives = mech.check_q(q_drives, mech.dof, "q_drives")
    if q_guess is not None and not all_modes:
        q0 = mech.check_q(q_guess, mech.model.nq, "q_guess")
        q, it, res = mech.solve_passive(q_drives, q0)
        sol = PositionSolution(q, mech.output(q), "guess", res, it)
        return PositionResult(
            mech.name, "direct", q_drives, mech.model.names[1:], (sol,), "Newton from guess"
        )
    seeds = closed_form_direct(mech, q_drives)
    if not seeds:
        raise UnreachablePoseError(
            f"{mech.name}: drives {q_drives.tolist()} admit no assembly (loop cannot close)"
        )
    sols = []
    for i, q0 in enumerate(seeds):
        q, it, res = mech.solve_passive(q_drives, q0)
        sols.append(PositionSolution(q, mech.output(q), f"assembly_{i}", res, it))
    sols = _dedupe(sols)
    if not all_modes:
        sols = sols[:1]
    return PositionResult(
        mech.name,
        "direct",
        q_drives,
        mech.model.names[1:],
        tuple(sols),
        "closed-form seeds + Newton on Pinocchio closures",
    )


def direct_position_multistart(
    mech: ClosedMechanism, q_drives: np.ndarray, n_starts: int = 96, seed: int = 0
) -> PositionResult:
    """Purely numeric direct problem: Newton/LM from random passive angles, deduplicated."""
    rng = np.random.default_rng(seed)
    sols = []
    for _ in range(n_starts):
        q0 = mech.assemble(q_drives, rng.uniform(-np.pi, np.pi, len(mech.passive)))
        try:
            q, it, res = mech.solve_passive(q_drives, q0, max_iter=60)
        except SolverError:
            continue
        sols.append(PositionSolution(q, mech.output(q), "multistart", res, it))
    sols = _dedupe(sols)
    return PositionResult(
        mech.name,
        "direct",
        np.asarray(q_drives),
        mech.model.names[1:],
        tuple(sols),
        f"multistart Newton/LM ({n_starts} starts)",
    )


def direct_position_path(
    mech: ClosedMechanism, q_drives_path: np.ndarray, q_start: np.ndarray, jump_tol: float = 0.05
) -> np.ndarray:
    """Continuation along a drive path: stays on the assembly mode of ``q_start``.

    Predictor q_p += −J_p⁻¹ J_a Δq_a (tangent of the closure manifold), Newton corrector;
    a step is halved when the corrector moves farther than ``jump_tol`` [rad] from the
    prediction (a sign of a branch jump near a type-2 singularity) or fails.

    Returns:
        (T, n) configurations [rad] along the path.

    Raises:
        SolverError: the step was halved below 1e-9 of the path step.
    """
    path = np.asarray(q_drives_path, dtype=float)
    out = np.zeros((len(path), mech.model.nq))
    q, _, _ = mech.solve_passive(path[0], q_start)
    out[0] = q
    for t in range(1, len(path)):
        qa0, qa1 = path[t - 1], path[t]
        s, frac = 0.0, 1.0
        while s < 1.0:
            frac = min(frac, 1.0 - s)
            target = qa0 + (s + frac) * (qa1 - qa0)
            _, jac = mech.residual_and_jacobian(q)
            pred = q.copy()
            dqa = target - q[mech.idx_driven]
            try:
                pred[mech.idx_passive] -= np.linalg.solve(
                    jac[:, mech.idx_passive], jac[:, mech.idx_driven] @ dqa
                )
                pred[mech.idx_driven] = target
                qn, _, _ = mech.solve_passive(target, pred)
                ok = _same(qn, pred, jump_tol)
            except (np.linalg.LinAlgError, SolverError):
                ok = False
            if ok:
                q, s = qn, s + frac
                frac = min(2.0 * frac, 1.0)
            else:
                frac *= 0.5
                if frac < 1e-9:
                    raise SolverError(f"{mech.name}: continuation stalled at path index {t}")
        out[t] = q
    return out
