"""``nlpsol`` options of the tracking OCP's NLPs (:mod:`ocp.tracking`, full and reduced)."""

from __future__ import annotations

from typing import Any

from ocp.stagewise import StagewiseNLP
from ocp.tracking_grid import TrackingGrid


def nlp_options(
    nlp: StagewiseNLP,
    solver: str,
    tol: float,
    max_iter: int,
    n_path: int,
    grid: TrackingGrid,
) -> dict[str, Any]:
    """``nlpsol`` options: IPOPT with the stage-wise derivatives of ``nlp`` (print level 0,
    ``tol``, adaptive barrier) or fatrop with the OCP's structure given manually
    (:class:`ocp.tracking_grid.TrackingGrid`'s ``[x_k, u_k]`` layout, ``n_path`` path
    constraints per stage)."""
    opts: dict[str, Any] = nlp.solver_options() if solver == "ipopt" else {}
    opts.update(error_on_fail=False, print_time=False)
    if solver == "ipopt":
        opts["ipopt"] = {
            "print_level": 0,
            "sb": "yes",
            "tol": tol,
            "max_iter": max_iter,
            "mu_strategy": "adaptive",
        }
        return opts
    # fatrop stops with a failure below ~1e-10 on this problem: floor its tolerance
    opts.update(
        structure_detection="manual",
        N=grid.N,
        nx=[grid.nx] * (grid.N + 1),
        nu=[grid.nu] * grid.N + [0],
        ng=[n_path] * grid.N + [0],
        fatrop={"print_level": 0, "tol": max(tol, 1e-10), "max_iter": max_iter},
    )
    return opts


__all__ = ["nlp_options"]
