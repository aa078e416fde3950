"""The closure Newton of :mod:`rcm_pin.model.newton` as one named ``casadi.Function``.

``closure_newton(q, qa, max_step, bounds) -> (q_sel, q_last, info, output)``: drives
``qa`` (k,) written into ``q`` (nq,), then ``n`` Newton iterations on the passive joints,
unrolled, each the numpy route's step (:func:`rcm_pin.model.newton.solve_passive`):

    e_i, J_i = e(q_i), J_p(q_i)                 (Pinocchio's residual and Newton Jacobian,
                                                  :func:`ocp.closure.pinocchio_closure`)
    s_i      = −J_i⁻¹ e_i                        square (m = n_p): ``ca.solve``, as numpy's
                                                  ``np.linalg.solve``
    s_i      = −R⁻¹ Qᵀ e_i,  J_i = Q R           tall (m > n_p, e.g. a parallelogram
                                                  written as a 4R loop): least squares, as
                                                  numpy's ``lstsq`` while no singular value
                                                  is dropped (κ guard below)
    s_i     ← s_i · max_step / |s_i|_∞   when |s_i|_∞ > max_step    (the same clipping)
    q_{i+1}  = q_i + s_i                         (passive entries; Euclidean models)

Outputs, with ρ_i = |e_i|₂ and c = the first i ≤ n with ρ_i < ``RESIDUAL_TOL`` (numpy
stops there):

* ``q_sel`` = q_c (q_n without one), passive revolute angles wrapped to [−π, π) exactly as
  :func:`rcm_pin.rotations.wrap_angle` does (``fmod``, then + 2π below 0, bit for bit);
* ``q_last`` = q_n unwrapped (the start of the next call when ρ_i ≥ tol throughout);
* ``info`` = [ρ_c (ρ_n), c (n), b, l]: b counts the steps before c where numpy would take
  another branch than this one: |s_i|_∞ not below 1e3 (NaN included; numpy's least
  squares / Levenberg–Marquardt fallbacks) or, tall, κ = ‖R‖_F ‖R⁻¹‖_F ≥ 1e9 (it bounds
  σ₁/σ_min from above, so below it ``lstsq`` with ``rcond`` = 1e-10 keeps every singular
  value). b > 0 means: not this kernel's result. l = 1 where ``bounds`` (2 nq,) =
  (lo, hi) hold q_sel: lo ≤ q_sel ≤ hi entry by entry (the caller passes the limits
  widened by ``LIMIT_TOL``: the very comparisons of ``within_limits``), else 0;
* ``output`` (size,): the value of ``mech.output`` at q_sel (what ``forward`` reports),
  from the output frame's placement by the symbolic forward kinematics of
  :class:`SymbolicModel` (Pinocchio's to rounding); empty without an output.

The selection runs backwards through ``if_else`` (never multiplying by a NaN of an unused
branch). Euclidean models with m ≥ n_p only; the provider declines others. A compiled
speed twin of the numpy route, pinned to it on seeded random drives and starts of every
closed catalogue mechanism (``tests/test_kernels.py``).
"""

from __future__ import annotations

import hashlib
from typing import Any

import casadi as ca
import numpy as np

from ocp.closure import pinocchio_closure
from ocp.kernels.digest import update_with_tree
from ocp.symbolic import SymbolicModel
from rcm_pin.model.loops import Loops
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.newton import RESIDUAL_TOL

#: A step at least this large leaves numpy's plain solve (``newton._step``) [rad, m].
STEP_LIMIT = 1e3
#: Over-determined loops: a least-squares step is taken only while ‖R‖_F ‖R⁻¹‖_F is below
#: this, so σ_min / σ₁ > 1e-9 > ``RANK_TOL``: numpy's ``lstsq`` then drops no singular value
#: and its step is the same least-squares step.
KAPPA_LIMIT = 1e9
#: Bump when the function's math changes (it is part of the compile-cache key).
VERSION = "3"


def supported(mech: Mechanism) -> bool:
    """Whether the kernel mirrors numpy's Newton here: a Euclidean model (nq = nv, one-DOF
    joints) whose closure Jacobian on the passive joints is square or tall (m ≥ n_p)."""
    loops = mech.loops
    return bool(
        loops is not None
        and loops.euclidean
        and mech.model.nq == mech.model.nv
        and loops.n_rows >= len(loops.passive_v) > 0
    )


def _wrap(angle: Any) -> Any:
    """[−π, π) wrap of :func:`rcm_pin.rotations.wrap_angle` (numpy's float remainder)."""
    two_pi = 2.0 * np.pi
    r = ca.fmod(angle + np.pi, two_pi)
    r = ca.if_else(r < 0, r + two_pi, r)
    return r - np.pi


def _newton_direction(jp: Any, e: Any) -> tuple[Any, Any]:
    """(−J_p⁺ e, κ): square: ``ca.solve`` and κ = 0; over-determined (m > n_p): least
    squares by QR, J_p = Q R, step −R⁻¹ Qᵀ e, and κ = ‖R‖_F ‖R⁻¹‖_F ≥ σ₁/σ_min."""
    if jp.shape[0] == jp.shape[1]:
        return -ca.solve(jp, e), ca.SX(0)
    q_mat, r_mat = ca.qr(jp)
    r_inv = ca.solve(r_mat, ca.SX.eye(jp.shape[1]))
    return -ca.mtimes(r_inv, ca.mtimes(q_mat.T, e)), ca.norm_fro(r_mat) * ca.norm_fro(r_inv)


def newton_step(sm: SymbolicModel, loops: Loops) -> ca.Function:
    """``newton_step(q, max_step) -> (q_next, rho, bad)``: one iteration (module docstring)."""
    q, max_step = ca.SX.sym("q", sm.nq), ca.SX.sym("max_step")
    e, jp = pinocchio_closure(sm, loops, q, [int(i) for i in loops.passive_v])
    step, kappa = _newton_direction(jp, e)
    peak = ca.norm_inf(step)
    bad = 1 - (peak < STEP_LIMIT) * (kappa < KAPPA_LIMIT)
    step = step * ca.if_else(peak > max_step, max_step / peak, 1.0)
    parts = [q[i] for i in range(sm.nq)]
    for i, iq in enumerate(loops.passive_q):
        parts[int(iq)] = q[int(iq)] + step[i]
    return ca.Function(
        "newton_step",
        [q, max_step],
        [ca.vertcat(*parts), ca.norm_2(e), bad],
        ["q", "max_step"],
        ["q_next", "rho", "bad"],
    )


def residual_norm(sm: SymbolicModel, loops: Loops) -> ca.Function:
    """``residual_norm(q) -> rho``: |e(q)|₂ [m, rad]."""
    q = ca.SX.sym("q", sm.nq)
    e, _ = pinocchio_closure(sm, loops, q, [])
    return ca.Function("residual_norm", [q], [ca.norm_2(e)], ["q"], ["rho"])


def build(mech: Mechanism, n: int, name: str) -> ca.Function:
    """The function ``name``: ``n`` unrolled iterations (module docstring), SX with CSE."""
    loops = mech.loops
    assert loops is not None and supported(mech)
    sm = SymbolicModel(mech.model)
    step, norm = newton_step(sm, loops), residual_norm(sm, loops)
    q_in, qa, max_step = ca.SX.sym("q", sm.nq), ca.SX.sym("qa", loops.dof), ca.SX.sym("max_step")
    parts = [q_in[i] for i in range(sm.nq)]
    for i, iq in enumerate(loops.drive_q):
        parts[int(iq)] = qa[i]
    qs, rhos, bads = [ca.vertcat(*parts)], [], []
    for _ in range(n):
        q_next, rho, bad = step(qs[-1], max_step)
        qs.append(q_next)
        rhos.append(rho)
        bads.append(bad)
    rhos.append(norm(qs[-1]))
    # backwards: the first converged iterate wins; b counts the bad steps before it
    sel, rho_sel, it_sel, b = qs[n], rhos[n], ca.SX(n), ca.SX(0)
    for i in range(n - 1, -1, -1):
        conv = rhos[i] < RESIDUAL_TOL
        sel = ca.if_else(conv, qs[i], sel)
        rho_sel = ca.if_else(conv, rhos[i], rho_sel)
        it_sel = ca.if_else(conv, i, it_sel)
        b = ca.if_else(conv, 0, bads[i] + b)
    wrapped = [sel[i] for i in range(sm.nq)]
    for iq in loops.wrap_q:
        wrapped[int(iq)] = _wrap(sel[int(iq)])
    q_sel, bounds = ca.vertcat(*wrapped), ca.SX.sym("bounds", 2 * sm.nq)
    inside = ca.logic_all(
        ca.vertcat(*(ca.logic_and(bounds[i] <= wrapped[i], wrapped[i] <= bounds[sm.nq + i])
                     for i in range(sm.nq)))
    )  # fmt: skip
    return ca.Function(
        name,
        [q_in, qa, max_step, bounds],
        [q_sel, qs[n], ca.vertcat(rho_sel, it_sel, b, inside), _output_value(sm, mech, q_sel)],
        ["q", "qa", "max_step", "bounds"],
        ["q_sel", "q_last", "info", "output"],
        {"cse": True},
    )


def _output_value(sm: SymbolicModel, mech: Mechanism, q: Any) -> Any:
    """``mech.output``'s value at ``q`` (size,), read from the output frame's placement as
    :meth:`rcm_pin.model.output.Output.value` reads it (:attr:`~.Output.layout`: the same
    entries, ``atan2`` of the same two for an angle); empty without an output."""
    output = mech.output
    if not output.present:
        return ca.SX(0, 1)
    p, r = sm.frame_placement(output.frame_id)(q)
    h = [r[i // 4, i % 4] if i % 4 < 3 else p[i // 4] for i in range(12)]
    picks, angles = output.layout
    value = [h[i] for i in picks]
    for k, i, j in angles:
        value[k] = ca.atan2(h[i], h[j])
    return ca.vertcat(*value)


def structure_key(mech: Mechanism, n: int) -> str:
    """A text that determines :func:`build`'s function: what :class:`SymbolicModel` reads
    of the kinematic tree (:func:`ocp.joints.joint_specs`: kinds, axes, placements, mimic
    scalings and offsets, indices; :func:`ocp.joints.frame_specs`), the closures, the
    drive / passive partition, the output (frame and coordinates) and ``n`` (masses,
    inertias and joint limits do not enter: the limits are an input)."""
    model, loops = mech.model, mech.loops
    assert loops is not None
    h = hashlib.sha256()
    update_with_tree(h, model)
    for c in loops.closures:
        h.update(f"{c.kind}|{c.frame_a_id}|{c.frame_b_id}|{c.rows}|".encode())
    for idx in (loops.drive_q, loops.passive_q, loops.passive_v, loops.wrap_q):
        h.update(np.asarray(idx, dtype=np.int64).tobytes() + b"|")
    out = f"{mech.output.frame_id}:{mech.output.coords}" if mech.output.present else "-"
    h.update(f"n={n}|tol={RESIDUAL_TOL!r}|limit={STEP_LIMIT!r}|out={out}|v={VERSION}".encode())
    return h.hexdigest()


__all__ = ["STEP_LIMIT", "VERSION", "build", "newton_step", "residual_norm", "structure_key",
           "supported"]  # fmt: skip
