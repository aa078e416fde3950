"""The right-hand side of a serial ``simulate`` as one compiled CasADi function.

For a serial plant under a task-space computed-torque law (square task, position rows)
the whole right-hand side y' = f(y, r) with y = (q, q̇) and the reference r = (x_T, ẋ_T,
ẍ_T) is one SX function,
written in the order of the math of :class:`rcm_pin.control.hot_path.SerialLaw` and
:class:`~rcm_pin.control.hot_path.SerialPlant`:

* task on the controller's model: x = p_f(q)[rows] (``frame_placement``), the full
  LOCAL_WORLD_ALIGNED rows J_f(q)[rows] (``frame_jacobian``, Mechanism column order),
  J = J_f[:, cols] over the task's coordinates, and the bias J̇ q̇ = ∂(J_f(q) q̇)/∂q · q̇
  by exact AD (``jtimes``; the other coordinates do not move the task, so it is the
  family's bias as well);
* law: q̈* = −K_n (q − q_post) − K_c q̇ (posture hold), and over the task's coordinates
  J q̈*_cols = f ẍ_T + K_p (x_T − x) + K_c (ẋ_T − J q̇_cols) − J̇ q̇ (K_p = ±K_n,
  ``printed_sign``);
* efforts τ = clip(RNEA_c(q, q̇, q̈*), −τ_max, τ_max) on the controller's model (``fmin``
  / ``fmax``; no limits: ±∞);
* plant: q̈ = M_p(q)⁻¹ (τ − b_p(q, q̇)) on the plant's model (the mechanism's block of
  Pinocchio's matrices, unrolled Cholesky).

Inputs ``y`` (n + nv), ``r`` = (x_T, ẋ_T, ẍ_T) (3 dim) and the law's numbers ``p`` =
(K_n, K_c, K_p, f, q_post (n), τ_max (nv)); outputs ``ydot`` (n + nv) and ``tau`` (nv).
The numbers are an input, so one library serves every gain, posture and limit of a pair
of models. Compiled to C (-O1) and cached on disk by :func:`ocp.compiled.compile_function`.

:func:`rcm_pin.control.backends.compiled_unsupported` says why a (plant, controller) pair
is not mirrored (closed, joint space, angular rows, a redundant task, continuous joints);
the provider then answers None. A compiled speed twin of the law, pinned on seeded random
states to the hot path and to ``ComputedTorque.effort`` (``tests/test_simulate_compiled.py``).
"""

from __future__ import annotations

import hashlib
import time
from typing import Any

import casadi as ca
import numpy as np
import pinocchio as pin

from ocp.buffered import RHSBuffers
from ocp.dynamics import cholesky_solve
from ocp.kernels.digest import source_digest
from ocp.symbolic import SymbolicModel
from rcm_pin.control.backends import compiled_unsupported
from rcm_pin.control.computed_torque import ComputedTorque
from rcm_pin.control.hot_path import SerialLaw, SerialPlant
from rcm_pin.model.mechanism import Mechanism

#: Optimisation flag of the C compiler (compile time matters more than the last µs).
OPT = "-O1"


def _to_pin(mech: Mechanism, q: Any, v: Any) -> tuple[Any, Any]:
    """Pinocchio's (q, v) from the Mechanism's (unlisted coordinates neutral; a continuous
    joint's θ -> cos θ, sin θ)."""
    qp, vp = ca.SX(pin.neutral(mech.model)), ca.SX.zeros(mech.model.nv)
    continuous = set(mech.continuous.tolist())
    for k, i in enumerate(mech.q_index):
        if k in continuous:
            qp[int(i)], qp[int(i) + 1] = ca.cos(q[k]), ca.sin(q[k])
        else:
            qp[int(i)] = q[k]
    for k, i in enumerate(mech.v_index):
        vp[int(i)] = v[k]
    return qp, vp


def build(plant: Mechanism, controller: ComputedTorque, name: str) -> ca.Function:
    """The SX right-hand side (module docstring) of ``plant`` under ``controller``."""
    mech, task, kin = controller.model, controller.task_output, controller.kinematics
    assert kin is not None
    n, nv, dim = plant.nq, plant.nv, task.dim
    cols, rows, vi = [int(c) for c in kin.joints], task.rows, mech.v_index
    y, r, p = ca.SX.sym("y", n + nv), ca.SX.sym("r", 3 * dim), ca.SX.sym("p", 4 + n + nv)
    q, v = y[:n], y[n:]
    x_t, xd_t, xdd_t = r[:dim], r[dim : 2 * dim], r[2 * dim :]
    kn, kc, kpos, ff = p[0], p[1], p[2], p[3]
    posture, tau_max = p[4 : 4 + n], p[4 + n :]
    # task on the controller's model
    ctrl_sm = SymbolicModel(mech.model)
    qc, vc = _to_pin(mech, q, v)
    x = ctrl_sm.frame_placement(task.frame_id)(qc)[0][rows]
    J_f = ctrl_sm.frame_jacobian(task.frame_id)(qc)[rows, :][:, vi.tolist()]
    J = J_f[:, cols]
    bias = ca.jtimes(ca.mtimes(J_f, v), q, v)  # J̇ q̇ = ∂(J_f q̇)/∂q · q̇
    # the law: posture hold, then the task's coordinates
    qdd = -kn * (q - posture) - kc * v
    a_star = ff * xdd_t + kpos * (x_t - x) + kc * (xd_t - ca.mtimes(J, v[cols]))
    qdd_task = ca.solve(J, a_star - bias)
    for k, c in enumerate(cols):
        qdd[c] = qdd_task[k]
    _, ac = _to_pin(mech, q, qdd)
    tau = ctrl_sm.rnea()(qc, vc, ac)[vi.tolist()]
    tau = ca.fmin(ca.fmax(tau, -tau_max), tau_max)
    # the plant's forward dynamics on its block of Pinocchio's matrices
    plant_sm = SymbolicModel(plant.model)
    qp, vp = _to_pin(plant, q, v)
    pv = plant.v_index.tolist()
    M = plant_sm.mass_matrix()(qp)[pv, pv]
    b = plant_sm.nonlinear_effects()(qp, vp)[pv]
    acc = cholesky_solve(M, tau - b)
    return ca.Function(
        name,
        [y, r, p],
        [ca.vertcat(v, acc), tau],
        ["y", "r", "p"],
        ["ydot", "tau"],
    )


def parameters(plant: Mechanism, controller: ComputedTorque) -> np.ndarray:
    """The input ``p`` = (K_n, K_c, K_p, f, q_post, τ_max) of ``controller``: the numbers
    of its Python hot path (:class:`~rcm_pin.control.hot_path.SerialLaw`)."""
    law = SerialLaw(controller)
    lim = law.limits
    tau_max = np.full(plant.nv, np.inf) if lim is None else np.broadcast_to(lim, (plant.nv,))
    return np.concatenate([[law.kn, law.kc, law.kpos, law.ff], law.posture, tau_max])


def structure_key(plant: Mechanism, controller: ComputedTorque) -> str:
    """What determines the function: both models, the task and its coordinates."""
    import pinocchio as pin

    kin, task = controller.kinematics, controller.task_output
    assert kin is not None
    parts = [
        _SOURCES, str(pin.__version__), plant.model.__str__(),
        _inertias(plant), _inertias(controller.model),
        str(plant.q_index.tolist()), str(plant.v_index.tolist()),
        str(controller.model.q_index.tolist()), str(controller.model.v_index.tolist()),
        str(task.frame_id), str(task.rows.tolist()), str(np.asarray(kin.joints).tolist()),
        controller.model.model.__str__(),
    ]  # fmt: skip
    return hashlib.sha256("\0".join(parts).encode()).hexdigest()


def _sources() -> str:
    """Digest of the code that writes the function (a change rebuilds the cache)."""
    import ocp.dynamics
    import ocp.joints
    import ocp.kinematics
    import ocp.symbolic

    mods = (ocp.dynamics, ocp.joints, ocp.kinematics, ocp.symbolic)
    return source_digest(__file__, mods)


_SOURCES = _sources()


def _inertias(mech: Mechanism) -> str:
    """Placements, inertias, armature, gravity and frames of a model as text."""
    m = mech.model
    rows = [repr(np.asarray(m.gravity.linear).tolist()), repr(np.asarray(m.armature).tolist())]
    rows += [repr(np.asarray(M.homogeneous).round(17).tolist()) for M in m.jointPlacements]
    rows += [repr(np.asarray(inertia.toDynamicParameters()).tolist()) for inertia in m.inertias]
    rows += [f"{f.name}:{f.parentJoint}:{np.asarray(f.placement.homogeneous).tolist()}"
             for f in m.frames]  # fmt: skip
    return "\n".join(rows)


class SerialRHSKernel:
    """y' = f(y, r) of one (plant, controller) pair on bound buffers (a
    lock makes a call thread-safe; it costs about 0.1 µs).

    Attributes:
        function: the (compiled) CasADi function.
        seconds: [s] wall time to build and compile (or load) it.
        compiled: whether it runs as compiled C (False: CasADi's VM).
    """

    def __init__(self, function: ca.Function, p: np.ndarray, seconds: float, compiled: bool):
        self.function, self.seconds, self.compiled = function, seconds, compiled
        self._rhs = RHSBuffers(function, p)

    def __call__(self, y: np.ndarray, r: np.ndarray | list[float]) -> np.ndarray:
        """y' = (q̇, q̈) (n + nv,) [rad/s, m/s; rad/s², m/s²] at y = (q, q̇) with the
        reference r = (x_T, ẋ_T, ẍ_T) (3 dim,): a new array."""
        with self._rhs.lock:
            return self._rhs.evaluate(y, r)[0].copy()

    def tau(self, y: np.ndarray, r: np.ndarray | list[float]) -> np.ndarray:
        """The clipped efforts (nv,) [N·m, N] at these inputs."""
        with self._rhs.lock:
            return self._rhs.evaluate(y, r)[1].copy()


def serial_rhs(plant: Mechanism, controller: object, vm: bool = False) -> SerialRHSKernel | None:
    """The compiled right-hand side of the pair, or None where it is not mirrored
    (:func:`rcm_pin.control.backends.compiled_unsupported`); ``vm``: CasADi's virtual
    machine instead of C.

    Raises:
        ValueError: the function differs from the Python hot path (:func:`check`).
    """
    if plant.loops is not None or compiled_unsupported(plant, controller) is not None:
        return None
    assert isinstance(controller, ComputedTorque)
    from ocp.compiled import compile_lazy

    start = time.perf_counter()
    key = structure_key(plant, controller)
    name = f"serial_rhs_{key[:12]}"
    p = parameters(plant, controller)
    if vm:
        fun = build(plant, controller, name)
        return SerialRHSKernel(fun, p, time.perf_counter() - start, False)
    made = compile_lazy(name, key, lambda: build(plant, controller, name), opt=OPT)
    kernel = SerialRHSKernel(made.function, p, time.perf_counter() - start, made.path is not None)
    check(kernel, plant, controller)
    return kernel


def check(kernel: SerialRHSKernel, plant: Mechanism, controller: ComputedTorque) -> None:
    """Compare with the Python hot path at a seeded random state (|q| ≤ 0.5 within the
    limits, 1e-9 relative): a guard against a structure its key missed.

    Raises:
        ValueError: they differ (the kernel layer then warns and the caller is told).
    """
    rng = np.random.default_rng(0)
    lo, hi = np.maximum(plant.lower, -0.5), np.minimum(plant.upper, 0.5)
    q, v, t = lo + (hi - lo) * rng.uniform(0.3, 0.7, plant.nq), rng.normal(0, 1, plant.nv), 0.3
    law = SerialLaw(controller)
    expected = SerialPlant(plant).accel(q, v, law.tau(t, q, v))
    got = kernel(np.concatenate([q, v]), np.concatenate(law.reference(t)))[plant.nq :]
    err = float(np.abs(got - expected).max() / max(np.abs(expected).max(), 1.0))
    if not err <= 1e-9:
        raise ValueError(f"the compiled right-hand side differs from Python's by {err:.1e}")


__all__ = ["OPT", "SerialRHSKernel", "build", "check", "parameters", "serial_rhs", "structure_key"]
