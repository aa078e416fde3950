"""Newton's method on the tracking OCP without path constraints (:mod:`ocp.tracking`, Radau).

With Radau collocation the gap constraints are linear and solvable for the node states:
``q_{k+1} = Q_{k,d}`` and ``v_{k+1} = V_d = (1/h) sum_j D_jd Q_{k,j}`` (``Q_{k,0} = q_k``).
The positions at the collocation points ``Y = (Q_0, ..., Q_{N-1})`` are then the only
variables, and the OCP without path constraints is the unconstrained problem

    min_Y  f(Y) = sum_k l_k(y_k),   y_k = (Q_{k-2,d}, Q_{k-1}, Q_k)

where stage k's window ``y_k`` (length ``n + 2 d n``) gives ``z_k = (q_k, v_k, Q_k, q_{k+1},
v_{k+1})`` linearly: ``q_k = Q_{k-1,d}``, ``v_k = V_d(Q_{k-2,d}, Q_{k-1})``. A constant prefix
``(Q_{-2,d}, Q_{-1})`` holds the boundary condition: ``Q_{-1} = (q_init, ..., q_init)`` and
``Q_{-2,d} = q_init + h v_init / D_0d`` (then ``V_d = v_init``). The windows overlap with
stride ``d n``, so the Hessian is banded (half-bandwidth ``n + 2 d n - 1``; sparser where
the cost couples fewer points, e.g. without an effort weight) and symmetric:

    (H(Y) + mu I) dY = -grad f(Y)

with the exact Hessian (the eliminated constraints are linear: it is the Lagrangian's).
A step is taken when it decreases f enough (Armijo); otherwise it is retried with a
Levenberg shift ``mu`` (a trust region in effect) that decays again after successes. One
call of one MX function per try gives the cost, the gradient and the step: the stage
function mapped over the stages, its gradients and Hessians scattered into the global ones
by constant 0/1 matrices, and
CasADi's sparse LDL^T (``ldl``: no BLAS, so no thread start-ups on a loaded machine; the
banded LAPACK Cholesky took 1-5 ms here against 0.2 ms single-threaded).
Converged: when the next step (Newton's, ``mu`` negligible) has ``max |dY| <= step_tol``
(the iterate is that close to the minimiser; the step is not taken), after two Newton
steps in a row whose predicted decrease is below f's rounding (``F_ROUND |f|``) and that
f does not confirm (an ill-conditioned problem at the noise floor of its gradient), or
when ``max |grad f| <= grad_tol``. ``iterations`` counts the steps taken.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from functools import partial
from typing import Any

import casadi as ca
import numpy as np

from ocp.buffered import BufferedFunction
from ocp.collocation import Collocation
from ocp.compiled import compile_lazy
from rcm_pin.errors import InvalidInputError

#: Bump when newton_stage changes: part of its disk-cache key.
NEWTON_VERSION = "1"
#: Armijo's sufficient-decrease fraction, and the predicted decrease (relative to |f|)
#: below which f's rounding hides it.
ARMIJO, F_ROUND = 1e-4, 1e-14
#: Levenberg shifts relative to max |H_ij|: the first one (and the floor below which the
#: shift is dropped), the largest before giving up, and the largest at which a step
#: below step_tol still counts as Newton's (the shifted step differs by ~ mu / H).
MU_MIN, MU_MAX, MU_NEWTON = 1e-8, 1e12, 1e-6


def reduced_stage(stage: ca.Function, col: Collocation, n: int) -> ca.Function:
    """``reduced_stage(y, p) -> (g, l)``: a tracking stage ``stage(z, p) -> (g, l)``
    (:func:`ocp.tracking_stage.tracking_stage`, ``p[-2] = 1/h``) in the window
    ``y = (Q_{k-2,d}, Q_{k-1}, Q_k)``, its gaps (zero by construction) dropped from g."""
    d = col.degree
    y, p = ca.SX.sym("y", n + 2 * d * n), stage.sx_in(1)
    inv_h = p[p.shape[0] - 2]
    q_prev = y[:n]
    prev = [y[n + r * n : n + (r + 1) * n] for r in range(d)]
    this = [y[n + (d + r) * n : n + (d + r + 1) * n] for r in range(d)]

    def v_end(q0: ca.SX, qs: list[ca.SX]) -> ca.SX:  # V_d, as tracking_stage writes it
        return sum(col.D[j, d - 1] * ([q0] + qs)[j] for j in range(d + 1)) * inv_h

    q_k, q_next = prev[-1], this[-1]
    z = ca.vertcat(q_k, v_end(q_prev, prev), *this, q_next, v_end(q_k, this))
    g, cost = stage(z, p)
    return ca.Function("reduced_stage", [y, p], [g[2 * n :], cost], ["y", "p"], ["g", "l"])


def newton_stage(
    stage: ca.Function, col: Collocation, n: int, opts: dict[str, Any] | None = None
) -> ca.Function:
    """``newton_stage(y, p) -> (l, dl/dy, triu d2l/dy2)`` (the Hessian sparse) of a stage
    without path constraints, in the window of :func:`reduced_stage`."""
    y, p = ca.SX.sym("y", n + 2 * col.degree * n), stage.sx_in(1)
    cost = reduced_stage(stage, col, n)(y, p)[1]
    upper = ca.triu(ca.hessian(cost, y)[0])  # sparse: the structure the linear solve uses
    return ca.Function(
        "newton_stage", [y, p], [cost, ca.densify(ca.gradient(cost, y)), upper],
        ["y", "p"], ["l", "grad", "hess"], opts or {},
    )  # fmt: skip


@dataclass(frozen=True)
class NewtonResult:
    """Positions at the collocation points ``(N d n,)`` and how Newton's method ended."""

    y: np.ndarray
    objective: float
    grad_norm: float  # max |grad f| at y
    iterations: int
    success: bool
    status: str


class NewtonTracking:
    """Newton's method for one stage, collocation scheme and grid.

    ``fun``: :func:`newton_stage` of the stage, as built or compiled (JIT or
    :mod:`ocp.compiled`)."""

    def __init__(self, fun: ca.Function, col: Collocation, n: int, n_stages: int) -> None:
        if col.scheme != "radau":
            raise InvalidInputError(
                f"Newton's elimination of the node states needs Radau collocation (its last "
                f"point is the interval's end); got {col.scheme!r}; valid: 'radau'"
            )
        d, big_n = col.degree, n_stages
        self.n, self.d, self.N, self.col = n, d, big_n, col
        s, stride = n + 2 * d * n, d * n
        self.pad, self.m = n + stride, big_n * stride
        y, prefix = ca.MX.sym("y", self.m), ca.MX.sym("prefix", self.pad)
        pars, mu = ca.MX.sym("p", fun.size1_in(1), big_n), ca.MX.sym("mu")
        windows = (np.arange(big_n)[None, :] * stride + np.arange(s)[:, None]).ravel("F")
        ext = ca.vertcat(prefix, y)
        w = ca.reshape(ext[windows.tolist()], s, big_n)
        ls, grads, hess = fun.map(big_n)(w, pars)
        # -- scatter: stage-local entries -> the global gradient and Hessian (pad dropped) --
        local = (np.arange(big_n)[:, None] * stride + np.arange(s)[None, :]).ravel() - self.pad
        keep = np.flatnonzero(local >= 0)
        a_grad = ca.DM(
            ca.Sparsity.triplet(self.m, big_n * s, local[keep].tolist(), keep.tolist()), 1.0
        )
        grad = ca.mtimes(a_grad, ca.vec(grads))
        pattern = fun.sparsity_out(2)
        sp, a_hess = _hessian_scatter(pattern, stride, big_n, self.pad, self.m)
        nonzeros = ca.sparsity_cast(hess, ca.Sparsity.dense(hess.nnz(), 1))  # stage by stage
        shifted = ca.vertcat(nonzeros, mu * ca.DM.ones(self.m))
        h_mat = ca.sparsity_cast(ca.mtimes(a_hess, shifted), sp)
        step = ca.solve(h_mat, -grad, "ldl")
        self._step = BufferedFunction(
            ca.Function(
                "newton_step",
                [y, prefix, pars, mu],
                [ca.sum2(ls), grad, step, ca.mmax(ca.fabs(nonzeros))],
            )
        )

    def prefix(self, x_init: np.ndarray, h: float) -> np.ndarray:
        """``(Q_{-2,d}, Q_{-1})`` of the boundary condition ``x_init = (q, v)``."""
        n, d = self.n, self.d
        q0, v0 = x_init[:n], x_init[n:]
        return np.concatenate([q0 + h * v0 / self.col.D[0, d - 1], np.tile(q0, d)])

    def _newton(
        self, y: np.ndarray, prefix: np.ndarray, pars: np.ndarray, mu: float = 0.0
    ) -> tuple[float, np.ndarray, np.ndarray, float]:
        """f, grad f, the step ``-(H + mu I)^-1 grad f`` and max |H_ij| at y."""
        f, grad, step, hmax = (np.array(o) for o in self._step(y, prefix, pars, np.array(mu)))
        return float(f[0]), grad, step, float(hmax[0])

    def solve(
        self,
        y0: np.ndarray,
        x_init: np.ndarray,
        params: np.ndarray,
        h: float,
        *,
        step_tol: float = 1e-12,
        grad_tol: float = 0.0,
        max_iter: int = 50,
    ) -> NewtonResult:
        """Minimise f from ``y0`` (N d n,) with stage parameters ``params`` (np, N).

        Newton steps while they decrease f enough (Armijo); otherwise a Levenberg shift
        ``mu I`` (from ``MU_MIN`` of max |H_ij|, x 10 per failure, / 10 per success, 0 below
        ``MU_MIN``): far from a minimiser the exact Hessian may be indefinite."""
        prefix, y = self.prefix(x_init, h), np.array(y0, dtype=float)
        pars, mu, it, floor = np.asarray(params, dtype=float), 0.0, 0, 0
        f, grad, step, hmax = self._newton(y, prefix, pars)
        while True:
            gnorm, size = float(np.abs(grad).max()), float(np.abs(step).max())
            slope, newton = float(grad @ step), mu <= MU_NEWTON * hmax
            if gnorm <= grad_tol or (newton and size <= step_tol) or floor >= 2:
                status = "Gradient_Zero" if gnorm <= grad_tol else "Step_Converged"
                return NewtonResult(y, f, gnorm, it, True, status)
            if it >= max_iter:
                return NewtonResult(y, f, gnorm, it, False, "Max_Iterations")
            if np.isfinite(slope) and slope < 0.0:
                trial, mu_next = y + step, (mu / 10.0 if mu > MU_MIN * hmax else 0.0)
                f_new, grad_new, step_new, h_new = self._newton(trial, prefix, pars, mu_next)
                # a Newton step whose predicted decrease f's rounding hides is taken; two
                # in a row: y is at the noise floor of grad f (converged)
                at_floor = newton and -slope <= F_ROUND * abs(f)
                if f_new <= f + ARMIJO * slope or at_floor:
                    floor = floor + 1 if at_floor and f_new > f + ARMIJO * slope else 0
                    y, f, grad, step, mu = trial, f_new, grad_new, step_new, mu_next
                    hmax, it = h_new, it + 1
                    continue
            mu = max(MU_MIN * hmax, 10.0 * mu)
            if not mu <= MU_MAX * max(hmax, 1e-300):
                return NewtonResult(y, f, gnorm, it, False, "No_Descent")
            f, grad, step, hmax = self._newton(y, prefix, pars, mu)

    def derivatives(
        self, y: np.ndarray, x_init: np.ndarray, params: np.ndarray, h: float
    ) -> tuple[float, np.ndarray, np.ndarray]:
        """f, grad f (the reduced problem's KKT residual) and the Newton step at y."""
        f, grad, step, _ = self._newton(np.asarray(y, float), self.prefix(x_init, h), params)
        return f, grad, step

    def node_states(self, y: np.ndarray, x_init: np.ndarray, h: float) -> np.ndarray:
        """Node states (N + 1, 2 n) of the positions y (the eliminated gap constraints)."""
        n, d = self.n, self.d
        q = y.reshape(self.N, d, n)
        starts = np.vstack([x_init[None, :n], q[:-1, -1]])
        qall = np.concatenate([starts[:, None], q], axis=1)  # (N, d + 1, n)
        v_end = np.einsum("j,kjn->kn", self.col.D[:, d - 1], qall) / h
        return np.vstack([x_init, np.hstack([q[:, -1], v_end])])


def newton_for(
    stage: ca.Function,
    col: Collocation,
    n: int,
    n_stages: int,
    *,
    opts: dict[str, Any] | None = None,
    compile: str | None = None,
) -> NewtonTracking:
    """:class:`NewtonTracking` of ``stage`` over ``n_stages``: its functions in CasADi's VM
    (``opts``: e.g. CasADi's JIT) or, ``compile`` (C compiler flags), through the disk
    cache of :mod:`ocp.compiled`, keyed by the serialised stage, the scheme and
    :data:`NEWTON_VERSION` (on a hit the Hessian is not even built)."""
    if compile is None:
        fun = newton_stage(stage, col, n, opts)
    else:
        key = hashlib.sha256(stage.serialize().encode()).hexdigest()
        key += f"{col.scheme}{col.degree}{n}{NEWTON_VERSION}"
        build = partial(newton_stage, stage, col, n)
        fun = compile_lazy("newton_stage", key, build, opt=compile).function
    return NewtonTracking(fun, col, n, n_stages)


def _hessian_scatter(
    pattern: ca.Sparsity, stride: int, n_stages: int, pad: int, m: int
) -> tuple[ca.Sparsity, ca.DM]:
    """The global Hessian's (symmetric, both triangles) sparsity and the 0/1 matrix that
    sums the stages' upper triangles (nonzeros of ``pattern``) and a diagonal shift into
    its nonzeros; entries of the constant prefix are dropped."""
    rows, cols = (np.array(a, dtype=int) for a in pattern.get_triplet())
    t = len(rows)
    base = np.arange(n_stages)[:, None] * stride - pad
    r, c = (base + rows[None, :]).ravel(), (base + cols[None, :]).ravel()
    src = np.arange(n_stages * t)
    ok = (r >= 0) & (c >= 0)
    off = ok & (r != c)
    diag = np.arange(m)
    rr = np.concatenate([r[ok], c[off], diag])
    cc = np.concatenate([c[ok], r[off], diag])
    ss = np.concatenate([src[ok], src[off], n_stages * t + diag])
    sp, mapping = ca.Sparsity.triplet(m, m, rr.tolist(), cc.tolist(), True)
    scatter = ca.Sparsity.triplet(sp.nnz(), n_stages * t + m, list(mapping), ss.tolist())
    return sp, ca.DM(scatter, 1.0)


__all__ = [
    "NEWTON_VERSION",
    "NewtonResult",
    "NewtonTracking",
    "newton_for",
    "newton_stage",
    "reduced_stage",
]
