"""Singularity-free orientation workspace of the Agile Eye: the largest tilt cone.

For a torsion range |σ| ≤ σ_m, the cone is the largest tilt θ* such that every orientation
R(θ, φ, σ) with θ < θ*, any azimuth φ and |σ| ≤ σ_m (:mod:`.maps`) is regular in a working
mode. For the Agile Eye every working mode has the same singular set, the six curves
v_i = ±u_i (:func:`.maps.singular_curves`), so θ*(σ_m) is the least tilt of those curves
over |σ| ≤ σ_m, whatever the mode. Two routes:

* :func:`cone_from_curves`: along each curve (parameter t, the turn about u_i), the least
  tilt over the arcs with |σ(t)| ≤ σ_m: at an interior minimum of θ(t) (bounded scalar
  minimisation) or at an arc end σ(t) = ±σ_m (``brentq``);
* :func:`cone_from_grid`: no curve construction. A grid over (θ, φ, σ) of the type-1 measure
  of :func:`.maps.measures` marks cells near a singularity (measure < ``eps``); from the
  lowest-tilt cells of each leg, SLSQP minimises θ subject to v_i ∥ u_i (the two components
  of v_i ⊥ u_i vanish) and |σ| ≤ σ_m.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq, minimize, minimize_scalar

from rcm_pin.mechanisms.spherical_3rrr import maps
from rcm_pin.mechanisms.spherical_3rrr.closed_form import GeometrySpherical
from rcm_pin.rotations import wrap_angle as wrap

#: Samples of each singular curve for bracketing.
CURVE_SAMPLES = 1441


def _curve_tt(g: GeometrySpherical, n: np.ndarray, leg: int, sign: float, t: float) -> tuple:
    tilt, _, tor = maps.tt_angles(n, maps.curve_rotations(g, leg, sign, np.array([t]))[0])
    return float(tilt), float(tor)


def cone_from_curves(g: GeometrySpherical, n: np.ndarray, sigma_max: float) -> float:
    """θ*(σ_m) [rad] from the six curves (module docstring); π when no curve point has
    |σ| ≤ σ_m."""
    t = np.linspace(0.0, 2.0 * np.pi, CURVE_SAMPLES)
    best = np.pi
    for leg in range(3):
        for sign in (1.0, -1.0):
            tilt, _, tor = maps.tt_angles(n, maps.curve_rotations(g, leg, sign, t))
            inside = np.abs(tor) <= sigma_max
            cands = []
            for k in range(1, len(t) - 1):  # interior minima of θ(t) on the arcs
                if inside[k] and tilt[k] <= tilt[k - 1] and tilt[k] <= tilt[k + 1]:
                    res = minimize_scalar(
                        lambda x, lg=leg, sg=sign: _curve_tt(g, n, lg, sg, x)[0],
                        bounds=(t[k - 1], t[k + 1]),
                        method="bounded",
                        options={"xatol": 1e-12},
                    )
                    if abs(_curve_tt(g, n, leg, sign, float(res.x))[1]) <= sigma_max:
                        cands.append(float(res.fun))
            for edge in (sigma_max, -sigma_max):  # arc ends σ(t) = ±σ_m
                f = wrap(tor - edge)
                for kk in np.flatnonzero(
                    (np.sign(f[:-1]) != np.sign(f[1:])) & (np.abs(f[:-1]) < 1)
                ):
                    x = brentq(
                        lambda s, lg=leg, sg=sign, e=edge: float(
                            wrap(_curve_tt(g, n, lg, sg, s)[1] - e)
                        ),
                        t[kk],
                        t[kk + 1],
                        xtol=1e-14,
                    )
                    cands.append(_curve_tt(g, n, leg, sign, x)[0])
            best = min([best, *cands])
    return best


def cone_from_grid(
    g: GeometrySpherical,
    n: np.ndarray,
    sigma_max: float,
    steps: tuple[int, int, int] = (91, 144, 61),
    eps: float = 0.05,
    mode: int = 0,
) -> float:
    """θ*(σ_m) [rad] by the grid and SLSQP (module docstring); ``steps`` = grid points in
    θ ∈ [0, π], φ ∈ [−π, π), σ ∈ [−σ_m, σ_m]."""
    tilt = np.linspace(0.0, np.pi, steps[0])
    az = np.linspace(-np.pi, np.pi, steps[1], endpoint=False)
    tor = np.linspace(-sigma_max, sigma_max, steps[2])
    tt, aa, ss = np.meshgrid(tilt, az, tor, indexing="ij")
    R = maps.tt_rotation(n, tt, aa, ss)
    type1, _ = maps.measures(g, R, mode)
    v = np.einsum("...ab,ib->...ia", R, g.v0)
    near = np.abs(np.sum(v * g.u, axis=-1))  # |u_i·v_i|, 1 on the singular set
    best = np.pi
    for leg in range(3):
        cells = np.argwhere((type1 < eps) & (near[..., leg] > np.sqrt(1.0 - eps**2)))
        if cells.size == 0:
            continue
        order = np.argsort(tilt[cells[:, 0]])[:8]
        f0 = maps.axis_frame(g.u[leg])[:, :2]  # two directions ⊥ u_leg
        for i, j, k in cells[order]:

            def perp(x: np.ndarray, lg: int = leg, f: np.ndarray = f0) -> np.ndarray:
                return f.T @ maps.tt_rotation(n, x[0], x[1], x[2]) @ g.v0[lg]

            res = minimize(
                lambda x: x[0],
                np.array([tilt[i], az[j], tor[k]]),
                jac=lambda x: np.array([1.0, 0.0, 0.0]),
                method="SLSQP",
                bounds=[(0.0, np.pi), (-2 * np.pi, 2 * np.pi), (-sigma_max, sigma_max)],
                constraints=[{"type": "eq", "fun": perp}],
                options={"ftol": 1e-14, "maxiter": 200},
            )
            if res.success and np.max(np.abs(perp(res.x))) < 1e-9:
                best = min(best, float(res.x[0]))
    return best


__all__ = ["CURVE_SAMPLES", "cone_from_curves", "cone_from_grid"]
