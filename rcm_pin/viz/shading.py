"""Shaded triangles seen by a perspective camera, drawn by matplotlib (no browser).

:func:`render` projects triangle meshes (:class:`rcm_pin.viz.triangles.Mesh`) with the
camera of the Meshcat pictures (:func:`rcm_pin.viz.camera.project`: eye, target, the
vertical field of view :data:`rcm_pin.viz.camera.FOV_DEG`, world z up), shades each face
by Lambert's law from its normal (a light near the eye, slightly above and to the right,
plus an ambient term) times its material colour, sorts the faces far to near (painter's
order) and draws them as one matplotlib ``PolyCollection`` on a white picture whose pixel
coordinates are those of :func:`~rcm_pin.viz.camera.project`. Marker meshes are drawn
after the bodies, one after the other, so they stay visible inside or behind them. Meshes finer than
the picture's pixels are first simplified by vertex clustering (:func:`cluster`).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from rcm_pin.viz.camera import FOV_DEG, project
from rcm_pin.viz.triangles import Mesh

#: Ambient share of the light (the rest is Lambert's diffuse term).
AMBIENT = 0.4
#: Light direction in the camera's (right, up, backwards) axes (normalised on use).
LIGHT = np.array([0.2, 0.25, 1.0])
#: Meshes with more faces than this are simplified to about one vertex per pixel.
CLUSTER_ABOVE = 2000
#: Nearest depth drawn [m] (faces closer to the eye are dropped).
NEAR = 1e-6


def camera_axes(eye: np.ndarray, target: np.ndarray) -> np.ndarray:
    """(3, 3) rows: right, up, forward unit vectors of the camera (world z up)."""
    f = np.asarray(target, float) - np.asarray(eye, float)
    f /= np.linalg.norm(f)
    r = np.cross(f, [0.0, 0.0, 1.0])
    if np.linalg.norm(r) < 1e-9:  # looking straight down or up: x is right
        r = np.array([1.0, 0.0, 0.0])
    r /= np.linalg.norm(r)
    return np.array([r, np.cross(r, f), f])


def cluster(vertices: np.ndarray, faces: np.ndarray, cell: float) -> tuple[np.ndarray, np.ndarray]:
    """Merge the vertices in each cube of side ``cell`` [m] into their mean; drop the faces
    that collapse. Returns the new vertices and faces."""
    keys = np.floor(vertices / cell).astype(np.int64)
    _, inv = np.unique(keys, axis=0, return_inverse=True)
    inv = inv.reshape(-1)
    n = int(inv.max()) + 1
    counts = np.bincount(inv, minlength=n)[:, None]
    merged = np.stack([np.bincount(inv, vertices[:, k], n) for k in range(3)], 1) / counts
    f = inv[faces]
    f = f[(f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])]
    return merged, f


def pixel_size(eye: np.ndarray, target: np.ndarray, height: int) -> float:
    """World length of one pixel at the target's distance [m]."""
    d = float(np.linalg.norm(np.asarray(target, float) - np.asarray(eye, float)))
    return 2.0 * d * np.tan(np.radians(FOV_DEG / 2)) / height


def faces_2d(mesh: Mesh, eye: np.ndarray, target: np.ndarray, size: tuple[int, int],
             cell: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
    """Projected faces (m, 3, 2) [px], their depths (m,) [m] and shaded RGBA (m, 4).

    Back faces of closed meshes are culled; both sides of open meshes are lit.
    """
    v, f = mesh.vertices, mesh.faces
    if len(f) > CLUSTER_ABOVE:
        v, f = cluster(v, f, cell)
    axes = camera_axes(eye, target)
    tri = v[f]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(normal, axis=1)
    centre = tri.mean(axis=1)
    depth = (centre - eye) @ axes[2]
    facing = np.einsum("ij,ij->i", normal, eye - centre)
    keep = (length > 0) & (depth > NEAR) & ((facing > 0) | (not mesh.closed))
    if np.any((tri[keep] - eye) @ axes[2] <= NEAR):  # a vertex behind the eye
        keep &= ((tri - eye) @ axes[2] > NEAR).all(axis=1)
    tri, normal, length, depth = tri[keep], normal[keep], length[keep], depth[keep]
    light = LIGHT @ np.array([axes[0], axes[1], -axes[2]])
    light /= np.linalg.norm(light)
    lambert = np.abs(normal @ light) / length
    shade = AMBIENT + (1.0 - AMBIENT) * lambert
    rgba = np.empty((len(tri), 4))
    rgba[:, :3] = np.clip(np.outer(shade, mesh.rgba[:3]), 0.0, 1.0)
    rgba[:, 3] = mesh.rgba[3]
    px = project(eye, target, tri.reshape(-1, 3), size).reshape(-1, 3, 2)
    return px, depth, rgba


def _layer(meshes: Sequence[Mesh], eye: np.ndarray, target: np.ndarray,
           size: tuple[int, int], cell: float) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """All faces of ``meshes`` far to near: (m, 3, 2) pixels and (m, 4) colours."""
    parts = [faces_2d(m, eye, target, size, cell) for m in meshes]
    if not parts:
        return np.zeros((0, 3, 2)), np.zeros((0, 4))
    px, depth, rgba = (np.concatenate([p[k] for p in parts]) for k in range(3))
    order = np.argsort(-depth, kind="stable")
    return px[order], rgba[order]


def render(bodies: Sequence[Mesh], markers: Sequence[Mesh], eye: np.ndarray,
           target: np.ndarray, png: str | Path, size: tuple[int, int] = (800, 600),
           title: str = "", under: Sequence[Mesh] = ()) -> tuple[Path, int]:  # fmt: skip
    """Write the shaded picture of bodies and markers (module docstring).

    Args:
        bodies: meshes drawn in depth order.
        markers: meshes drawn over the bodies, one after the other.
        eye: camera position [m].
        target: point looked at [m].
        png: output path.
        size: width and height [px].
        title: text in the top-left corner (none if empty).
        under: meshes drawn first, under everything (the base plate: its large faces would
            not sort by depth with the bodies').

    Returns:
        The PNG path and the number of faces drawn.
    """
    from matplotlib.collections import PolyCollection
    from matplotlib.figure import Figure

    eye, target = np.asarray(eye, float), np.asarray(target, float)
    w, h = int(size[0]), int(size[1])
    cell = pixel_size(eye, target, h)
    fig = Figure(figsize=(w / 100, h / 100), dpi=100, facecolor="white")
    ax = fig.add_axes((0.0, 0.0, 1.0, 1.0))
    ax.set_xlim(0, w)
    ax.set_ylim(h, 0)
    ax.set_axis_off()
    drawn = 0
    for layer in (under, bodies, *([m] for m in markers)):
        px, rgba = _layer(layer, eye, target, (w, h), cell)
        if len(px):
            edges = rgba.copy()
            edges[:, 3] = np.where(rgba[:, 3] < 1.0, 0.0, 1.0)  # close seams of opaque faces
            faces = PolyCollection(px, facecolors=rgba, edgecolors=edges, linewidths=0.4)  # type: ignore[arg-type]
            ax.add_collection(faces, autolim=False)
            drawn += len(px)
    if title:
        fig.text(0.01, 0.99, title, ha="left", va="top", fontsize=9, color="0.25")
    png = Path(png)
    png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(png, dpi=100, facecolor="white")
    return png, drawn
