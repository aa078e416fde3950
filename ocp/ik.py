"""Inverse kinematics of one frame, or of a mechanism's output, as a nonlinear program.

Variables ``q`` (Pinocchio order, box-bounded by the joint limits); objective

    f(q) = 1/2 |r(q)|^2        (r: :mod:`ocp.ik_residuals`, modes pose / position / output)

(``|R - R_t|_F = 2 sqrt(2) sin(theta/2)``: smooth, zero exactly at the target);
optional general constraints from :mod:`ocp.ik_constraints`. The model is any
:class:`rcm_pin.Mechanism` (default frame: its tool or output frame) or a ``pin.Model``
with a frame. A closed Mechanism adds its loop closures as equality constraints
``e(q) = 0`` (:mod:`ocp.closure`) on the full configuration of its cut-open tree, and its
default mode is ``"output"``: the output coordinates (``mech.output``, e.g. x, y, rz of
the 3-RRR platform); every solution is then one of its working modes. Solvers:

* ``"lm"``: projected Levenberg-Marquardt (:mod:`ocp.ik_lm`), the default when only box
  constraints are present;
* ``"ipopt"``: interior point, exact Hessian, the default with general constraints or
  loop closures;
* ``"sqpmethod"``: CasADi SQP (``qrqp``, exact Hessian convexified by eigenvalue
  clipping; ``regularize`` stalls on these problems).

Failures raise typed errors carrying the :class:`IKResult` (:mod:`ocp.ik_result`;
``raise_on_failure=False`` returns it instead).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Literal

import casadi as ca
import numpy as np

from ocp.buffered import BufferedFunction
from ocp.closure import closure_expr, independent_rows
from ocp.ik_constraints import Constraint, constraint_expr, violation
from ocp.ik_lm import LevenbergMarquardt, build_lm_step
from ocp.ik_nlp import NlpSolver
from ocp.ik_residuals import Mode, output_residual, pose_residual
from ocp.ik_result import IKResult, failure
from ocp.ik_targets import (
    box,
    output_target,
    random_configuration,
    start_configuration,
    target_vector,
)
from ocp.models import ModelSource, resolve
from ocp.symbolic import JIT_OPTIONS
from rcm_pin.errors import InvalidInputError

SolverName = Literal["auto", "lm", "ipopt", "sqpmethod"]


class IKProblem:
    """IK of ``frame`` of a model, or of a Mechanism's output; build once, :meth:`solve`
    for many targets."""

    def __init__(
        self,
        model: ModelSource,
        frame: str | int | None = None,
        *,
        mode: Mode | None = None,
        lower: np.ndarray | None = None,
        upper: np.ndarray | None = None,
        position_weight: float = 1.0,
        orientation_weight: float = 0.1,
        constraints: Sequence[Constraint] = (),
        tol: float = 1e-12,
        reach_tol: float = 1e-9,
        max_iter: int = 100,
        restarts: int = 0,
        seed: int = 0,
        jit: bool = False,
    ) -> None:
        src = resolve(model, frame)
        self.sm, self.fid, self.mechanism = src.sm, src.frame_id, src.mechanism
        mech = self.mechanism
        self.loops = None if mech is None else mech.loops
        closed = self.loops is not None
        self.mode: Mode = ("output" if closed else "pose") if mode is None else mode
        if self.mode not in ("pose", "position", "output"):
            raise InvalidInputError(f"mode must be 'pose', 'position' or 'output', got {mode!r}")
        if self.mode == "output" and (mech is None or self.fid != mech.tool_frame_id):
            raise InvalidInputError(
                "mode='output' solves a Mechanism's output coordinates on its output frame; "
                "valid: an rcm_pin.Mechanism and frame=None, or mode='pose' / 'position'"
            )
        self.constraints = tuple(constraints)
        self.tol, self.reach_tol, self.max_iter, self.jit = tol, reach_tol, max_iter, jit
        self.restarts, self._rng = int(restarts), np.random.default_rng(seed)
        self.lower, self.upper = box(self.sm, lower, upper)
        self._home = None
        if mech is not None and closed and _assembled(mech):  # closed: the default start
            self._home = mech.to_pin(mech.home)
        q = ca.SX.sym("q", self.sm.nq)
        p, rot = self.sm.frame_placement(self.fid)(q)
        wp, wo = position_weight, orientation_weight
        res = (
            output_residual(mech.output, p, rot, wp, wo)  # type: ignore[union-attr]
            if self.mode == "output"
            else pose_residual(self.mode, p, rot, wp, wo)
        )
        target, r = res.target, res.r
        dv = ca.SX.sym("dv", self.sm.nv)  # tangent map dq/dv at dv = 0 (continuous joints)
        tangent = ca.substitute(ca.jacobian(self.sm.integrate()(q, dv), dv), dv, 0 * dv)
        opts = dict(JIT_OPTIONS) if jit else {}
        self.residual = ca.Function("ik_residual", [q, target], [r], ["q", "target"], ["r"])
        self.jacobian = ca.Function(
            "ik_jacobian",
            [q, target],
            [ca.mtimes(ca.jacobian(r, q), tangent)],
            ["q", "target"],
            ["J"],
        )
        exprs = [constraint_expr(c, *self._placement(c.frame, q, p, rot)) for c in self.constraints]
        closure = every_row = ca.SX(0, 1)
        if self.loops is not None and mech is not None:  # constraints: an independent set
            jac = mech.residual_and_jacobian(mech.home)[1] if _assembled(mech) else None
            rows = None if jac is None else independent_rows(jac)
            closure = closure_expr(self.sm, self.loops, q, rows)
            every_row = closure_expr(self.sm, self.loops, q)  # the residual reports them all
        m = closure.shape[0]
        self._g = ca.vertcat(*[e.g for e in exprs], closure)
        self._lbg = np.concatenate([e.lbg for e in exprs] + [np.zeros(m)])
        self._ubg = np.concatenate([e.ubg for e in exprs] + [np.zeros(m)])
        self.errors = ca.Function(
            "ik_errors",
            [q, target],
            [
                res.position_error,
                res.orientation_error,
                ca.norm_2(r),
                ca.densify(self._g),
                ca.norm_inf(every_row) if m else ca.DM(0.0),
            ],
            ["q", "target"],
            ["pos_err", "angle", "res", "g", "closure"],
            opts,
        )
        self._errors = BufferedFunction(self.errors)
        self._q, self._target, self._r = q, target, r
        self._lm: LevenbergMarquardt | None = None
        self._nlp: dict[str, NlpSolver] = {}

    # -- set-up --------------------------------------------------------------------------
    def _placement(self, frame: str | int | None, q: Any, p: Any, rot: Any) -> tuple[Any, Any]:
        if frame is None or self.sm.frame_id(frame) == self.fid:
            return p, rot
        out = self.sm.frame_placement(frame)(q)
        return out[0], out[1]

    @property
    def default_solver(self) -> str:
        """``"lm"`` with box constraints only, ``"ipopt"`` with general ones or closures."""
        return "lm" if not self.constraints and self.loops is None else "ipopt"

    def target_vector(self, target: Any) -> np.ndarray:
        """The target parameter: ``[p_t; vec(R_t)]`` (12,) from a 4x4 pose, a ``pin.SE3``
        or a 3-vector position; in output mode the output value vector."""
        if self.mode == "output":
            return output_target(self.mechanism.output, target)  # type: ignore[union-attr]
        return target_vector(target, self.mode)

    def random_configuration(self) -> np.ndarray:
        """Uniform within the finite limits (continuous joints: uniform angle)."""
        return random_configuration(self.sm, self.lower, self.upper, self._rng)

    # -- solving -------------------------------------------------------------------------
    def _run_lm(self, q0: np.ndarray, tvec: np.ndarray) -> tuple[np.ndarray, str, int, bool]:
        if self._lm is None:
            opts = dict(JIT_OPTIONS) if self.jit else {}
            bounded = [
                (j.idx_v, j.idx_q)
                for j in self.sm.joints
                if not j.mimic and j.kind != "revolute_unbounded"
            ]
            step = build_lm_step(
                self.residual,
                self.jacobian,
                self.sm.integrate(),
                self.lower,
                self.upper,
                bounded,
                opts,
            )
            self._lm = LevenbergMarquardt(step, self.tol, self.max_iter)
        out = self._lm.run(q0, tvec)
        ok = out.status == "converged" or (
            out.status == "stationary" and out.residual_norm <= self.reach_tol
        )
        return out.q, out.status, out.iterations, ok

    def nlp_solver(self, name: str) -> NlpSolver:
        """The cached ``nlpsol`` wrapper (``"ipopt"`` or ``"sqpmethod"``)."""
        if name not in self._nlp:
            self._nlp[name] = NlpSolver(
                name,
                self.sm,
                self._q,
                self._target,
                self._r,
                self._g,
                self._lbg,
                self._ubg,
                self.lower,
                self.upper,
                self.tol,
                self.max_iter,
                self.jit,
            )
        return self._nlp[name]

    def solve(
        self,
        target: Any,
        q0: Any = None,
        *,
        solver: SolverName = "auto",
        restarts: int | None = None,
        raise_on_failure: bool = True,
    ) -> IKResult:
        """Solve for ``target`` from ``q0`` (Pinocchio order; default: the middle of the
        joint ranges, for a closed Mechanism its closed ``home`` configuration).

        On failure, retry up to ``restarts`` times (default: the problem's) from uniformly
        random configurations within the limits; the best attempt is returned or raised.
        """
        tvec = self.target_vector(target)
        if q0 is None and self._home is not None:
            q0 = self._home
        q_init = start_configuration(self.sm, q0, self.lower, self.upper)
        name = self.default_solver if solver == "auto" else solver
        if name == "lm" and (self.constraints or self.loops is not None):
            raise InvalidInputError(
                "solver 'lm' handles box constraints only; general constraints and loop "
                "closures need 'ipopt' or 'sqpmethod'"
            )
        if name not in ("lm", "ipopt", "sqpmethod"):
            raise InvalidInputError(f"solver must be auto, lm, ipopt or sqpmethod, got {solver!r}")
        best: IKResult | None = None
        iters = 0
        for attempt in range(1 + (self.restarts if restarts is None else restarts)):
            start = q_init if attempt == 0 else self.random_configuration()
            if name == "lm":
                q, status, it, ok = self._run_lm(start, tvec)
            else:
                q, status, it, ok = self.nlp_solver(name).solve(start, tvec)
            iters += it
            result = self._result(q, tvec, status, name, iters, ok)
            if best is None or result.residual_norm < best.residual_norm or result.success:
                best = result
            if result.success:
                break
        assert best is not None
        if raise_on_failure and not best.success:
            raise failure(
                best, self.sm.frames[self.fid].name, self.reach_tol, self.loops is not None
            )
        return best

    def _result(
        self, q: np.ndarray, tvec: np.ndarray, status: str, name: str, iters: int, ok: bool
    ) -> IKResult:
        pos_err, angle, res, g, closure = self._errors(q, tvec)
        viol = violation(g, self._lbg, self._ubg)
        success = ok and res[0] <= self.reach_tol and viol <= 1e-8
        success = success and closure[0] <= self.reach_tol
        return IKResult(
            q=q,
            success=bool(success),
            status=status,
            solver=name,
            iterations=iters,
            residual_norm=float(res[0]),
            position_error=float(pos_err[0]),
            orientation_error=float(angle[0]),
            constraint_violation=viol,
            closure_residual=float(closure[0]),
        )


def solve_ik(model: ModelSource, frame: str | int | None, target: Any, q0: Any = None,
             **options: Any) -> IKResult:  # fmt: skip
    """One-shot :class:`IKProblem` ``(model, frame, **options).solve(target, q0)``."""
    solver = options.pop("solver", "auto")
    return IKProblem(model, frame, **options).solve(target, q0, solver=solver)


def _assembled(mech: Any) -> bool:
    """Whether ``mech.home`` closes the loops (the default home may stay open)."""
    return float(np.linalg.norm(mech.closure_residual(mech.home))) < 1e-9


__all__ = ["IKProblem", "IKResult", "Mode", "solve_ik"]
