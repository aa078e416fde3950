"""Camera geometry for :mod:`rcm_pin.viz.viewer`: framing a scene and projecting points.

Meshcat's camera is a three.js ``PerspectiveCamera`` under ``/Cameras/default/rotated``
(a y-up frame: world (x, y, z) is (x, z, −y) there) driven by OrbitControls, which
always aim at the world origin. :class:`rcm_pin.viz.viewer.Viewer` therefore shifts the scene
so the target sits at the origin; these functions do the arithmetic.
"""

from __future__ import annotations

import numpy as np

#: Direction from the scene centre to the camera (front-right, slightly above).
VIEW_DIRECTION = np.array([0.55, -1.0, 0.45])
#: Vertical field of view set on Meshcat's camera [deg] (Meshcat's own default is 75).
FOV_DEG = 35.0
_CORNERS = np.array(np.meshgrid([0, 1], [0, 1], [0, 1])).reshape(3, -1).T


def box_corners(lo: np.ndarray, hi: np.ndarray, T: np.ndarray) -> np.ndarray:
    """The 8 corners (8, 3) of the local box [lo, hi] placed by the 4x4 transform T."""
    local = np.where(_CORNERS, np.asarray(hi), np.asarray(lo))
    return local @ T[:3, :3].T + T[:3, 3]


def frame_points(points: np.ndarray, direction: np.ndarray | None = None,
                 margin: float = 1.0) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Camera (eye, target) that keeps every point in view.

    Args:
        points: (N, 3) world points [m].
        direction: from the target towards the eye (default :data:`VIEW_DIRECTION`).
        margin: distance factor (> 1 leaves more room).

    Returns:
        eye and target, world coordinates [m]; the target is the bounding-box centre.
    """
    p = np.reshape(points, (-1, 3))
    lo, hi = p.min(0), p.max(0)
    target = (lo + hi) / 2
    radius = max(0.5 * float(np.linalg.norm(hi - lo)), 1e-3)
    distance = margin * radius / np.sin(np.radians(FOV_DEG / 2))
    d = np.asarray(VIEW_DIRECTION if direction is None else direction, dtype=float)
    return target + distance * d / np.linalg.norm(d), target


def plane_basis(normal: np.ndarray) -> np.ndarray:
    """(3, 3) orthonormal columns (u, w, n) of a plane with normal n turned to z ≥ 0
    (u, w = x, y for n = ±z)."""
    n = np.asarray(normal, dtype=float)
    n = n / np.linalg.norm(n) if n[2] >= 0 else -n / np.linalg.norm(n)
    u = np.cross([0.0, 1.0, 0.0], n) if abs(n[1]) < 0.9 else np.cross(n, [1.0, 0.0, 0.0])
    u /= np.linalg.norm(u)
    return np.column_stack([u, np.cross(n, u), n])


def meshcat_position(eye: np.ndarray, target: np.ndarray) -> list[float]:
    """The camera's ``position`` property (y-up frame) for eye and target."""
    off = np.asarray(eye, dtype=float) - np.asarray(target, dtype=float)
    return [float(off[0]), float(off[2]), float(-off[1])]


def project(eye: np.ndarray, target: np.ndarray, points: np.ndarray,
            size: tuple[int, int] = (800, 600)) -> np.ndarray:  # fmt: skip
    """Pixel coordinates (N, 2) (column, row) of world points seen by the camera."""
    eye, target = np.asarray(eye, dtype=float), np.asarray(target, dtype=float)
    f = (target - eye) / np.linalg.norm(target - eye)
    r = np.cross(f, [0.0, 0.0, 1.0])
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    d = np.reshape(points, (-1, 3)) - eye
    t = np.tan(np.radians(FOV_DEG / 2)) * (d @ f)
    x, y = (d @ r) / (t * size[0] / size[1]), (d @ u) / t
    return np.c_[(x + 1) / 2 * size[0], (1 - y) / 2 * size[1]]
