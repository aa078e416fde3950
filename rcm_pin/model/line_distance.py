"""Distance from a straight line to a solid: box, cylinder, sphere, triangle mesh.

A line is a point p and a direction d (any length ≠ 0), both in the solid's own frame
(the URDF visual's origin: a box centred on it, a cylinder along its z axis, a sphere
round it). Every function returns the smallest distance [m] from a point of the line to a
point of the solid, 0 where the line passes through it (touching counts):

* sphere (centre 0, radius r): max(0, |p − (p·d̂) d̂| − r), exact;
* box (half sides h): the squared distance from p + t d̂ to the box,
  Σᵢ max(0, |pᵢ + t d̂ᵢ| − hᵢ)², is piecewise quadratic in t with breakpoints
  t = (±hᵢ − pᵢ) / d̂ᵢ; minimised exactly on each piece (the slab test is the case of a
  zero minimum);
* cylinder (radius r, half length h, axis z): 0 where the t-interval inside the infinite
  cylinder meets the slab |z| ≤ h (exact); otherwise the distance, a convex function of
  t, is minimised by Brent's bounded method on an interval that holds the minimiser
  (|t − t₀| ≤ D + √(r² + h²), t₀ the foot of the centre, D its distance), to 1e-13 m in t;
* triangles: 0 where the line crosses a triangle (Möller–Trumbore with t unbounded:
  a closed mesh is then passed through); otherwise the nearest point of a triangle lies on
  one of its edges, so the miss is the smallest line–segment distance (exact).

Pure numpy (and scipy's scalar minimiser); no rcm_pin import but the errors.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import minimize_scalar

from rcm_pin.errors import InvalidInputError

#: Length below which a direction, or a triangle's determinant, counts as zero [m, m²].
TINY = 1e-15


def _unit(d: np.ndarray) -> np.ndarray:
    n = float(np.linalg.norm(d))
    if not n > TINY:
        raise InvalidInputError(f"line direction {d.tolist()} has zero length; valid: |d| > 0")
    return d / n


def _line(p: object, d: object) -> tuple[np.ndarray, np.ndarray]:
    return np.asarray(p, dtype=float).reshape(3), _unit(np.asarray(d, dtype=float).reshape(3))


def point_line_distance(c: object, p: object, d: object) -> float:
    """Distance [m] from the point c to the line p + t d."""
    p, u = _line(p, d)
    w = np.asarray(c, dtype=float) - p
    return float(np.linalg.norm(w - (w @ u) * u))


def line_sphere(p: object, d: object, radius: float) -> float:
    """Miss [m] of the line p + t d and the sphere of ``radius`` [m] at the origin."""
    return max(0.0, point_line_distance(np.zeros(3), p, d) - radius)


def line_box(p: object, d: object, half: object) -> float:
    """Miss [m] of the line p + t d and the box of half sides ``half`` [m] at the origin."""
    p, u = _line(p, d)
    h = np.asarray(half, dtype=float)
    moving = np.abs(u) > TINY
    cuts = np.concatenate([(s * h[moving] - p[moving]) / u[moving] for s in (-1.0, 1.0)])
    cuts = np.sort(cuts)  # at least two: a unit direction moves along some axis
    # one sample inside each piece: below, between each pair of breakpoints, above
    samples = np.concatenate([[cuts[0] - 1.0], (cuts[:-1] + cuts[1:]) / 2, [cuts[-1] + 1.0]])
    lows = np.concatenate([[-np.inf], cuts])
    highs = np.concatenate([cuts, [np.inf]])
    best = math.inf
    for t_in, lo, hi in zip(samples, lows, highs, strict=True):
        x = p + t_in * u
        side = np.where(x > h, 1.0, np.where(x < -h, -1.0, 0.0))  # active faces
        out = side != 0.0
        a = float(u[out] @ u[out])
        t = t_in if a == 0.0 else -float(u[out] @ (p[out] - side[out] * h[out])) / a
        t = min(max(t, lo), hi)
        gap = np.maximum(np.abs(p + t * u) - h, 0.0)
        best = min(best, float(np.linalg.norm(gap)))
    return best


def _cylinder_gap(x: np.ndarray, radius: float, half_length: float) -> float:
    radial = max(0.0, math.hypot(x[0], x[1]) - radius)
    axial = max(0.0, abs(x[2]) - half_length)
    return math.hypot(radial, axial)


def line_cylinder(p: object, d: object, radius: float, half_length: float) -> float:
    """Miss [m] of the line p + t d and the solid cylinder of ``radius`` and half length
    ``half_length`` [m] along z, centred at the origin (module docstring)."""
    p, u = _line(p, d)
    # t-interval inside the infinite cylinder: a t² + b t + c ≤ 0
    a, b = float(u[:2] @ u[:2]), 2.0 * float(p[:2] @ u[:2])
    c = float(p[:2] @ p[:2]) - radius * radius
    if a <= TINY * TINY:
        radial = (-math.inf, math.inf) if c <= 0.0 else None
    else:
        disc = b * b - 4.0 * a * c
        root = math.sqrt(disc) if disc >= 0.0 else None
        radial = None if root is None else ((-b - root) / (2 * a), (-b + root) / (2 * a))
    if abs(u[2]) <= TINY:
        axial = (-math.inf, math.inf) if abs(p[2]) <= half_length else None
    else:
        ends = sorted(((-half_length - p[2]) / u[2], (half_length - p[2]) / u[2]))
        axial = (ends[0], ends[1])
    if (
        radial is not None
        and axial is not None
        and max(radial[0], axial[0]) <= min(radial[1], axial[1])
    ):
        return 0.0
    t0 = -float(p @ u)
    reach = float(np.linalg.norm(p + t0 * u)) + math.hypot(radius, half_length)
    res = minimize_scalar(
        lambda t: _cylinder_gap(p + t * u, radius, half_length),
        bounds=(t0 - reach, t0 + reach),
        method="bounded",
        options={"xatol": 1e-13},
    )
    return min(float(res.fun), _cylinder_gap(p + t0 * u, radius, half_length))


def _segments(p: np.ndarray, u: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distances (k,) from the line p + t u (unit u) to the segments a[i]–b[i]."""
    e = b - a
    w = a - p
    ee = np.einsum("ij,ij->i", e, e)
    ue, uw, ew = e @ u, w @ u, np.einsum("ij,ij->i", e, w)
    den = ee - ue * ue  # |e|² sin²(angle): 0 for a segment parallel to the line
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(den > TINY * ee, (ue * uw - ew) / den, 0.0)
    s = np.clip(np.nan_to_num(s), 0.0, 1.0)
    q = w + s[:, None] * e  # the segment's point, relative to p
    best = np.linalg.norm(q - (q @ u)[:, None] * u, axis=1)
    for end in (w, w + e):  # the ends: clamping s can miss the optimum only there
        best = np.minimum(best, np.linalg.norm(end - (end @ u)[:, None] * u, axis=1))
    return best


def line_triangles(p: object, d: object, vertices: object, faces: object) -> float:
    """Miss [m] of the line p + t d and a triangle mesh (vertices (n, 3) [m], faces
    (m, 3) indices): 0 where it crosses a triangle, else the nearest edge's distance.

    Raises:
        InvalidInputError: a mesh without triangles.
    """
    p, u = _line(p, d)
    v = np.asarray(vertices, dtype=float).reshape(-1, 3)
    f = np.asarray(faces, dtype=int).reshape(-1, 3)
    if f.size == 0:
        raise InvalidInputError("a mesh without triangles; valid: at least one face")
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    e1, e2 = b - a, c - a
    h = np.cross(u, e2)
    det = np.einsum("ij,ij->i", e1, h)
    ok = np.abs(det) > TINY * np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1)
    det = np.where(ok, det, 1.0)  # a triangle parallel to the line: its edges decide
    s = p - a
    bu = np.einsum("ij,ij->i", s, h) / det
    bv = (np.cross(s, e1) @ u) / det
    hit = ok & (bu >= 0.0) & (bv >= 0.0) & (bu + bv <= 1.0)
    if np.any(hit):
        return 0.0
    edges = [(a, b), (b, c), (c, a)]
    return float(min(_segments(p, u, x, y).min() for x, y in edges))


__all__ = [
    "TINY",
    "line_box",
    "line_cylinder",
    "line_sphere",
    "line_triangles",
    "point_line_distance",
]
