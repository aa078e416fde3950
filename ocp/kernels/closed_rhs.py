"""The right-hand side of a closed-plant ``simulate`` as one compiled CasADi function.

For a closed plant under the task-space computed-torque law of a closed
:class:`~rcm_pin.control.computed_torque.ComputedTorque` (no drive switching) the whole
right-hand side y' = f(y, r), y = (q, q̇), r = (x_T, ẋ_T, ẍ_T), is one SX function in
the order of the math of :class:`rcm_pin.control.closed_hot_path.ClosedLaw` and
:class:`~rcm_pin.control.closed_hot_path.ClosedPlant`:

* closure rows of a model (:func:`closure_rows`): c = (p_a − p_b)[rows] (6d: with
  log₃(R_a R_bᵀ)), J_c = (J_a − J_b)[rows] (LOCAL_WORLD_ALIGNED), γ = J̇_c q̇ =
  ∂(J_c q̇)/∂q · q̇ by exact AD (Pinocchio's classical acceleration at q̈ = 0);
* task of the controller's model (:func:`task_rows`): x (positions, planar angles by
  atan2), J_x, J̇_x q̇ likewise; e = x_T − x with angle rows wrapped where |e| > π;
* law: a* = f ẍ_T + K_p e + K_c (ẋ_T − J_x q̇); [J_c; J_x] q̈* = [−γ − 2ζω J_c q̇ − ω² c;
  a* − J̇_x q̇]; τ = RNEA(q, q̇, q̈*); [S  J_cᵀ] [τ_d; λ] = τ; τ_d clipped to ±τ_max;
* plant: the KKT system [M −J_cᵀ; J_c 0] [q̈; λ] = [Sτ_d − b; −γ − 2ζω J_c q̇ − ω² c]
  on the plant's model, solved by its Schur complement (Cholesky of M, then of
  J_c M⁻¹ J_cᵀ: both symmetric positive definite while J_c has full row rank).

Rank: the kernel is built for closure rows of full rank m (checked at a seeded state;
redundant rows, e.g. eye_4dof's 11 rows of rank 8, are not mirrored: the provider
declines). Its output ``guard`` = ‖R‖_F ‖R⁻¹‖_F of the QR factor of the plant's J_cᵀ
bounds σ₁/σ_min(J_c) from above; a call answers only where guard < ``KAPPA_LIMIT`` (1e9,
so σ_min/σ₁ > 1e-9 > ``RANK_TOL``: :func:`rcm_pin.dynamics.constrained.forward_dynamics`
would keep all m rows there) and the output is finite; elsewhere it declines and the
caller runs the Python route for that call.

Inputs ``y`` (2n), ``r`` (3 dim), ``p`` = (K_p, K_c, f, ω_c, ζ_c, ω_p, ζ_p, τ_max (k));
outputs ``ydot`` (2n), ``tau`` (k, clipped), ``raw`` (k, unclipped), ``x``, ``xd`` (the
plant's task value and rate) and ``guard``. The SX function is
:func:`ocp.kernels.closed_function.build`; compiled to C (-O1) and cached on disk
(:func:`ocp.compiled.compile_lazy`, verified by :mod:`ocp.so_cache`), called on bound
buffers (:mod:`ocp.buffered`).
"""

from __future__ import annotations

import time

import casadi as ca
import numpy as np

from ocp.buffered import RHSBuffers
from ocp.kernels.closed_function import build, structure_key
from ocp.kernels.newton_function import KAPPA_LIMIT
from ocp.kernels.serial_rhs import OPT
from rcm_pin.control.closed_backend import closed_unsupported
from rcm_pin.control.closed_hot_path import ClosedLaw, ClosedPlant
from rcm_pin.control.computed_torque import ComputedTorque
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.newton import constraint_rank


def parameters(
    plant: Mechanism, controller: ComputedTorque, baumgarte: tuple[float, float]
) -> np.ndarray:
    """The input ``p`` of ``controller`` with the plant's ``baumgarte`` (ω, ζ): the numbers
    of the Python hot path (:class:`~rcm_pin.control.closed_hot_path.ClosedLaw`)."""
    law = ClosedLaw(controller, plant)
    lim = law.limits
    tau_max = np.full(law.k, np.inf) if lim is None else np.broadcast_to(lim, (law.k,))
    head = [law.kpos, law.kc, law.ff, law.w, law.z, float(baumgarte[0]), float(baumgarte[1])]
    return np.concatenate([head, tau_max]).astype(float)


class BoundClosedRHS:
    """One run's right-hand side: the kernel's function on its own bound buffers with the
    plant's Baumgarte numbers (a lock makes a call thread-safe)."""

    def __init__(self, function: ca.Function, p: np.ndarray) -> None:
        self._rhs = RHSBuffers(function, p)
        #: calls that declined (rank guard or a non-finite result)
        self.declined = 0

    def __call__(self, y: np.ndarray, r: np.ndarray | list[float]) -> np.ndarray | None:
        """y' (2n,) at y = (q, q̇) with r = (x_T, ẋ_T, ẍ_T): a new array, or None where
        the kernel declines (module docstring)."""
        with self._rhs.lock:
            outputs = self._rhs.evaluate(y, r)
            out, guard = outputs[0], outputs[5]
            if guard[0] < KAPPA_LIMIT and np.isfinite(out).all():
                return out.copy()
            self.declined += 1
            return None

    def outputs(self, y: np.ndarray, r: np.ndarray | list[float]) -> tuple[np.ndarray, ...]:
        """(ydot, tau, raw, x, xd, guard) at these inputs: copies."""
        with self._rhs.lock:
            return tuple(o.copy() for o in self._rhs.evaluate(y, r))


class ClosedRHSKernel:
    """The compiled function of one (plant, controller) pair.

    Attributes:
        function: the (compiled) CasADi function.
        seconds: [s] wall time to build and compile (or load) it.
        compiled: whether it runs as compiled C (False: CasADi's VM).
    """

    def __init__(self, function: ca.Function, p: np.ndarray, seconds: float, compiled: bool):
        self.function, self.seconds, self.compiled = function, seconds, compiled
        self._p = p

    def bind(self, baumgarte: tuple[float, float]) -> BoundClosedRHS:
        """The right-hand side of one run with the plant's Baumgarte (ω [rad/s], ζ)."""
        p = self._p.copy()
        p[5], p[6] = float(baumgarte[0]), float(baumgarte[1])
        return BoundClosedRHS(self.function, p)


def closed_rhs(plant: Mechanism, controller: object, vm: bool = False) -> ClosedRHSKernel | None:
    """The compiled right-hand side of the pair, or None where it is not mirrored
    (:func:`rcm_pin.control.closed_backend.closed_unsupported`, or closure rows of less
    than full rank at a seeded state); ``vm``: CasADi's virtual machine instead of C.

    Raises:
        ValueError: the function differs from the Python hot path (:func:`check`).
    """
    if plant.loops is None or closed_unsupported(plant, controller) is not None:
        return None
    assert isinstance(controller, ComputedTorque)
    q, v = _state(plant)
    jc = plant.loops.n_rows
    if constraint_rank(ClosedPlant(plant, (50.0, 1.0)).kin.closure(q, v)[1]) < jc:
        return None
    start = time.perf_counter()
    key = structure_key(plant, controller)
    name = f"closed_rhs_{key[:12]}"
    p = parameters(plant, controller, (50.0, 1.0))
    if vm:
        kernel = ClosedRHSKernel(build(plant, controller, name), p, 0.0, False)
    else:
        from ocp.compiled import compile_lazy

        made = compile_lazy(name, key, lambda: build(plant, controller, name), opt=OPT)
        kernel = ClosedRHSKernel(made.function, p, 0.0, made.path is not None)
    kernel.seconds = time.perf_counter() - start
    check(kernel, plant, controller)
    return kernel


def _state(plant: Mechanism) -> tuple[np.ndarray, np.ndarray]:
    """A seeded state near the home configuration (q within 0.05 of it, q̇ ~ N(0, 1))."""
    rng = np.random.default_rng(0)
    return plant.home + rng.uniform(-0.05, 0.05, plant.nq), rng.normal(0.0, 1.0, plant.nv)


def check(kernel: ClosedRHSKernel, plant: Mechanism, controller: ComputedTorque) -> None:
    """Compare with the Python hot path at a seeded state (1e-9 relative): a guard
    against a structure its key missed.

    Raises:
        ValueError: they differ (the kernel layer then warns and the caller is told).
    """
    q, v = _state(plant)
    t, baumgarte = 0.3, (50.0, 1.0)
    law = ClosedLaw(controller, plant)
    expected = ClosedPlant(plant, baumgarte).accel(q, v, law.tau(t, q, v))
    got = kernel.bind(baumgarte)(np.concatenate([q, v]), np.concatenate(law.reference(t)))
    got = np.full(plant.nv, np.nan) if got is None else got[plant.nv :]
    err = float(np.abs(got - expected).max() / max(np.abs(expected).max(), 1.0))
    if not err <= 1e-9:
        raise ValueError(f"the compiled right-hand side differs from Python's by {err:.1e}")


__all__ = ["BoundClosedRHS", "ClosedRHSKernel", "check", "closed_rhs", "parameters"]
