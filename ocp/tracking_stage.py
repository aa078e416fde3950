"""One stage of the tracking OCP (:mod:`ocp.tracking`) as SX functions of its window.

Stage variables ``z = (x_k, u_k, x_{k+1})``: node state ``x_k = (q_k, v_k)``, collocation
positions ``u_k = (Q_1..Q_d)``, next node state. Parameters ``p = (p_ref (3, d), posture
(n), 1/h, h/T)``: the step enters as a parameter, so one model and cost (weights, limits
present) give one stage function for every horizon and grid (compiled once,
:mod:`ocp.compiled`). In the order of the math:

    V_r = (1/h) sum_j D_jr Q_j,   A_r = (1/h) sum_j D_jr V_j      (Q_0 = q_k, V_0 = v_k)
    T_r = rnea(Q_r, V_r, A_r)
    l   = (h/T) sum_r B_r [w_p |p(Q_r) - p_ref,r|^2 + sum_i w_i (Q_r,i - posture_i)^2
          + w_tau |T_r|^2]
    g   = [x_{k+1} - sum_j E_j (Q_j, V_j);  T_1..T_d (drive limits);  V_1..V_d (velocity
          limits)]
"""

from __future__ import annotations

from typing import NamedTuple

import casadi as ca
import numpy as np

from ocp.collocation import Collocation
from ocp.symbolic import SymbolicModel


class StageCost(NamedTuple):
    """Weights of the stage cost: position [1/m^2], posture (n,) [1/rad^2 or 1/m^2],
    effort [1/(N m)^2]."""

    position: float
    posture: np.ndarray
    effort: float


class Stage(NamedTuple):
    """``stage(z, p) -> (g, l)`` and ``outputs(z, inv_h) -> (V, A, tau, p)`` (n or 3, d)."""

    stage: ca.Function
    outputs: ca.Function


def tracking_stage(
    sm: SymbolicModel,
    frame_id: int,
    col: Collocation,
    weights: StageCost,
    drive_limits: bool,
    velocity_limits: bool,
) -> Stage:
    """The stage functions of one model, frame, collocation scheme and cost."""
    n, d = sm.nv, col.degree
    nx, nu = 2 * n, n * d
    z = ca.SX.sym("z", 2 * nx + nu)
    p_ref, post = ca.SX.sym("p_ref", 3, d), ca.SX.sym("posture", n)
    inv_h, quad = ca.SX.sym("inv_h"), ca.SX.sym("h_over_T")
    x, x_next = z[:nx], z[nx + nu :]
    qs = [x[:n]] + [z[nx + r * n : nx + (r + 1) * n] for r in range(d)]
    vs = [x[n:]] + [sum(col.D[j, r] * qs[j] for j in range(d + 1)) * inv_h for r in range(d)]
    acc = [sum(col.D[j, r] * vs[j] for j in range(d + 1)) * inv_h for r in range(d)]
    place, rnea = sm.frame_placement(frame_id), sm.rnea()
    taus = [rnea(qs[r + 1], vs[r + 1], acc[r]) for r in range(d)]
    pos = [place(qs[r + 1])[0] for r in range(d)]
    # -- objective (quadrature of the stage cost over the interval, time-averaged) ---------
    cost = 0
    for r in range(d):
        stage = weights.position * ca.sumsqr(pos[r] - p_ref[:, r])
        stage += ca.dot(weights.posture, (qs[r + 1] - post) ** 2)
        if weights.effort:
            stage += weights.effort * ca.sumsqr(taus[r])
        cost += quad * col.B[r] * stage
    # -- dynamics (gap closing) and path constraints --------------------------------------
    end = ca.vertcat(
        sum(col.E[j] * qs[j] for j in range(d + 1)),
        sum(col.E[j] * vs[j] for j in range(d + 1)),
    )
    g = [x_next - end] + (taus if drive_limits else []) + (vs[1:] if velocity_limits else [])
    pars = ca.vertcat(ca.vec(p_ref), post, inv_h, quad)
    return Stage(
        ca.Function("tracking_stage", [z, pars], [ca.vertcat(*g), cost], ["z", "p"], ["g", "l"]),
        ca.Function(
            "tracking_outputs",
            [z, inv_h],
            [ca.horzcat(*vs[1:]), ca.horzcat(*acc), ca.horzcat(*taus), ca.horzcat(*pos)],
            ["z", "inv_h"],
            ["V", "A", "tau", "p"],
        ),
    )


__all__ = ["Stage", "StageCost", "tracking_stage"]
