"""An NLP made of ``N`` identical stages, with derivatives assembled stage by stage.

Variables ``w`` (length ``N stride + n_tail``); stage ``k`` reads the window
``z_k = w[k stride : k stride + nz]`` (windows overlap on the shared node states) and a
parameter column ``P[:, k]``; one SX function ``stage(z, p) -> (g, l)`` gives its
constraints and cost, and

    f(w) = sum_k l_k,      g(w) = [g_0; g_1; ...; g_{N-1}].

CasADi's automatic derivatives of the whole (mapped) NLP are slow here (the Hessian of
300 inverse-dynamics calls); instead the per-stage gradient, Jacobian and Lagrangian
Hessian are generated once in SX (optionally compiled to C: CasADi's JIT, or
:mod:`ocp.compiled`'s disk cache so that a model's build compiles once), mapped over the
stages, and their nonzeros scattered into the global sparse matrices by constant 0/1
matrices (overlapping windows sum). These are handed to ``nlpsol`` as ``grad_f``,
``jac_g`` and ``hess_lag``: the exact Hessian (or the cost's only, ``hessian="cost"``), at
the cost of N small function calls.
"""

from __future__ import annotations

import hashlib
from functools import partial
from typing import Any, Literal

import casadi as ca
import numpy as np

from ocp.compiled import Compiled, compile_lazy


def _scatter(
    rows: np.ndarray, cols: np.ndarray, shape: tuple[int, int]
) -> tuple[ca.Sparsity, ca.DM]:
    """Global sparsity of the triplets and the 0/1 matrix summing them into its nonzeros."""
    sp, mapping = ca.Sparsity.triplet(shape[0], shape[1], rows.tolist(), cols.tolist(), True)
    t = len(rows)
    assemble = ca.DM(ca.Sparsity.triplet(sp.nnz(), t, list(mapping), list(range(t))), 1.0)
    return sp, assemble


#: Bump when the stage derivative functions change: part of their disk-cache key.
DERIVATIVES_VERSION = "1"

Hessian = Literal["exact", "cost"]


def stage_functions(
    stage: ca.Function, hessian: Hessian = "exact", opts: dict[str, Any] | None = None
) -> tuple[ca.Function, ca.Function, ca.Function, ca.Function]:
    """``stage_fg(z, p) -> (g, l)``, ``stage_grad(z, p) -> (l, dl/dz)``,
    ``stage_jac(z, p) -> (g, dg/dz)`` (sparse) and ``stage_hess(z, p, lam_f, lam_g)``, the
    upper triangle of the Lagrangian Hessian (sparse):

        exact:  triu d2/dz2 (lam_f l + lam_g . g)
        cost:   triu d2/dz2 (lam_f l)            (lam_g unused)

    "cost" drops the constraints' curvature: the same Hessian where g is linear or its
    multipliers vanish (inactive inequalities), a Gauss-Newton-like approximation elsewhere;
    the KKT point it converges to is the same, only the iterations differ.
    """
    opts = opts or {}
    z, p = stage.sx_in()
    g, l_val = stage(z, p)
    lam_f, lam_g = ca.SX.sym("lam_f"), ca.SX.sym("lam_g", g.shape[0])
    lag = lam_f * l_val + (ca.dot(lam_g, g) if hessian == "exact" else 0)
    hess = ca.triu(ca.hessian(lag, z)[0])
    return (
        ca.Function("stage_fg", [z, p], [g, l_val], opts),
        ca.Function("stage_grad", [z, p], [l_val, ca.densify(ca.gradient(l_val, z))], opts),
        ca.Function("stage_jac", [z, p], [g, ca.jacobian(g, z)], opts),
        ca.Function("stage_hess", [z, p, lam_f, lam_g], [hess], opts),
    )


def compiled_stage_functions(
    stage: ca.Function, hessian: Hessian = "exact", opt: str = "-O1"
) -> tuple[list[ca.Function], list[Compiled]]:
    """:func:`stage_functions` compiled through the disk cache (:mod:`ocp.compiled`), keyed
    by the serialised ``stage``, :data:`DERIVATIVES_VERSION` and (``stage_hess`` only)
    ``hessian``: on a hit the derivatives are not even built. Returns the functions and
    the cache records."""
    key = hashlib.sha256(stage.serialize().encode()).hexdigest() + DERIVATIVES_VERSION
    made: list[tuple[ca.Function, ...]] = []

    def build(i: int) -> ca.Function:
        if not made:
            made.append(stage_functions(stage, hessian))
        return made[0][i]

    names = ("stage_fg", "stage_grad", "stage_jac", "stage_hess")
    records = [
        compile_lazy(name, key + (hessian if i == 3 else ""), partial(build, i), opt=opt)
        for i, name in enumerate(names)
    ]
    return [r.function for r in records], records


def _nonzeros(x: ca.MX) -> ca.MX:
    """The nonzeros of ``x`` as a column (column-major order)."""
    return ca.sparsity_cast(x, ca.Sparsity.dense(x.nnz(), 1))


class StagewiseNLP:
    """``nlp`` dict and derivative functions for ``nlpsol`` from one stage function.

    ``hessian``: "exact" or "cost" (:func:`stage_functions`); ``compile``: C compiler
    optimisation flag(s) (e.g. ``"-O1"``) to compile the stage functions through the disk
    cache, or None (CasADi's VM, or CasADi's JIT through ``opts``).
    """

    def __init__(
        self,
        stage: ca.Function,
        n_stages: int,
        stride: int,
        n_tail: int,
        params: ca.MX,
        p_symbol: ca.MX,
        opts: dict[str, Any],
        *,
        hessian: Hessian = "exact",
        compile: str | None = None,
    ) -> None:
        nz, ng, n = stage.size1_in(0), stage.size1_out(0), n_stages
        self.nw = n * stride + n_tail
        if (n - 1) * stride + nz > self.nw:
            raise ValueError("stage windows exceed the variable vector")
        self.compiled: list[Compiled] = []
        if compile is None:
            funs = list(stage_functions(stage, hessian, opts))
        else:
            funs, self.compiled = compiled_stage_functions(stage, hessian, compile)
        f_fg, f_grad, f_jac, f_hess = funs
        sp_j, sp_h = f_jac.sparsity_out(1), f_hess.sparsity_out(0)
        # -- scatter maps: stage-local (i, j) -> global (row, col) ------------------------
        off = np.arange(n) * stride
        zi = np.arange(nz)
        self._grad_sp, a_grad = _scatter(
            (off[:, None] + zi).ravel(), np.zeros(n * nz, int), (self.nw, 1)
        )
        jr, jc = np.array(sp_j.get_triplet()[0]), np.array(sp_j.get_triplet()[1])
        self._jac_sp, a_jac = _scatter(
            (np.arange(n)[:, None] * ng + jr).ravel(),
            (off[:, None] + jc).ravel(),
            (n * ng, self.nw),
        )
        hr, hc = np.array(sp_h.get_triplet()[0]), np.array(sp_h.get_triplet()[1])
        self._hess_sp, a_hess = _scatter(
            (off[:, None] + hr).ravel(), (off[:, None] + hc).ravel(), (self.nw, self.nw)
        )
        # -- global functions in MX: gather windows, map the stage, scatter ---------------
        w = ca.MX.sym("w", self.nw)
        idx = (off[None, :] + zi[:, None]).ravel(order="F")
        windows = ca.reshape(w[idx.tolist()], nz, n)
        gs, ls = f_fg.map(n)(windows, params)
        self.nlp = {"x": w, "p": p_symbol, "f": ca.sum2(ls), "g": ca.vec(gs)}
        gs0, ls0 = stage.map(n)(windows, params)  # the SX stage: expandable (fatrop)
        self._nlp_sx = ca.Function("nlp_mx", [w, p_symbol], [ca.sum2(ls0), ca.vec(gs0)])
        mf, mg = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", n * ng)
        ls2, grads = f_grad.map(n)(windows, params)
        gs2, jacs = f_jac.map(n)(windows, params)
        jnzs = _nonzeros(jacs)  # stage by stage: the map concatenates horizontally
        hnzs = _nonzeros(f_hess.map(n)(windows, params, mf, ca.reshape(mg, ng, n)))
        self.grad_f = ca.Function(
            "grad_f",
            [w, p_symbol],
            [
                ca.sum2(ls2),
                ca.densify(ca.sparsity_cast(ca.mtimes(a_grad, ca.vec(grads)), self._grad_sp)),
            ],
            ["x", "p"],
            ["f", "grad_f_x"],
        )
        self.jac_g = ca.Function(
            "jac_g",
            [w, p_symbol],
            [ca.vec(gs2), ca.sparsity_cast(ca.mtimes(a_jac, jnzs), self._jac_sp)],
            ["x", "p"],
            ["g", "jac_g_x"],
        )
        self.hess_lag = ca.Function(
            "hess_lag",
            [w, p_symbol, mf, mg],
            [ca.sparsity_cast(ca.mtimes(a_hess, hnzs), self._hess_sp)],
            ["x", "p", "lam_f", "lam_g"],
            ["triu_hess_gamma_x_x"],
        )

    def expanded(self) -> dict[str, Any]:
        """The same NLP as one flat SX graph (for solvers that take no custom
        derivatives, e.g. fatrop): CasADi then differentiates it as a whole."""
        w = ca.SX.sym("w", self.nw)
        p = ca.SX.sym("p", self.nlp["p"].shape[0])
        f, g = self._nlp_sx.expand()(w, p)
        return {"x": w, "p": p, "f": f, "g": g}

    def solver_options(self) -> dict[str, Any]:
        """``nlpsol`` options that install the assembled derivatives (compiled stage
        functions have no CasADi derivatives: then no ``nlp_grad`` either, f and g at the
        solution come from the solver)."""
        opts: dict[str, Any] = {
            "grad_f": self.grad_f,
            "jac_g": self.jac_g,
            "hess_lag": self.hess_lag,
            "calc_lam_x": False,
            "calc_lam_p": False,
        }
        if self.compiled:
            opts.update(no_nlp_grad=True, calc_f=False, calc_g=False)
        return opts


__all__ = [
    "DERIVATIVES_VERSION",
    "Hessian",
    "StagewiseNLP",
    "compiled_stage_functions",
    "stage_functions",
]
