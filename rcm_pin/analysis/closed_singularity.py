"""Type-1 / type-2 verdicts of closed mechanisms at an output pose, per working mode.

For every working mode of an output pose (:func:`rcm_pin.analysis.position.inverse`) the
report gathers three routes: the family's A and B from the paper's equations (their
normalised determinants), Pinocchio's A and B (:mod:`.loop_velocity`: singular values,
measures, verdict) and the screw test (:mod:`.screws`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rcm_pin.analysis.capabilities import position_solver
from rcm_pin.analysis.loop_velocity import SINGULAR_TOL, classify, velocity_matrices
from rcm_pin.analysis.passive_singularity import passive_report
from rcm_pin.analysis.position import PositionSolution, forward, inverse
from rcm_pin.analysis.screws import screw_test
from rcm_pin.analysis.singularity_model import singularity_model
from rcm_pin.errors import InvalidInputError
from rcm_pin.model.mechanism import Mechanism


def mode_labels(mech: Mechanism) -> tuple[str, ...]:
    """The family's working-mode labels (empty without a closed form)."""
    return position_solver(mech).mode_labels(mech)


def parse_mode(mech: Mechanism, text: str | int | None) -> int | None:
    """A working mode given as an index or a label -> index (None stays None).

    Raises:
        InvalidInputError: neither a valid index nor a valid label.
    """
    if text is None:
        return None
    labels = mode_labels(mech)
    s = str(text).strip()
    if s in labels:
        return labels.index(s)
    if s.isdigit() and int(s) < max(len(labels), 1):
        return int(s)
    valid = f"0..{len(labels) - 1} or " + ", ".join(labels) if labels else "0"
    raise InvalidInputError(f"mode {s!r} is not a working mode of {mech.name}; valid: {valid}")


def configuration_report(
    mech: Mechanism, q: np.ndarray, tol: float = SINGULAR_TOL, label: str = ""
) -> dict[str, Any]:
    """Every route's verdict at one closed configuration (type 2 alone without an output,
    :mod:`.passive_singularity`; no screw route without legs)."""
    loops = mech.require_loops()
    if not loops.output.present:
        return passive_report(mech, q, tol, label)
    vm = velocity_matrices(mech, q)
    c = classify(mech, q, tol)
    s = screw_test(mech, q, tol) if loops.legs else None
    scale = np.where(loops.output.angular, loops.length_scale, 1.0)
    ab = singularity_model(mech).ab_matrices(mech, q)
    return {
        "mode": label,
        "q": q,
        "residual": float(np.linalg.norm(mech.closure_residual(q))),
        "det_A": ab.det_A,
        "det_B": ab.det_B,
        "sigma_A": np.linalg.svd(vm.A / scale[None, :], compute_uv=False),
        "sigma_B": np.linalg.svd(vm.B / loops.length_scale, compute_uv=False),
        "measure_type1": c.measure_type1,
        "measure_type2": c.measure_type2,
        "type1": c.type1,
        "type2": c.type2,
        "verdict": c.label,
        "screw": None
        if s is None
        else {
            "measure_type1": s.measure_type1,
            "measure_type2": s.measure_type2,
            "type1": s.type1,
            "type2": s.type2,
            "leg_measures": s.leg_measures,
        },
        "screw_agrees": None if s is None else bool(s.type1 == c.type1 and s.type2 == c.type2),
    }


def pose_singularities(
    mech: Mechanism, pose: Any, mode: int | None = None, tol: float = SINGULAR_TOL
) -> dict[str, Any]:
    """The verdicts at an output pose, for every working mode (or for one mode).

    Raises:
        InvalidInputError: malformed pose or mode.
        UnreachablePoseError: the pose is outside the workspace.
    """
    result = inverse(mech, pose)
    sols: list[PositionSolution] = list(result.solutions)
    if mode is not None:
        if not 0 <= mode < len(sols):
            raise InvalidInputError(f"mode {mode}; valid: 0..{len(sols) - 1}")
        sols = [sols[mode]]
    modes = [
        dict(configuration_report(mech, s.q, tol, s.mode), index=i) for i, s in enumerate(sols)
    ]
    return {
        "mechanism": mech.name,
        "pose": result.given,
        "output_coords": list(mech.output.coords),
        "tol": tol,
        "modes": modes,
    }


def drive_singularities(mech: Mechanism, drives: Any, tol: float = SINGULAR_TOL) -> dict[str, Any]:
    """The verdicts of every assembly mode of drive values."""
    result = forward(mech, drives, all_modes=True)
    modes = [
        dict(configuration_report(mech, s.q, tol, s.mode), pose=s.output, assembly=s.mode)
        for s in result.solutions
    ]
    return {
        "mechanism": mech.name,
        "q_drives": result.given,
        "output_coords": list(mech.output.coords),
        "tol": tol,
        "modes": modes,
    }


__all__ = [
    "configuration_report",
    "drive_singularities",
    "mode_labels",
    "parse_mode",
    "pose_singularities",
]
