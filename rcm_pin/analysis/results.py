"""Result types of the position problems (:mod:`rcm_pin.analysis.position`)."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output


@dataclass(frozen=True)
class PositionSolution:
    """One solution: coordinates, output value, label, residual, iterations, limits.

    Attributes:
        q: Mechanism coordinates (n,) [rad, m].
        output: value of the output coordinates (layout of the result's ``output``).
        mode: branch, working-mode or assembly-mode label.
        residual: closure residual (closed) or output error vs the target [m, rad].
        iterations: Newton iterations of the polish (0 for closed forms).
        within_limits: every coordinate inside its joint limits.
    """

    q: np.ndarray
    output: np.ndarray
    mode: str
    residual: float
    iterations: int
    within_limits: bool


@dataclass(frozen=True)
class PositionResult:
    """Every solution of one position problem (``kind`` = ``forward`` or ``inverse``)."""

    mechanism: Mechanism
    kind: str
    given: np.ndarray
    output: Output
    solutions: tuple[PositionSolution, ...]
    method: str

    @property
    def count(self) -> int:
        """Number of distinct solutions."""
        return len(self.solutions)

    def inputs(self, sol: PositionSolution) -> np.ndarray:
        """Input vector of a solution, as :func:`rcm_pin.forward` takes it: the drive values
        (closed) or the coordinates (serial) [rad, m]."""
        loops = self.mechanism.loops
        return sol.q.copy() if loops is None else sol.q[loops.drive_q].copy()

    def drives(self, sol: PositionSolution) -> dict[str, float]:
        """Drive values of a solution by drive name (serial: every coordinate)."""
        mech = self.mechanism
        if mech.loops is None:
            return dict(zip(mech.coordinate_names, sol.q.tolist(), strict=True))
        return dict(zip(mech.loops.drives, sol.q[mech.loops.drive_q].tolist(), strict=True))

    def to_json(self) -> dict[str, Any]:
        """Plain dict for the CLI and the report (schema in ``docs/cli.md``)."""
        mech = self.mechanism
        return {
            "mechanism": mech.name,
            "kind": self.kind,
            "given": self.given.tolist(),
            "method": self.method,
            "coordinates": list(mech.coordinate_names),
            "joint_names": list(mech.joint_names),
            "drive_names": list(mech.input_names),
            "output_frame": self.output.frame,
            "output_coords": list(self.output.coords),
            "count": self.count,
            "solutions": [self._solution_json(s) for s in self.solutions],
        }

    def _solution_json(self, sol: PositionSolution) -> dict[str, Any]:
        mech = self.mechanism
        out: dict[str, Any] = {
            "mode": sol.mode,
            "q": sol.q.tolist(),
            "drives": self.drives(sol),
            "output": self.output.to_json(sol.output),
            "pose": frame_placement(mech, sol.q).tolist(),
            "residual": sol.residual,
            "iterations": sol.iterations,
            "within_limits": sol.within_limits,
        }
        if mech.rcm is not None:
            from rcm_pin.analysis.kinematics import rcm_error

            out["rcm_error"] = rcm_error(mech, sol.q)
        return out


def closed_form_solutions(
    qs: Iterable[np.ndarray],
    outputs: Iterable[np.ndarray],
    modes: Iterable[str],
    residuals: Iterable[float],
    inside: Iterable[bool],
) -> list[PositionSolution]:
    """:class:`PositionSolution` s of checked closed-form branches (0 iterations), built
    without the frozen dataclass's ``__init__`` (six ``object.__setattr__`` calls each):
    the same objects, equal to the constructor's, about 40 % cheaper (a kernel's results)."""
    new, out = object.__new__, []
    for q, v, mode, res, ok in zip(qs, outputs, modes, residuals, inside):
        s = new(PositionSolution)
        d = s.__dict__  # (item stores: cheaper than one update call with keywords)
        d["q"], d["output"], d["mode"], d["residual"] = q, v, mode, res
        d["iterations"], d["within_limits"] = 0, ok
        out.append(s)
    return out


def one_solution(
    mech: Mechanism,
    kind: str,
    given: np.ndarray,
    method: str,
    solution: tuple[np.ndarray, np.ndarray, str, float, int, bool],
) -> PositionResult:
    """The :class:`PositionResult` of one :class:`PositionSolution` (its fields in
    ``solution``; the output is ``mech.output``), both built as
    :func:`closed_form_solutions` builds its solutions (equal to the constructors';
    :func:`rcm_pin.forward`'s hot path)."""
    new = object.__new__
    s, r = new(PositionSolution), new(PositionResult)
    d = s.__dict__
    d["q"], d["output"], d["mode"], d["residual"], d["iterations"], d["within_limits"] = solution
    d = r.__dict__
    d["mechanism"], d["kind"], d["given"] = mech, kind, given
    d["output"], d["solutions"], d["method"] = mech.output, (s,), method
    return r


def inverse_result(
    mech: Mechanism,
    given: np.ndarray,
    output: Output,
    solutions: tuple[PositionSolution, ...],
    method: str,
) -> PositionResult:
    """The :class:`PositionResult` of an inverse problem, built as
    :func:`closed_form_solutions` builds its solutions (equal to the constructor's)."""
    r = object.__new__(PositionResult)
    d = r.__dict__
    d["mechanism"], d["kind"], d["given"] = mech, "inverse", given
    d["output"], d["solutions"], d["method"] = output, solutions, method
    return r


def frame_placement(mech: Mechanism, q: np.ndarray) -> np.ndarray:
    """4×4 world placement of the output (tool) frame at coordinates q."""
    pin.forwardKinematics(mech.model, mech.data, mech.q_pin(q))
    return pin.updateFramePlacement(mech.model, mech.data, mech.output.frame_id).homogeneous


__all__ = [
    "PositionResult",
    "PositionSolution",
    "closed_form_solutions",
    "frame_placement",
    "inverse_result",
    "one_solution",
]
