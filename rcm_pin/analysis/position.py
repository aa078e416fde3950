"""The position problems of every mechanism: :func:`forward` and :func:`inverse`.

* Serial mechanisms: ``forward`` maps coordinates to the tool pose (Pinocchio forward
  kinematics); ``inverse`` returns every branch of a tool pose (or of the tool position
  only) from the family's closed form where it has one (the RCM mechanisms' analytic IK),
  else from a multistart bounded least squares (:mod:`.serial_ik`). Every branch is checked
  by forward kinematics (the second route) and flagged against the joint limits.
* Closed mechanisms: ``forward`` (the direct problem) maps drive values to every assembly
  mode (distinct placements, :mod:`.assembly_modes`); ``inverse`` maps output
  coordinates to every working mode. Seeds come from the
  family's closed form, else from random starts (:mod:`.closed_position`); every solution
  ends with a Newton polish on Pinocchio's closures and is accepted only with a closure
  residual below :data:`ACCEPT_TOL`.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from rcm_pin.analysis import closed_position as cp
from rcm_pin.analysis import forward_route
from rcm_pin.analysis.assembly_modes import distinct_modes
from rcm_pin.analysis.assembly_modes import note as self_motion_note
from rcm_pin.analysis.branch_check import check_branches, placement, within_limits
from rcm_pin.analysis.capabilities import NumericPosition, position_solver
from rcm_pin.analysis.pose_target import plain_pose
from rcm_pin.analysis.results import (
    PositionResult,
    PositionSolution,
    closed_form_solutions,
    frame_placement,
    inverse_result,
)
from rcm_pin.analysis.serial_ik import check_starts
from rcm_pin.errors import InvalidInputError, SolverError, UnreachablePoseError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output
from rcm_pin.model.output_choice import require_output
from rcm_pin.model.serial_branches import BranchArrays, SerialBranches, serial_branches
from rcm_pin.rotations import numeric_array, pose_from_matrix, short_repr

#: A closed-loop solve is accepted below this closure residual [m].
ACCEPT_TOL = 1e-12


def forward(
    mech: Mechanism, q: Any, all_modes: bool = False, q_guess: Any = None
) -> PositionResult:
    """Forward (direct) position problem.

    Args:
        mech: the mechanism.
        q: serial: coordinates (n,) [rad, m]; closed: drive values (k,) [rad, m].
        all_modes: closed: every assembly mode (else the first one).
        q_guess: closed: full starting configuration (n,); the solve follows its branch.

    Raises:
        InvalidInputError: wrong shape or non-finite values.
        UnreachablePoseError: closed: the drives admit no assembly.
        SolverError: closed: Newton failed from ``q_guess``.
    """
    loops = mech.loops
    if loops is None:  # the hot paths: the general route's results, cheaper
        return forward_route.serial(mech, q)
    if q_guess is not None and not all_modes:
        return forward_route.from_guess(mech, loops, q, q_guess)
    drives = mech.check_q(q, "drives", loops.dof)
    found = position_solver(mech).direct(mech, drives)
    seeds, method = found.seeds, found.method
    sols: list[PositionSolution] = []
    for q0 in seeds:
        try:
            qs, it, res = cp.solve_drives(mech, drives, q0)
        except SolverError:
            continue
        sols.append(_closed_solution(mech, qs, f"assembly_{len(sols)}", res, it))
    sols = [  # numbered 0, 1, ... after merging (docs/conventions.md)
        replace(s, mode=f"assembly_{i}")
        for i, s in enumerate(distinct_modes(mech, cp.dedupe(mech, sols)))
    ]
    if not sols:
        raise UnreachablePoseError(
            f"{mech.name}: drives {drives.tolist()} admit no assembly (the loops cannot "
            f"close); valid: drive values inside the workspace of {mech.name}"
        )
    method += self_motion_note(mech, sols)
    sols = sols if all_modes else sols[:1]
    return PositionResult(mech, "forward", drives, mech.output, tuple(sols), method)


def _closed_solution(
    mech: Mechanism, q: np.ndarray, label: str, res: float, it: int
) -> PositionSolution:
    return PositionSolution(q, mech.output_value(q), label, res, it, within_limits(mech, q))


def inverse(
    mech: Mechanism,
    target: Any,
    coords: tuple[str, ...] | None = None,
    *,
    limits: bool = False,
    starts: int | None = None,
) -> PositionResult:
    """Inverse position problem: every branch / working mode for an output target.

    Args:
        mech: the mechanism.
        target: value of the output coordinates (``mech.output``: serial the tool pose as
            x, y, z and R, or a 4×4 / 3×4 matrix; closed the sidecar's output coordinates,
            a rotation as 9 numbers or a 3×3 matrix).
        coords: a subset of the output coordinates to solve for (e.g. ``("x", "y", "z")``:
            the tool position only; the other coordinates are free and left at 0).
        limits: keep only the solutions inside the joint limits.
        starts: starts of the numeric multistart, where no closed form answers (default:
            serial :data:`~rcm_pin.analysis.serial_ik.N_STARTS`, closed 96; seeded).

    Raises:
        InvalidInputError: malformed target or ``coords``.
        NotARotationError: a rotation too far from SO(3).
        SingularConfigurationError: a degenerate target (the family names the cause).
        UnreachablePoseError: no solution (or none inside the limits with ``limits``);
            from the numeric serial route only where the reach bound proves it.
        SolutionNotFoundError: the numeric serial route found none within ``starts``
            starts and nothing proves that none exists.
        UnknownFrameError: a closed mechanism without an output frame (lists candidates).
    """
    require_output(mech, "the inverse position problem")
    output = mech.output if coords is None else mech.output.subset(_coords(mech, coords))
    plain = coords is None and starts is None and mech.loops is None
    value, fast = _read(output, target, serial_branches(mech) if plain else None)
    if fast is not None:  # every branch checked in one compiled call (the same results)
        qs, outs, residuals, flags, labels, method = fast
        sols = closed_form_solutions(qs, outs, labels, residuals, flags)
    else:
        sols, method = _solutions(mech, output, value, starts)
    if not sols:
        raise UnreachablePoseError(
            f"{mech.name}: target {output.to_json(value)} is outside the workspace (no "
            f"{'branch' if mech.loops is None else 'working mode'} reaches it)"
        )
    if limits:
        inside = [s for s in sols if s.within_limits]
        if not inside:
            shown = "; ".join(f"{s.mode}: {violated_limits(mech, s.q)}" for s in sols[:4])
            more = f"; ... ({len(sols) - 4} more)" if len(sols) > 4 else ""
            raise UnreachablePoseError(
                f"{mech.name}: none of the {len(sols)} solutions of target "
                f"{_target_text(output, value)} lies within the joint limits ({shown}{more}); "
                "valid: a target with a solution inside the limits"
            )
        sols = inside
    return inverse_result(mech, value, output, tuple(sols), method)


def _read(
    output: Output, target: Any, kernel: SerialBranches | None
) -> tuple[np.ndarray, BranchArrays | None]:
    """The target's value and the kernel's branches of it (None: no kernel, or it declines:
    the numpy route). A plain matrix goes to the kernel unscreened: the kernel declines an
    R that :func:`plain_pose` would send to the SVD projection (``KEEP_TOL``); then, or
    for any other target, the value is read as without a kernel (projected if need be)."""
    if kernel is not None:
        raw = plain_pose(output, target, screen=False)
        fast = None if raw is None else kernel(raw)
        if raw is not None and fast is not None:
            return raw, fast
    value = plain_pose(output, target)
    if value is not None:  # as given: a kernel has declined this very value
        return value, None
    value = output.coerce(_as_value(output, target))
    return value, None if kernel is None else kernel(value)


def _solutions(
    mech: Mechanism, output: Output, value: np.ndarray, starts: int | None
) -> tuple[list[PositionSolution], str]:
    """The numpy route: the family's candidates, each checked (serial: Pinocchio FK of
    every branch) or polished (closed: Newton on the closures); and the method text."""
    solver = position_solver(mech)
    if starts is not None and isinstance(solver, NumericPosition):
        solver = solver.with_starts(check_starts(starts))
    found = solver.inverse(mech, value, output)
    branches, method = found.branches, found.method
    if mech.loops is None:  # the second route: Pinocchio FK of every branch
        return check_branches(mech, output, value, branches), method
    sols = []
    for b in branches:
        q, it, res = cp.polish(mech, value, output, b.q)
        if res >= ACCEPT_TOL:
            raise SolverError(f"{mech.name}: inverse polish residual {res:.2e} m for {b.label}")
        value_q = output.value(placement(mech, q))
        sols.append(PositionSolution(q, value_q, b.label, res, it, within_limits(mech, q)))
    # closed-form working modes stay distinct by label, even where they meet
    if not found.closed_form:
        sols = cp.dedupe(mech, sols)
    return sols, method


def violated_limits(mech: Mechanism, q: np.ndarray, tol: float = 1e-12) -> str:
    """The coordinates of q outside the joint limits, e.g. ``q3 = 0.173 > 0.12``."""
    parts = []
    for name, v, lo, hi in zip(mech.coordinate_names, q, mech.lower, mech.upper, strict=True):
        if v < lo - tol:
            parts.append(f"{name} = {v:.6g} < {lo:.6g}")
        elif v > hi + tol:
            parts.append(f"{name} = {v:.6g} > {hi:.6g}")
    return ", ".join(parts) or "inside"


def _target_text(output: Output, value: np.ndarray) -> str:
    """x=0.1, y=0.2, ... (a rotation as 'rotation')."""
    j = output.to_json(value)
    return ", ".join(f"{k}={v:.6g}" if isinstance(v, float) else k for k, v in j.items()
                     if k != "angles")  # fmt: skip


def _coords(mech: Mechanism, coords: Any) -> tuple[str, ...]:
    """``coords`` as a tuple of output tokens (a bare string or a non-sequence is refused)."""
    if isinstance(coords, (list, tuple)) and all(isinstance(c, str) for c in coords):
        return tuple(coords)
    raise InvalidInputError(
        f"coords {short_repr(coords)} is not a sequence of output coordinates; valid: a "
        f"tuple of tokens from {', '.join(mech.output.coords)}, e.g. ('x', 'y', 'z')"
    )


def _as_value(output: Output, target: Any) -> Any:
    """A homogeneous matrix as the value vector of a pose output (x, y, z, R)."""
    if output.coords != ("x", "y", "z", "rotation"):
        return target
    arr = numeric_array(target, "target")
    if arr.shape in ((4, 4), (3, 4)):
        R, p = pose_from_matrix(arr)
        return np.concatenate([p, R.reshape(9)])
    return target


__all__ = [
    "ACCEPT_TOL",
    "PositionResult",
    "PositionSolution",
    "forward",
    "frame_placement",
    "inverse",
    "within_limits",
]
