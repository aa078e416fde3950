"""Design metrics of the planar 3-RRR: the regular workspace of a working mode, conditioning.

For the working mode ``+++`` at the orientation φ = 0 (the home pose: the platform centred
at the origin), on an n × n grid of (x, y) covering the reach (:class:`.workspace.Grid`):

* the *regular region* is the connected part, around the grid point nearest the origin, of
  the poses every leg reaches where both normalised determinants |det A_n|, |det B_n|
  (:func:`rcm_pin.mechanisms.planar_3rrr.normalised_ab`) are at least ``MARGIN``: the
  part of the workspace the mechanism sweeps without crossing a singular curve;
* ``regular_area`` [m²]: its area (cells × cell area);
* ``mean_conditioning`` [-]: the mean over the region of κ⁻¹ of the output Jacobian
  J = −A⁻¹B (ẋ = J q̇_a) with its rotation row multiplied by the characteristic length
  L = ``loops.length_scale`` (every row in m/rad); tests compare J with Pinocchio's
  :func:`rcm_pin.analysis.loop_velocity.velocity_matrices`.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from rcm_pin.interfaces.design import DesignMetric
from rcm_pin.mechanisms.planar_3rrr import closed_form as p3
from rcm_pin.mechanisms.planar_3rrr import geometry, normalised_ab
from rcm_pin.mechanisms.planar_3rrr.workspace import Grid
from rcm_pin.model.mechanism import Mechanism

#: Smallest |det A_n|, |det B_n| of a regular pose.
MARGIN = 0.05
#: Grid points per side.
GRID = 121
#: Working mode of the metrics (``+++``).
MODE = 0


def regular_region(mech: Mechanism, n: int = GRID) -> tuple[Grid, np.ndarray, np.ndarray]:
    """(grid, boolean (ny, nx) regular region, drive angles (ny, nx, 3) of the mode) at φ = 0."""
    g = geometry(mech)
    grid = Grid.around(g, n)
    poses = grid.poses(0.0)
    qs, ok = p3.inverse_position(g, poses)
    q = np.nan_to_num(qs[..., MODE, :])
    a_n, b_n = normalised_ab(g, poses, q)
    with np.errstate(invalid="ignore"):
        good = ok & (np.abs(np.linalg.det(a_n)) >= MARGIN) & (np.abs(np.linalg.det(b_n)) >= MARGIN)
    labels, _ = ndimage.label(good)
    iy, ix = np.argmin(np.abs(grid.y)), np.argmin(np.abs(grid.x))
    region = labels == labels[iy, ix] if labels[iy, ix] else np.zeros_like(good)
    return grid, region, q


def output_jacobians(mech: Mechanism, poses: np.ndarray, drives: np.ndarray) -> np.ndarray:
    """J = −A⁻¹B (N, 3, 3) [m/rad; m/rad; rad/rad] of poses (N, 3) with their drives (N, 3)."""
    a_mat, b_mat = p3.ab_matrices(geometry(mech), poses, drives)
    return -np.linalg.solve(a_mat, b_mat)


def regular_area(mech: Mechanism) -> float:
    """Area [m²] of the regular region (module docstring)."""
    grid, region, _ = regular_region(mech)
    return float(region.sum() * (grid.x[1] - grid.x[0]) * (grid.y[1] - grid.y[0]))


def mean_conditioning(mech: Mechanism) -> float:
    """Mean κ⁻¹ of the length-scaled output Jacobian over the regular region (0 if empty)."""
    grid, region, q = regular_region(mech)
    if not region.any():
        return 0.0
    jac = output_jacobians(mech, grid.poses(0.0)[region], q[region])
    jac[:, 2, :] *= mech.require_loops().length_scale
    s = np.linalg.svd(jac, compute_uv=False)
    return float(np.mean(s[:, -1] / s[:, 0]))


METRICS: dict[str, DesignMetric] = {
    m.name: m
    for m in (
        DesignMetric(
            "regular_area",
            "m^2",
            "max",
            "area of working mode +++ at φ = 0 reached without a singularity (|det| ≥ 0.05)",
            regular_area,
        ),
        DesignMetric(
            "mean_conditioning",
            "-",
            "max",
            "mean inverse condition number of −A⁻¹B over that region (rotation row × L)",
            mean_conditioning,
        ),
    )
}

__all__ = ["MARGIN", "METRICS", "mean_conditioning", "output_jacobians", "regular_area"]
