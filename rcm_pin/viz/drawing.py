"""The no-browser picture: a matplotlib line drawing of any mechanism at a configuration.

Lines join each joint origin to its parent's (dashed grey from the world origin to the
first joints); each closure adds the segments from the parent joints of its two cut
frames to the frames (so a closed configuration shows the loops closed) and a red ring
at the cut point. A planar mechanism (:func:`rcm_pin.model.loops.plane_normal`) is drawn
in its plane; any other in 3-D with short red/green/blue segments along each joint
frame's x/y/z axes. A red dot marks the RCM point A (with a dashed line along the
insertion axis), a black square the tool / output frame.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin

from rcm_pin.model.constraints import plane_normal
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.viz.camera import plane_basis

#: Colour of the links.
LINK = "tab:orange"


def _segments(mech: Mechanism, data: pin.Data) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Link segments (2, 3) and cut points (3,) from the placements in ``data`` [m]."""
    model = mech.model
    links = [
        np.array([data.oMi[model.parents[j]].translation, data.oMi[j].translation])
        for j in range(1, model.njoints)
    ]
    cuts = []
    for c in mech.loops.closures if mech.loops is not None else ():
        for fid in (c.frame_a_id, c.frame_b_id):
            parent = model.frames[fid].parentJoint
            links.append(np.array([data.oMi[parent].translation, data.oMf[fid].translation]))
        cuts.append(data.oMf[c.frame_a_id].translation.copy())
    return links, cuts


def _label(axis: np.ndarray, name: str) -> str:
    """Axis label: the world axis it is (``x [m]``, ``-y [m]``), else ``name [m]``."""
    for k, world in enumerate("xyz"):
        if abs(abs(axis[k]) - 1.0) < 1e-9:
            return f"{'' if axis[k] > 0 else '-'}{world} [m]"
    return f"{name} [m]"


def fallback_png(mech: Mechanism, q: np.ndarray, png: str | Path, title: str = "") -> Path:
    """Write the line drawing of ``mech`` at coordinates ``q`` (module docstring).

    Args:
        mech: any mechanism.
        q: coordinates (n,) [rad, m] (closed mechanisms: a closed configuration).
        png: output path.
        title: figure title (default: the mechanism name and what is drawn).

    Returns:
        The PNG path.
    """
    from matplotlib.figure import Figure

    q = mech.check_q(q)
    model, data = mech.model, mech.model.createData()
    pin.forwardKinematics(model, data, mech.to_pin(q))
    pin.updateFramePlacements(model, data)
    links, cuts = _segments(mech, data)
    tool = data.oMf[mech.output.frame_id].translation
    pts = np.vstack([*links, tool[None]])
    normal = plane_normal(model)
    fig = Figure(figsize=(6.4, 4.8), dpi=100)
    if normal is not None:
        basis = plane_basis(normal)[:, :2]
        ax: Any = fig.add_subplot()
        dim = 2
    else:
        basis = np.eye(3)
        ax = fig.add_subplot(projection="3d")
        dim = 3

    def flat(p: np.ndarray) -> np.ndarray:  # world points (..., 3) -> drawing coordinates
        return np.asarray(p) @ basis

    for j, seg in enumerate(links, start=1):  # the base (from the world origin) dashed
        base = j < model.njoints and model.parents[j] == 0
        ax.plot(*flat(seg).T, "--" if base else "-o", color="0.6" if base else LINK,
                lw=1 if base else 2, ms=3)  # fmt: skip
    scale = 0.25 * float(np.ptp(pts, axis=0).max() or 0.1)
    if dim == 3:
        for j in range(1, model.njoints):
            o, R = data.oMi[j].translation, data.oMi[j].rotation
            for k, c in enumerate("rgb"):
                ax.plot(*np.c_[o, o + scale * R[:, k]], color=c, lw=1)
    ax.scatter(*flat(tool), color="k", marker="s", s=30, zorder=3, label="tool / output frame")
    for i, p in enumerate(cuts):  # rings, so a tool centre at a cut point stays visible
        ax.scatter(*flat(p), facecolors="none", edgecolors="r", s=90, lw=1.5, zorder=4,
                   label=None if i else "cut point")  # fmt: skip
    if mech.rcm is not None:
        a = data.oMf[mech.rcm.point_frame_id].translation
        e = data.oMf[mech.rcm.axis_frame_id].rotation[:, mech.rcm.axis]
        depth = float((tool - a) @ e)
        ax.scatter(*flat(a), color="r", s=40, zorder=3, label="RCM A")
        ends = np.array([a - 0.3 * depth * e, a + 1.3 * depth * e])
        ax.plot(*flat(ends).T, color="tab:green", ls="--", lw=1)
    _limits(ax, flat(pts), scale, basis)
    what = "joints and cut points" if cuts else "joint frames"
    ax.set_title(title or f"{mech.name}: {what} (matplotlib fallback)")
    ax.legend(loc="upper left", fontsize=8)
    png = Path(png)
    png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(png)
    return png


def _limits(ax: Any, pts: np.ndarray, scale: float, basis: np.ndarray) -> None:
    """Axis labels; equal ranges around the drawn points (a cube in 3-D)."""
    labels = [_label(basis[:, k], "uw"[k] if basis.shape[1] == 2 else "xyz"[k])
              for k in range(basis.shape[1])]  # fmt: skip
    if basis.shape[1] == 2:
        ax.set(aspect="equal", xlabel=labels[0], ylabel=labels[1])
        return
    centre, half = (pts.max(0) + pts.min(0)) / 2, float(np.ptp(pts, axis=0).max()) / 2 + scale
    ax.set(xlim=centre[0] + [-half, half], ylim=centre[1] + [-half, half])
    ax.set(zlim=centre[2] + [-half, half], xlabel=labels[0], ylabel=labels[1], zlabel=labels[2])
