"""Singularity verdicts of any mechanism, as one report shape (for the CLI and notebooks).

* serial: the SVD analysis of the tool Jacobian (tasks ``full`` and ``position``) and the
  family's named causes (:mod:`.singularity`);
* closed: type 1 / type 2 from A and B, the screw route and the family's determinants
  (:mod:`.closed_singularity`).

:func:`at_inputs` solves the forward problem first (every assembly mode of a closed
mechanism), :func:`at_target` the inverse problem (every branch / working mode), and
:func:`grid_map` maps a measure over two coordinates (serial) or over the workspace (closed).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rcm_pin.analysis import closed_singularity as cs
from rcm_pin.analysis import maps, singularity
from rcm_pin.analysis.capabilities import reference_poses
from rcm_pin.analysis.position import PositionResult, forward, inverse
from rcm_pin.errors import InvalidInputError
from rcm_pin.model.mechanism import Mechanism


def configuration(mech: Mechanism, q: np.ndarray, label: str = "") -> dict[str, Any]:
    """The verdicts at one configuration (module docstring)."""
    if mech.loops is not None:
        return cs.configuration_report(mech, q, label=label)
    analyses = {t: singularity.analyse(mech, q, t) for t in singularity.TASKS}
    causes = singularity.causes(mech, q)
    singular = analyses["full"].singular or bool(causes)
    return {
        "mode": label,
        "q": q,
        "rank_tolerance": singularity.RANK_TOL,
        **{t: a.to_json() for t, a in analyses.items()},
        "causes": [c.__dict__ for c in causes],
        "verdict": "singular" if singular else "regular",
    }


def _report(mech: Mechanism, result: PositionResult) -> dict[str, Any]:
    return {
        "mechanism": mech.name,
        "kind": result.kind,
        "given": result.given,
        "output_coords": list(result.output.coords),
        "tol": cs.SINGULAR_TOL if mech.loops is not None else singularity.RANK_TOL,
        "modes": [
            dict(configuration(mech, s.q, s.mode), output=result.output.to_json(s.output))
            for s in result.solutions
        ],
    }


def at_inputs(mech: Mechanism, inputs: Any) -> dict[str, Any]:
    """Verdicts for input values: coordinates (serial) or drives (every assembly mode)."""
    return _report(mech, forward(mech, inputs, all_modes=mech.loops is not None))


def at_target(
    mech: Mechanism, target: Any, coords: tuple[str, ...] | None = None, mode: int | None = None
) -> dict[str, Any]:
    """Verdicts for an output target: every branch / working mode (or one, by index)."""
    rep = _report(mech, inverse(mech, target, coords))
    if mode is not None:
        if not 0 <= mode < len(rep["modes"]):
            raise InvalidInputError(f"mode {mode}; valid: 0..{len(rep['modes']) - 1}")
        rep["modes"] = [rep["modes"][mode]]
    return rep


def base_configuration(mech: Mechanism) -> np.ndarray:
    """A regular configuration to map around (:class:`.capabilities.ReferencePoses`)."""
    return reference_poses(mech).regular(mech)


def grid_map(
    mech: Mechanism,
    coords: tuple[int, int] | None = None,
    n: int = 41,
    *,
    task: str = "full",
    measure: str = "manipulability",
    wide: bool = False,
    mode: int = 0,
    phi: float = 0.0,
    max_cells: int = 250_000,
) -> dict[str, Any]:
    """A measure over coordinates (i, j) (serial, 0-based) or over the workspace (closed).

    Raises:
        InvalidInputError: coordinates given for a closed mechanism or missing for a serial
            one, or more than ``max_cells`` grid cells.
    """
    if n * n > max_cells:
        raise InvalidInputError(f"grid of {n}x{n} cells; valid: at most {max_cells} cells")
    if mech.loops is not None:
        if coords is not None:
            raise InvalidInputError(
                f"{mech.name} maps over its workspace; valid: --grid without coordinates"
            )
        return maps.singularity_map(mech, mode, phi, n)
    if coords is None:
        raise InvalidInputError(
            f"{mech.name} maps over two coordinates; valid: --grid i,j[,N], e.g. 1,2,41"
        )
    i, j = coords
    q0 = base_configuration(mech)
    span = None
    if wide and 0 <= i < mech.nq and 0 <= j < mech.nq:
        reach = np.maximum(np.abs(mech.lower), np.abs(mech.upper))
        limits = [
            (-np.pi, np.pi) if r else (-reach[k], reach[k]) for k, r in enumerate(mech.revolute)
        ]
        span = (limits[i], limits[j])
    xs, ys, vals = singularity.grid(mech, q0, i, j, n, task, measure, span)
    return {
        "mechanism": mech.name,
        "base_q": q0,
        "coordinates": [i + 1, j + 1],
        "task": task,
        "measure": measure,
        "x": xs,
        "y": ys,
        "values": vals,
        "min": float(vals.min()),
        "max": float(vals.max()),
    }


__all__ = ["at_inputs", "at_target", "base_configuration", "configuration", "grid_map"]
