"""The right-hand side backends of :func:`rcm_pin.control.simulate.simulate`.

* ``"python"`` (default): the lean Python right-hand side of :mod:`rcm_pin.control.hot_path`
  / :mod:`rcm_pin.control.closed_hot_path` (every mechanism, every controller).
* ``"compiled"``: the whole serial right-hand side (plant forward dynamics + the
  computed-torque law) as one compiled CasADi function, the kernel kind
  :func:`rcm_pin.model.kernels.serial_rhs` (provider: :mod:`ocp.kernels.serial_rhs`); the
  reference r = (x_T, ẋ_T, ẍ_T)(t) stays in Python (:func:`stacked_reference`) and is an
  input. It equals the
  Python right-hand side to rounding (tests: 1e-12), which changes the integrator's step
  sequence, so a trajectory differs from the ``"python"`` one at the integration
  tolerance: it is used only on request. Output samples (efforts, task values) are
  recomputed by the Python hot path either way.

A closed plant's ``"compiled"`` backend is the kernel kind
:func:`rcm_pin.model.kernels.closed_rhs` (:mod:`rcm_pin.control.closed_backend`: the closed
law and the KKT dynamics; a call near a rank loss of the closure rows runs the Python
right-hand side).

``"compiled"`` covers a serial plant under a task-space :class:`ComputedTorque` tracking
position rows with as many task coordinates as rows (a square J), without continuous
joints, and a closed plant under a closed ComputedTorque without drive switching
(:func:`~rcm_pin.control.closed_backend.closed_unsupported`); elsewhere
(:func:`compiled_unsupported`), or with kernels disabled or no provider, :func:`compiled_rhs`
raises :class:`~rcm_pin.errors.InvalidInputError` naming why (no silent fallback: the
caller asked for it). At a singular task Jacobian the ``"python"`` right-hand side raises
numpy's ``LinAlgError``; the serial compiled one returns NaN and the run ends ``failed``
(the families' stop events end a run before that); the closed kernel declines a
non-finite result, so the Python route runs and raises as it would.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import cast

import numpy as np

from rcm_pin.control.closed_backend import closed_compiled_rhs, closed_unsupported
from rcm_pin.control.computed_torque import ComputedTorque
from rcm_pin.control.references import CartesianTrajectory, CircleWithAngle, Reference
from rcm_pin.errors import InvalidInputError
from rcm_pin.model import kernels
from rcm_pin.model.mechanism import Mechanism

#: The backends of ``simulate``.
BACKENDS = ("python", "compiled")
#: What ``"compiled"`` covers (the tail of its error messages).
COVERS = (
    "backend='python' (every mechanism), or 'compiled' for a serial plant under a "
    "task-space ComputedTorque tracking positions with a square task (no continuous joints) "
    "or a closed plant under a ComputedTorque without drive switching"
)
RHS = Callable[[float, np.ndarray], np.ndarray]


def check_backend(backend: str) -> str:
    """``backend`` if it is one of :data:`BACKENDS`.

    Raises:
        InvalidInputError: any other value.
    """
    if backend not in BACKENDS:
        raise InvalidInputError(f"backend {backend!r} is invalid; valid: {', '.join(BACKENDS)}")
    return backend


def compiled_unsupported(plant: Mechanism, controller: object) -> str | None:
    """Why ``"compiled"`` does not cover (plant, controller); None where it does."""
    if not isinstance(controller, ComputedTorque):
        return "it needs a ComputedTorque controller"
    if plant.loops is not None:
        return closed_unsupported(plant, controller)
    mech, task, kin = controller.model, controller.task_output, controller.kinematics
    reasons = [
        (plant.loops is not None or kin is None, "closed mechanisms are not supported"),
        (controller.space != "task", "joint-space control is not supported"),
        (bool(task.angular.any()), "angular task rows (wrapped errors) are not supported"),
        (kin is not None and len(kin.joints) != task.dim,
         f"a redundant task ({task.dim} rows, {0 if kin is None else len(kin.joints)} "
         "coordinates) is not supported"),
        (plant.nq != plant.nv or mech.nq != mech.nv or plant.model.nq != plant.model.nv
         or mech.model.nq != mech.model.nv, "continuous joints are not supported"),
        (plant.nq != mech.nq, "the plant and the controller's model differ in size"),
    ]  # fmt: skip
    return next((why for bad, why in reasons if bad), None)


def stacked_reference(ref: Reference) -> Callable[[float], list[float] | np.ndarray]:
    """r(t) = (x_T, ẋ_T, ẍ_T) stacked (3 dim,). A :class:`CartesianTrajectory` is
    evaluated on Python floats with :mod:`math` (the operations of
    :func:`~rcm_pin.control.hot_path.reference_function`: x_T = c + a sin φ, ẋ_T = (a ω)
    cos φ, ẍ_T = (−a ω²) sin φ with φ = ω t + φ₀; the sines may differ from numpy's by an
    ulp), about 1 µs instead of 5; any other reference: its ``evaluate``, concatenated."""
    if type(ref) is CircleWithAngle:
        return _circle_with_angle(ref)
    if type(ref) is not CartesianTrajectory:
        return lambda t: np.concatenate(ref.evaluate(t))
    dim = np.broadcast(np.asarray(ref.centre), np.asarray(ref.amplitude)).size
    c, a, ph = (np.broadcast_to(np.asarray(v, dtype=float), (dim,)).tolist()
                for v in (ref.centre, ref.amplitude, ref.phase))  # fmt: skip
    w = float(ref.omega)
    coeffs = list(zip(c, a, [ai * w for ai in a], [-ai * w**2 for ai in a], ph))
    sin, cos = math.sin, math.cos

    def evaluate(t: float) -> list[float]:
        x, xd, xdd = [], [], []
        for ci, ai, aw, aw2, pi in coeffs:
            arg = w * t + pi
            s = sin(arg)
            x.append(ci + ai * s)
            xd.append(aw * cos(arg))
            xdd.append(aw2 * s)
        return x + xd + xdd

    return evaluate


def _circle_with_angle(ref: CircleWithAngle) -> Callable[[float], list[float]]:
    """:meth:`CircleWithAngle.evaluate` on Python floats, stacked (the same operations in
    the same order; ``math``'s sine and cosine)."""
    w = 2.0 * math.pi / ref.period
    cx, cy = float(ref.centre[0]), float(ref.centre[1])
    r, a, phi0, mw2 = float(ref.radius), float(ref.phi_amp), float(ref.phi0), -(w**2)
    sin, cos = math.sin, math.cos

    def evaluate(t: float) -> list[float]:
        c, s = cos(w * t), sin(w * t)
        x, y, phi = cx + r * c, cy + r * s, phi0 + a * s
        return [x, y, phi, -r * w * s, r * w * c, a * w * c,
                mw2 * (x - cx), mw2 * (y - cy), mw2 * (phi - phi0)]  # fmt: skip

    return evaluate


def compiled_rhs(
    plant: Mechanism,
    controller: ComputedTorque | None,
    baumgarte: tuple[float, float] = (50.0, 1.0),
    fallback: RHS | None = None,
) -> RHS:
    """y'(t, y) of the ``"compiled"`` backend: the kernel with the controller's reference
    evaluated in Python (:func:`stacked_reference`); a closed plant's with its Baumgarte
    numbers (ω [rad/s], ζ) and ``fallback`` (the Python right-hand side) for the calls
    its kernel declines (:mod:`rcm_pin.control.closed_backend`).

    Raises:
        InvalidInputError: ``"compiled"`` does not cover the pair, kernels are disabled or
            no provider built the kernel (module docstring).
    """
    why = compiled_unsupported(plant, controller)
    if why is None and not kernels.enabled():
        why = f"kernels are disabled (${kernels.DISABLE_ENV} or kernels.set_enabled(False))"
    find = kernels.serial_rhs if plant.loops is None else kernels.closed_rhs
    kernel: object = None if why is not None else find(plant, controller)
    if why is None and kernel is None:
        why = (
            "no kernel provider built it (a KernelWarning says why; is ocp installed? closure "
            "rows of less than full rank are not covered)"
        )
    if kernel is None or controller is None:
        raise InvalidInputError(
            f"backend 'compiled' is not available for {plant.name}: {why}; valid: {COVERS}"
        )
    reference = stacked_reference(controller.reference)
    if plant.loops is not None:
        return closed_compiled_rhs(kernel, reference, baumgarte, fallback)
    serial = cast(kernels.SerialRHS, kernel)

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        return serial(y, reference(t))

    return rhs


__all__ = [
    "BACKENDS",
    "COVERS",
    "RHS",
    "check_backend",
    "compiled_rhs",
    "compiled_unsupported",
    "stacked_reference",
]
