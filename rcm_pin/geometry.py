"""Plane geometry shared by the closed forms: the intersections of two circles.

Circles (c0, r0) and (c1, r1) with centres d = |c1 − c0| apart meet where
d > 0 and |r0 − r1| ≤ d ≤ r0 + r1; with e = (c1 − c0) / d, n = e turned by +π/2,

    a = (d² + r0² − r1²) / (2 d),   h = √(r0² − a²),   P± = c0 + a e ± h n,

P+ left of the line c0 → c1 (counter-clockwise side), P− right of it; they coincide
(h = 0) where the circles touch. Seen from c0, P± lie at the angles ∠(c1 − c0) ± atan2(h, a).
Pure numpy, no rcm_pin import: every layer may use it.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]


def circle_offsets(d: ArrayLike, r0: ArrayLike, r1: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """(a, h) (...) of the module docstring for centre distances d and radii r0, r1 (broadcast):
    the intersections lie a along c0 → c1 and ±h across it (h ≥ 0); both NaN where the
    circles do not meet (d = 0, d > r0 + r1 or d < |r0 − r1|)."""
    d, r0, r1 = (np.asarray(x, dtype=np.float64) for x in (d, r0, r1))
    meet = (d > 0.0) & (d <= r0 + r1) & (d >= np.abs(r0 - r1))
    with np.errstate(invalid="ignore", divide="ignore"):
        a = (d * d + r0 * r0 - r1 * r1) / (2.0 * d)
        h = np.sqrt(np.maximum(r0 * r0 - a * a, 0.0))
    return np.where(meet, a, np.nan), np.where(meet, h, np.nan)


def circle_intersections(c0: ArrayLike, r0: ArrayLike, c1: ArrayLike, r1: ArrayLike) -> FloatArray:
    """(P+, P−) (..., 2, 2) of circles broadcast over leading dimensions: index 0 the point
    left of c0 → c1, index 1 the one right of it (module docstring); NaN where the circles
    do not meet, the same point twice where they touch.

    Args:
        c0, c1: centres (..., 2) [m].
        r0, r1: radii (...) [m].
    """
    c0, c1 = np.asarray(c0, dtype=np.float64), np.asarray(c1, dtype=np.float64)
    d_vec = c1 - c0
    d = np.hypot(d_vec[..., 0], d_vec[..., 1])
    a, h = circle_offsets(d, r0, r1)
    with np.errstate(invalid="ignore", divide="ignore"):
        e = d_vec / d[..., None]
    n = np.stack([-e[..., 1], e[..., 0]], axis=-1)
    mid = c0 + a[..., None] * e
    return np.stack([mid + h[..., None] * n, mid - h[..., None] * n], axis=-2)


def circle_points(c0: ArrayLike, r0: float, c1: ArrayLike, r1: float) -> list[FloatArray]:
    """The distinct intersections (2,) of two circles, left of c0 → c1 first: 0, 1 (the
    circles touch) or 2 points (:func:`circle_intersections`)."""
    left, right = circle_intersections(c0, r0, c1, r1)
    if not np.isfinite(left).all():
        return []
    return [left] if np.array_equal(left, right) else [left, right]


__all__ = ["circle_intersections", "circle_offsets", "circle_points"]
