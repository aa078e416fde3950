"""Numeric routes of the closed-loop position problems (no closed form needed).

* :func:`solve_drives`: the rank-revealing Newton of :mod:`rcm_pin.model.newton` on the
  mechanism's (per-thread) data, or the same Newton in a CasADi closure kernel
  (:mod:`rcm_pin.model.kernels`) where one reproduces it (the result is the same to
  rounding; wherever the kernel declines, the numpy route runs from the same start);
* :func:`multistart_seeds` / :func:`inverse_seeds`: random starting configurations (a
  seeded generator, so results repeat), deduplicated after the solve by :func:`dedupe`;
* :func:`direct_position_multistart`: the purely numeric direct problem that the tests
  compare against the families' closed forms;
* :func:`direct_position_path`: continuation along a drive path on one assembly mode.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rcm_pin.analysis.results import PositionResult, PositionSolution
from rcm_pin.errors import SolverError
from rcm_pin.model import kernels
from rcm_pin.model.family import Branch
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.newton import MAX_ITER, MAX_STEP, solve_output, solve_passive
from rcm_pin.model.output import Output
from rcm_pin.rotations import wrap_angle

#: Two solutions are the same mode when their coordinates differ by less than this.
SAME_TOL = 1e-7


def solve_drives(
    mech: Mechanism,
    drives: np.ndarray,
    q0: np.ndarray,
    *,
    max_iter: int = MAX_ITER,
    max_step: float = MAX_STEP,
) -> tuple[np.ndarray, int, float]:
    """Passive joints for drive values from a starting configuration (Newton).

    Args:
        mech: a closed mechanism.
        drives: drive values (k,) [rad, m].
        q0: full starting configuration (nq,).
        max_iter, max_step: of :func:`rcm_pin.model.newton.solve_passive`.

    Returns:
        (q with passive revolute angles wrapped, iterations, final residual norm [m]).

    Raises:
        SolverError: no convergence (the numpy route's message).
    """
    mech.require_loops()
    kernel = kernels.closure_newton(mech)
    if kernel is not None:
        out = kernel(q0, drives, max_iter=max_iter, max_step=max_step)
        if out is not None:
            return out.q, out.iterations, out.residual
    return solve_numpy(mech, drives, q0, max_iter, max_step)


def solve_numpy(
    mech: Mechanism, drives: np.ndarray, q0: np.ndarray, max_iter: int, max_step: float
) -> tuple[np.ndarray, int, float]:
    """:func:`solve_drives` on the numpy route only (no kernel asked): where a kernel
    declined, or with the kernels disabled (the arguments as :func:`solve_drives`').

    Raises:
        SolverError: no convergence.
    """
    return solve_passive(
        mech.model, mech.data, mech.require_loops(), drives, q0, name=mech.name,
        max_iter=max_iter, max_step=max_step,
    )  # fmt: skip


def polish(
    mech: Mechanism, target: np.ndarray, output: Output, q0: np.ndarray
) -> tuple[np.ndarray, int, float]:
    """Newton over every joint on [closure; output − target] = 0 from a seed."""
    q, it, res, _ = solve_output(
        mech.model, mech.data, mech.require_loops(), output, target, np.asarray(q0, dtype=float)
    )
    return q, it, res


def difference(mech: Mechanism, qa: np.ndarray, qb: np.ndarray) -> np.ndarray:
    """qa − qb with revolute angles wrapped to [−π, π)."""
    d = np.asarray(qa, dtype=float) - np.asarray(qb, dtype=float)
    idx = mech.loops.revolute_q if mech.loops is not None else np.flatnonzero(mech.revolute)
    d[idx] = wrap_angle(d[idx])
    return d


def same(mech: Mechanism, qa: np.ndarray, qb: np.ndarray, tol: float = SAME_TOL) -> bool:
    """Whether two configurations are the same mode."""
    return float(np.max(np.abs(difference(mech, qa, qb)), initial=0.0)) < tol


def dedupe(mech: Mechanism, sols: list[PositionSolution]) -> list[PositionSolution]:
    """Solutions with distinct configurations, first occurrence kept."""
    out: list[PositionSolution] = []
    for s in sols:
        if not any(same(mech, s.q, o.q) for o in out):
            out.append(s)
    return out


def _random_q(mech: Mechanism, rng: np.random.Generator, n: int) -> np.ndarray:
    lo = np.where(np.isfinite(mech.lower), mech.lower, -np.pi)
    hi = np.where(np.isfinite(mech.upper), mech.upper, np.pi)
    lo = np.maximum(lo, -np.pi)
    hi = np.minimum(hi, np.pi)
    return rng.uniform(lo, hi, size=(n, mech.nq))


def multistart_seeds(
    mech: Mechanism, drives: np.ndarray, n_starts: int = 96, seed: int = 0
) -> list[np.ndarray]:
    """Random full configurations with the given drive values (seeded)."""
    rng = np.random.default_rng(seed)
    qs = _random_q(mech, rng, n_starts)
    qs[:, mech.require_loops().drive_q] = drives
    return list(qs)


def inverse_seeds(
    mech: Mechanism, target: np.ndarray, output: Output, n_starts: int = 96, seed: int = 0
) -> list[Branch]:
    """Working modes of an output target from random starts, then from ``home`` (last, so
    that the order of the random starts' modes stays), each polished and deduplicated."""
    rng = np.random.default_rng(seed)
    found: list[np.ndarray] = []
    for q0 in [*_random_q(mech, rng, n_starts), mech.home]:
        q, _, res = polish(mech, target, output, q0)
        if res < 1e-12 and not any(same(mech, q, f) for f in found):
            found.append(q)
    return [Branch(q, f"mode_{i}") for i, q in enumerate(found)]


def direct_position_multistart(
    mech: Mechanism, drives: Any, n_starts: int = 96, seed: int = 0
) -> PositionResult:
    """Purely numeric direct problem: Newton from random passive joints, deduplicated."""
    drives = mech.check_q(drives, "drives", mech.require_loops().dof)
    sols = []
    for q0 in multistart_seeds(mech, drives, n_starts, seed):
        try:
            q, it, res = solve_drives(mech, drives, q0)
        except SolverError:
            continue
        inside = bool(np.all(q >= mech.lower - 1e-12) and np.all(q <= mech.upper + 1e-12))
        sols.append(PositionSolution(q, mech.output_value(q), "multistart", res, it, inside))
    return PositionResult(
        mech,
        "forward",
        drives,
        mech.output,
        tuple(dedupe(mech, sols)),
        f"multistart Newton ({n_starts} starts)",
    )


def direct_position_path(
    mech: Mechanism, drives_path: Any, q_start: Any, jump_tol: float = 0.05
) -> np.ndarray:
    """Continuation along a drive path: stays on the assembly mode of ``q_start``.

    Predictor q_p += −J_p⁺ J_a Δq_a (tangent of the closure manifold), Newton corrector;
    a step is halved when the corrector moves farther than ``jump_tol`` [rad] from the
    prediction (a sign of a branch jump near a type-2 singularity) or fails.

    Returns:
        (T, n) configurations along the path.

    Raises:
        SolverError: the step was halved below 1e-9 of the path step.
    """
    loops = mech.require_loops()
    path = np.asarray(drives_path, dtype=float)
    if path.ndim != 2 or path.shape[1] != loops.dof or not np.all(np.isfinite(path)):
        from rcm_pin.errors import InvalidInputError

        raise InvalidInputError(
            f"drive path has shape {path.shape}; valid: (T, {loops.dof}) finite values"
        )
    out = np.zeros((len(path), mech.nq))
    q, _, _ = solve_drives(mech, path[0], mech.check_q(q_start, "q_start"))
    out[0] = q
    for t in range(1, len(path)):
        qa0, qa1 = path[t - 1], path[t]
        s, frac = 0.0, 1.0
        while s < 1.0:
            frac = min(frac, 1.0 - s)
            target = qa0 + (s + frac) * (qa1 - qa0)
            _, jac = mech.residual_and_jacobian(q)
            pred = q.copy()
            dqa = target - q[loops.drive_q]
            try:
                pred[loops.passive_q] -= np.linalg.lstsq(
                    jac[:, loops.passive_v], jac[:, loops.drive_v] @ dqa, rcond=None
                )[0]
                pred[loops.drive_q] = target
                qn, _, _ = solve_drives(mech, target, pred)
                ok = same(mech, qn, pred, jump_tol)
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


__all__ = [
    "SAME_TOL",
    "dedupe",
    "difference",
    "direct_position_multistart",
    "direct_position_path",
    "inverse_seeds",
    "multistart_seeds",
    "polish",
    "same",
    "solve_drives",
    "solve_numpy",
]
