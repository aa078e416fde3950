"""The ``"compiled"`` backend of a closed plant (:mod:`rcm_pin.control.backends`).

The kernel kind :func:`rcm_pin.model.kernels.closed_rhs` (provider:
:mod:`ocp.kernels.closed_rhs`) is the whole closed right-hand side, the closed
computed-torque law and the plant's KKT forward dynamics, as one compiled CasADi function
that equals :class:`~rcm_pin.control.closed_hot_path.ClosedLaw` and
:class:`~rcm_pin.control.closed_hot_path.ClosedPlant` to rounding. It is built for
closure rows of full rank; a call where the plant's J_c is near a rank loss (or where
the result is not finite) declines, and that call runs the Python route (``fallback``)
from the same inputs. The output samples (efforts, saturation, the plant's task value and
rate) come from the kernel too (:func:`samples_of`; the law's outputs equal the Python
hot path's to rounding), and from the Python hot path where one is not finite.

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
from rcm_pin.control.hot_path import SampledEfforts
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

    def samples(t: np.ndarray, q: np.ndarray, v: np.ndarray, drive_v: Any) -> Any:
        count = len(t)
        tau, sat = np.zeros((count, v.shape[1])), np.zeros(count, dtype=bool)
        x: list[np.ndarray] = []
        xd: list[np.ndarray] = []
        for i in range(count):
            out = bound.outputs(np.concatenate([q[i], v[i]]), reference(float(t[i])))
            tau[i, drive_v], sat[i] = out[1], bool(np.any(out[1] != out[2]))
            x.append(out[3])
            xd.append(out[4])
        if not (np.isfinite(tau).all() and np.isfinite(x).all() and np.isfinite(xd).all()):
            return None
        no = np.zeros(count, dtype=bool)
        return SampledEfforts(tau, sat, no, np.full(count, np.nan), np.array(x), np.array(xd))

    rhs.bound = bound  # type: ignore[attr-defined]
    rhs.samples = samples  # type: ignore[attr-defined]
    return rhs


def samples_of(
    fast: RHS | None, law: Any, t: np.ndarray, q: np.ndarray, v: np.ndarray
) -> SampledEfforts:
    """The output samples of a run: from the closed kernel of a :func:`closed_compiled_rhs`
    ``fast`` where it answers (module docstring), else ``law.samples`` (the Python hot
    path of :meth:`~rcm_pin.control.computed_torque.ComputedTorque.hot_path_law`)."""
    kernel_samples = getattr(fast, "samples", None)
    out = None if kernel_samples is None else kernel_samples(t, q, v, law.drive_v)
    return law.samples(t, q, v) if out is None else out  # type: ignore[no-any-return]


__all__ = ["closed_compiled_rhs", "closed_unsupported", "samples_of"]
