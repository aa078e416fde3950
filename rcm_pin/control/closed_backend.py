"""The ``"compiled"`` backend of a closed plant (:mod:`rcm_pin.control.backends`).

The kernel kind :func:`rcm_pin.model.kernels.closed_rhs` (provider:
:mod:`ocp.kernels.closed_rhs`) is the whole closed right-hand side, the closed
computed-torque law and the plant's KKT forward dynamics, as one compiled CasADi function
that equals :class:`~rcm_pin.control.closed_hot_path.ClosedLaw` and
:class:`~rcm_pin.control.closed_hot_path.ClosedPlant` to rounding. It is built for
closure rows of full rank; a call where the plant's J_c is near a rank loss (or where
the result is not finite) declines, and that call runs the Python route (``fallback``)
from the same inputs. The output samples (efforts, task values) are recomputed by the
Python hot path, as for a serial plant.

Covered (:func:`closed_unsupported`): a task-space ComputedTorque on a closed model
without drive switching, plant and model Euclidean (no continuous joints, q and q̇ in
Pinocchio's order), of equal size, with the law's two systems square (closure rows +
task rows = drives + closure rows = nv) and no mimic joints.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from rcm_pin.control.computed_torque import ComputedTorque
from rcm_pin.model.mechanism import Mechanism

RHS = Callable[[float, np.ndarray], np.ndarray]


def closed_unsupported(plant: Mechanism, controller: object) -> str | None:
    """Why the closed ``"compiled"`` backend does not cover (plant, controller); None
    where it does."""
    if not isinstance(controller, ComputedTorque):
        return "it needs a ComputedTorque controller"
    mech, task = controller.model, controller.task_output
    loops, plant_loops = mech.loops, plant.loops
    if loops is None or plant_loops is None:
        return "the plant and the controller's model must both be closed"
    euclid = all(
        m.loops is not None and m.loops.euclidean and m.identity_order and m.nq == m.nv
        and np.array_equal(m.v_index, np.arange(m.model.nv))
        for m in (plant, mech)
    )  # fmt: skip
    reasons = [
        (controller.switching is not None, "drive switching is not supported"),
        (not euclid, "continuous joints (or a reordered model) are not supported"),
        (plant.nv != mech.nv or plant_loops.n_rows != loops.n_rows,
         "the plant and the controller's model differ in size"),
        (plant.coupling.has_mimic or mech.coupling.has_mimic, "mimic joints are not supported"),
        ("rotation" in task.coords, "a rotation-matrix task is not supported"),
        (loops.n_rows + task.dim != mech.nv or len(loops.drive_v) + loops.n_rows != mech.nv,
         f"{loops.n_rows} closure rows, {task.dim} task rows and {len(loops.drive_v)} drives "
         f"for {mech.nv} joints (the law's systems are not square) are not supported"),
    ]  # fmt: skip
    return next((why for bad, why in reasons if bad), None)


def closed_compiled_rhs(
    kernel: Any,
    reference: Callable[[float], Any],
    baumgarte: tuple[float, float],
    fallback: RHS | None,
) -> RHS:
    """y'(t, y) of the closed ``"compiled"`` backend: the kernel bound to ``baumgarte``,
    ``fallback`` (the Python right-hand side) where a call declines (without one: NaN,
    and the run ends ``failed``). The bound kernel is the function's attribute ``bound``."""
    bound = kernel.bind(baumgarte)

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        out = bound(y, reference(t))
        if out is None:
            if fallback is None:
                return np.full(len(y), np.nan)
            return fallback(t, y)
        return out  # type: ignore[no-any-return]

    rhs.bound = bound  # type: ignore[attr-defined]
    return rhs


__all__ = ["closed_compiled_rhs", "closed_unsupported"]
