"""Figures of the spherical 3-RRR: singularity maps in tilt-and-torsion angles, the cone.

* :func:`maps_figure`: polar maps (azimuth φ as the polar angle, tilt θ [deg] as the radius)
  of the type-1 measure (colour) and the type-2 measure (contour lines) of one working mode
  at a few torsions σ, with the points where the singular curves cross each slice (×; other
  designs: the zero contours of det A, red, type 2, and det B, blue, type 1), and
  a last panel with the six singular curves themselves (:func:`.maps.singular_curves`),
  coloured by their torsion;
* :func:`cone_figure`: the largest singularity-free tilt cone θ*(σ_m) against the torsion
  half-range σ_m, both routes of :mod:`.workspace`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from rcm_pin.mechanisms.spherical_3rrr import maps, workspace
from rcm_pin.mechanisms.spherical_3rrr.closed_form import GeometrySpherical
from rcm_pin.rotations import wrap_angle as wrap


def slice_points(curves: list[dict], torsion: float) -> list[tuple[float, float]]:
    """(azimuth, tilt) [rad] where the singular curves cross σ = ``torsion`` (linear
    interpolation between curve samples)."""
    out = []
    for c in curves:
        f = wrap(c["torsion"] - torsion)
        defined = c["tilt"] < np.pi - 1e-6  # σ is undefined at θ = π
        if np.all(np.abs(f[defined]) < 1e-9):  # the whole curve lies in the slice
            out += [(float(a), float(t)) for a, t in zip(c["azimuth"], c["tilt"], strict=True)]
            continue
        for k in np.flatnonzero((np.sign(f[:-1]) != np.sign(f[1:])) & (np.abs(f[:-1]) < 1.0)):
            s = f[k] / (f[k] - f[k + 1])
            tilt = c["tilt"][k] + s * (c["tilt"][k + 1] - c["tilt"][k])
            az = c["azimuth"][k] + s * wrap(c["azimuth"][k + 1] - c["azimuth"][k])
            out.append((float(az), float(tilt)))
    return out


def maps_figure(
    g: GeometrySpherical,
    path: Path,
    torsions_deg: tuple[float, ...] = (-60.0, 0.0, 60.0),
    mode: int = 0,
    n: int = 91,
) -> Path:
    """Write the maps PNG (module docstring) and return its path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    axis = maps.symmetry_axis(g)
    tilt = np.linspace(0.0, np.pi, n)
    az = np.linspace(-np.pi, np.pi, 2 * n)
    tt, aa = np.meshgrid(tilt, az, indexing="ij")
    curves = maps.singular_curves(g, axis) if g.agile_eye else []
    panels = len(torsions_deg) + (1 if curves else 0)
    # constrained layout keeps the angle labels of neighbouring panels apart (0° and 180°
    # overlapped with fixed spacing)
    fig, axes = plt.subplots(
        1,
        panels,
        figsize=(4.2 * panels, 4.4),
        subplot_kw={"projection": "polar"},
        layout="constrained",
    )
    for ax, sig in zip(np.atleast_1d(axes), torsions_deg, strict=False):
        type1, type2 = maps.measures(g, maps.tt_rotation(axis, tt, aa, np.radians(sig)), mode)
        mesh = ax.pcolormesh(aa, np.degrees(tt), type1, shading="auto", cmap="viridis",
                             vmin=0.0, vmax=1.0)  # fmt: skip
        ax.contour(aa, np.degrees(tt), type2, levels=[0.1, 0.3, 0.5], colors="white",
                   linewidths=0.8)  # fmt: skip
        if not curves:  # other designs: singular surfaces, curves in each slice
            det_a, det_b = maps.determinants(
                g, maps.tt_rotation(axis, tt, aa, np.radians(sig)), mode
            )
            for det, colour in ((det_a, "red"), (det_b, "blue")):
                if np.nanmin(det) < 0 < np.nanmax(det):
                    ax.contour(aa, np.degrees(tt), det, levels=[0.0], colors=colour, linewidths=1.5)
        pts = slice_points(curves, np.radians(sig))
        if pts:
            ax.plot([p[0] for p in pts], np.degrees([p[1] for p in pts]), "rx", ms=7, mew=1.5)
        ax.set_title(f"torsion σ = {sig:g}°", fontsize=9)
        _polar_style(ax)
    fig.colorbar(mesh, ax=np.atleast_1d(axes)[: len(torsions_deg)].tolist(), shrink=0.7,
                 label="type 1: min|B_ii| (colour)")  # fmt: skip
    if curves:
        ax = np.atleast_1d(axes)[-1]
        for c in curves:
            sc = ax.scatter(c["azimuth"], np.degrees(c["tilt"]), c=np.degrees(c["torsion"]),
                            s=2, cmap="twilight", vmin=-180, vmax=180)  # fmt: skip
        fig.colorbar(sc, ax=ax, shrink=0.7, label="torsion σ [deg]")
        ax.set_title("the six singular curves v_i = ±u_i", fontsize=9)
        _polar_style(ax)
    marks = (
        "red ×: singular"
        if curves
        else "red: det A = 0 (type 2); type 1 on the edge of the coloured (reachable) region"
    )
    fig.suptitle(
        f"working mode {mode}: tilt θ [deg] (radius), azimuth φ of the platform axis; white: "
        f"type-2 σmin/σmax = 0.1, 0.3, 0.5; {marks}",
        fontsize=10,
    )
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return Path(path)


def cone_figure(
    g: GeometrySpherical, path: Path, sigmas_deg: np.ndarray, checks: dict[float, float]
) -> Path:
    """Write θ*(σ_m) (curve route over ``sigmas_deg``, grid route at ``checks``
    {σ_m [deg]: θ* [rad]}) and return the path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    axis = maps.symmetry_axis(g)
    cone = [workspace.cone_from_curves(g, axis, np.radians(s)) for s in sigmas_deg]
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(sigmas_deg, np.degrees(cone), "-", label="curve route")
    ax.plot(list(checks), np.degrees(list(checks.values())), "o", mfc="none",
            label="grid + SLSQP route")  # fmt: skip
    ax.set_xlabel("torsion half-range σ_m [deg]")
    ax.set_ylabel("largest singularity-free tilt θ* [deg]")
    ax.set_title("Agile Eye: singularity-free cone about the symmetry axis")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)


def _polar_style(ax: Any) -> None:
    """Tilt radius 0–180°, ticks every 45°, labels readable over the map and the marks."""
    ax.set_rlim(0, 180)
    ax.set_rticks([45, 90, 135])
    ax.tick_params(labelsize=7)
    ax.set_axisbelow(False)
    for label in ax.get_yticklabels():
        label.set_bbox({"facecolor": "white", "alpha": 0.7, "pad": 1, "edgecolor": "none"})


__all__ = ["cone_figure", "maps_figure", "slice_points"]
