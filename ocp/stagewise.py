"""An NLP made of ``N`` identical stages, with derivatives assembled stage by stage.

Variables ``w`` (length ``N stride + n_tail``); stage ``k`` reads the window
``z_k = w[k stride : k stride + nz]`` (windows overlap on the shared node states) and a
parameter column ``P[:, k]``; one SX function ``stage(z, p) -> (g, l)`` gives its
constraints and cost, and

    f(w) = sum_k l_k,      g(w) = [g_0; g_1; ...; g_{N-1}].

CasADi's automatic derivatives of the whole (mapped) NLP are slow here (the Hessian of
300 inverse-dynamics calls); instead the per-stage gradient, Jacobian and Lagrangian
Hessian are generated once in SX (optionally JIT-compiled: small C functions), mapped over
the stages, and their nonzeros scattered into the global sparse matrices by constant
0/1 matrices (overlapping windows sum). These are handed to ``nlpsol`` as ``grad_f``,
``jac_g`` and ``hess_lag``: the exact Hessian, at the cost of N small function calls.
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np


def _scatter(
    rows: np.ndarray, cols: np.ndarray, shape: tuple[int, int]
) -> tuple[ca.Sparsity, ca.DM]:
    """Global sparsity of the triplets and the 0/1 matrix summing them into its nonzeros."""
    sp, mapping = ca.Sparsity.triplet(shape[0], shape[1], rows.tolist(), cols.tolist(), True)
    t = len(rows)
    assemble = ca.DM(ca.Sparsity.triplet(sp.nnz(), t, list(mapping), list(range(t))), 1.0)
    return sp, assemble


class StagewiseNLP:
    """``nlp`` dict and derivative functions for ``nlpsol`` from one stage function."""

    def __init__(
        self,
        stage: ca.Function,
        n_stages: int,
        stride: int,
        n_tail: int,
        params: ca.MX,
        p_symbol: ca.MX,
        opts: dict[str, Any],
    ) -> None:
        z, p = stage.sx_in()
        g, l_val = stage(z, p)
        nz, ng, n = z.shape[0], g.shape[0], n_stages
        self.nw = n * stride + n_tail
        if (n - 1) * stride + nz > self.nw:
            raise ValueError("stage windows exceed the variable vector")
        lam_f, lam_g = ca.SX.sym("lam_f"), ca.SX.sym("lam_g", ng)
        jac = ca.jacobian(g, z)
        hess = ca.triu(ca.hessian(lam_f * l_val + ca.dot(lam_g, g), z)[0])
        sp_j, sp_h = jac.sparsity(), hess.sparsity()
        jnz, hnz = jac.nz[:], hess.nz[:]  # nonzeros, column-major
        f_grad = ca.Function("stage_grad", [z, p], [l_val, ca.densify(ca.gradient(l_val, z))], opts)
        f_jac = ca.Function("stage_jac", [z, p], [g, jnz if jac.nnz() else ca.SX(0, 1)], opts)
        f_hess = ca.Function(
            "stage_hess", [z, p, lam_f, lam_g], [hnz if hess.nnz() else ca.SX(0, 1)], opts
        )
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
        compiled = ca.Function("stage_fg", [z, p], [g, l_val], opts) if opts else stage
        gs, ls = compiled.map(n)(windows, params)
        self.nlp = {"x": w, "p": p_symbol, "f": ca.sum2(ls), "g": ca.vec(gs)}
        mf, mg = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", n * ng)
        ls2, grads = f_grad.map(n)(windows, params)
        gs2, jnzs = f_jac.map(n)(windows, params)
        hnzs = f_hess.map(n)(windows, params, mf, ca.reshape(mg, ng, n))
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
            [ca.vec(gs2), ca.sparsity_cast(ca.mtimes(a_jac, ca.vec(jnzs)), self._jac_sp)],
            ["x", "p"],
            ["g", "jac_g_x"],
        )
        self.hess_lag = ca.Function(
            "hess_lag",
            [w, p_symbol, mf, mg],
            [ca.sparsity_cast(ca.mtimes(a_hess, ca.vec(hnzs)), self._hess_sp)],
            ["x", "p", "lam_f", "lam_g"],
            ["triu_hess_gamma_x_x"],
        )

    def expanded(self) -> dict[str, Any]:
        """The same NLP as one flat SX graph (for solvers that take no custom
        derivatives, e.g. fatrop): CasADi then differentiates it as a whole."""
        w = ca.SX.sym("w", self.nw)
        p = ca.SX.sym("p", self.nlp["p"].shape[0])
        f_mx = ca.Function("nlp_mx", [self.nlp["x"], self.nlp["p"]], [self.nlp["f"], self.nlp["g"]])
        f, g = f_mx.expand()(w, p)
        return {"x": w, "p": p, "f": f, "g": g}

    def solver_options(self) -> dict[str, Any]:
        """``nlpsol`` options that install the assembled derivatives."""
        return {
            "grad_f": self.grad_f,
            "jac_g": self.jac_g,
            "hess_lag": self.hess_lag,
            "calc_lam_x": False,
            "calc_lam_p": False,
        }


__all__ = ["StagewiseNLP"]
