"""Inverse kinematics of one frame as a nonlinear least-squares program.

Variables ``q`` (Pinocchio order, box-bounded by the joint limits); objective

    f(q) = 1/2 |r(q)|^2,   r = [w_p (p(q) - p_t);  w_o vec(R(q) - R_t)]   (pose)
                           r = w_p (p(q) - p_t)                             (position)

(``|R - R_t|_F = 2 sqrt(2) sin(theta/2)``: smooth, zero exactly at the target);
optional general constraints from :mod:`ocp.ik_constraints`. Solvers:

* ``"lm"``: projected Levenberg-Marquardt (:mod:`ocp.ik_lm`), the default when only box
  constraints are present;
* ``"ipopt"``: interior point, exact Hessian, the default with general constraints;
* ``"sqpmethod"``: CasADi SQP (``qrqp``, exact Hessian convexified by eigenvalue
  clipping; ``regularize`` stalls on these problems).

A target that leaves a residual above ``reach_tol`` at a stationary point raises
:class:`~rcm_pin.errors.UnreachablePoseError`; a solver that stops for another reason
raises :class:`~rcm_pin.errors.SolverError`. Both carry the :class:`IKResult` as
``err.result`` (``raise_on_failure=False`` returns it instead).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

import casadi as ca
import numpy as np
import pinocchio as pin

from ocp.buffered import BufferedFunction
from ocp.ik_constraints import Constraint, constraint_expr, violation
from ocp.ik_lm import LevenbergMarquardt, build_lm_step
from ocp.ik_nlp import NlpSolver
from ocp.ik_targets import box, random_configuration, start_configuration, target_vector
from ocp.symbolic import JIT_OPTIONS, SymbolicModel
from rcm_pin.errors import InvalidInputError, SolverError, UnreachablePoseError

Mode = Literal["pose", "position"]
SolverName = Literal["auto", "lm", "ipopt", "sqpmethod"]


@dataclass(frozen=True)
class IKResult:
    """Solution and diagnostics of one IK solve."""

    q: np.ndarray  # Pinocchio configuration (nq,)
    success: bool
    status: str  # "converged", "stationary", "max_iter" or the NLP solver's status
    solver: str  # "lm", "ipopt" or "sqpmethod"
    iterations: int  # summed over the restarts
    residual_norm: float  # |r(q)| (weighted)
    position_error: float  # |p - p_t| [m]
    orientation_error: float  # rotation angle between R and R_t [rad]; nan for position
    constraint_violation: float  # general constraints (0 without)


class IKProblem:
    """IK of ``frame`` of a model; build once, :meth:`solve` for many targets."""

    def __init__(
        self,
        model: pin.Model | SymbolicModel,
        frame: str | int,
        *,
        mode: Mode = "pose",
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
        if mode not in ("pose", "position"):
            raise InvalidInputError(f"mode must be 'pose' or 'position', got {mode!r}")
        self.sm = model if isinstance(model, SymbolicModel) else SymbolicModel(model)
        self.fid, self.mode, self.constraints = self.sm.frame_id(frame), mode, tuple(constraints)
        self.tol, self.reach_tol, self.max_iter, self.jit = tol, reach_tol, max_iter, jit
        self.restarts, self._rng = int(restarts), np.random.default_rng(seed)
        self.lower, self.upper = box(self.sm, lower, upper)
        q, target = ca.SX.sym("q", self.sm.nq), ca.SX.sym("target", 12)
        p, rot = self.sm.frame_placement(self.fid)(q)
        r = position_weight * (p - target[:3])
        if mode == "pose":
            r = ca.vertcat(r, orientation_weight * ca.vec(rot - ca.reshape(target[3:], 3, 3)))
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
        self._g = ca.vertcat(*[e.g for e in exprs]) if exprs else ca.SX(0, 1)
        self._lbg = np.concatenate([e.lbg for e in exprs]) if exprs else np.zeros(0)
        self._ubg = np.concatenate([e.ubg for e in exprs]) if exprs else np.zeros(0)
        err_rot = ca.norm_fro(rot - ca.reshape(target[3:], 3, 3))
        self.errors = ca.Function(
            "ik_errors",
            [q, target],
            [ca.norm_2(p - target[:3]), err_rot, ca.norm_2(r), ca.densify(self._g)],
            ["q", "target"],
            ["pos_err", "rot_fro", "res", "g"],
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
        """``"lm"`` without general constraints, ``"ipopt"`` with them."""
        return "lm" if not self.constraints else "ipopt"

    def target_vector(self, target: Any) -> np.ndarray:
        """``[p_t; vec(R_t)]`` (12,) from a 4x4 pose, a ``pin.SE3`` or a 3-vector position."""
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
        """Solve for ``target`` from ``q0`` (default: the middle of the joint ranges).

        On failure, retry up to ``restarts`` times (default: the problem's) from uniformly
        random configurations within the limits; the best attempt is returned or raised.
        """
        tvec, q_init = (
            self.target_vector(target),
            start_configuration(self.sm, q0, self.lower, self.upper),
        )
        name = self.default_solver if solver == "auto" else solver
        if name == "lm" and self.constraints:
            raise InvalidInputError("solver 'lm' handles box constraints only; use 'ipopt'")
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
            raise self._failure(best)
        return best

    def _result(
        self, q: np.ndarray, tvec: np.ndarray, status: str, name: str, iters: int, ok: bool
    ) -> IKResult:
        pos_err, rot_fro, res, g = self._errors(q, tvec)
        viol = violation(g, self._lbg, self._ubg)
        rot = 2.0 * np.arcsin(min(1.0, rot_fro[0] / (2.0 * np.sqrt(2.0))))
        success = ok and res[0] <= self.reach_tol and viol <= 1e-8
        return IKResult(
            q=q,
            success=bool(success),
            status=status,
            solver=name,
            iterations=iters,
            residual_norm=float(res[0]),
            position_error=float(pos_err[0]),
            orientation_error=float(rot) if self.mode == "pose" else float("nan"),
            constraint_violation=viol,
        )

    def _failure(self, r: IKResult) -> Exception:
        orientation = (
            f", orientation error {r.orientation_error:.3g} rad" if self.mode == "pose" else ""
        )
        msg = (
            f"IK of frame {self.sm.frames[self.fid].name!r} ({r.solver}, {r.status}, "
            f"{r.iterations} it): residual {r.residual_norm:.3g} > reach_tol "
            f"{self.reach_tol:.0e}, position error {r.position_error:.3g} m{orientation}, "
            f"constraint violation {r.constraint_violation:.3g}"
        )
        stuck = r.status in (
            "stationary",
            "converged",
            "Solve_Succeeded",
            "Infeasible_Problem_Detected",
            "Solved_To_Acceptable_Level",
        )
        err: Exception = (
            UnreachablePoseError(
                f"unreachable target: {msg}; the solver stopped at a stationary point, which "
                "a local method cannot tell from a local minimum: valid targets lie in the "
                "image of the joint limits (retry with restarts > 0 to rule out a local minimum)"
            )
            if stuck
            else SolverError(f"IK solver failed: {msg}")
        )
        err.result = r  # type: ignore[attr-defined]
        return err


def solve_ik(
    model: pin.Model | SymbolicModel, frame: str | int, target: Any, q0: Any = None, **options: Any
) -> IKResult:
    """One-shot :class:`IKProblem` ``(model, frame, **options).solve(target, q0)``."""
    solver = options.pop("solver", "auto")
    return IKProblem(model, frame, **options).solve(target, q0, solver=solver)


__all__ = ["IKProblem", "IKResult", "solve_ik"]
