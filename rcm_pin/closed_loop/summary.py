"""JSON-ready summaries of closed-loop analyses (used by the CLI and notebook 05).

* :func:`pose_singularities`: per working mode of an output pose, the closed-form det A,
  det B, Pinocchio's A/B singular values and type-1/type-2 verdict
  (:func:`.velocity.classify`) and the screw-theory verdict (:func:`.screws.screw_test`);
* :func:`singularity_map`: closed-form det A / det B over the constant-orientation
  workspace (3-RRR) or the point workspace (five-bar) of one working mode;
* :func:`workspace_areas`: areas of the constant-orientation, total and reachable
  workspaces on a grid (3-RRR), or of the point workspace (five-bar).

Normalised determinants (dimensionless): 3-RRR det A / (8 l2³ r_p), det B / (8 l1³ l2³);
five-bar det A / (4 l2_1 l2_2), det B / (4 l1_1 l1_2 l2_1 l2_2).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from rcm_pin.closed_loop import five_bar as fb
from rcm_pin.closed_loop import planar_3rrr as p3
from rcm_pin.closed_loop import workspace as ws
from rcm_pin.closed_loop.core import ClosedMechanism
from rcm_pin.closed_loop.screws import screw_test
from rcm_pin.closed_loop.velocity import SINGULAR_TOL, classify, velocity_matrices
from rcm_pin.errors import InvalidInputError, UnreachablePoseError


def is_3rrr(mech: ClosedMechanism) -> bool:
    """True for the planar 3-RRR family (output x, y, rz), False for the five-bar."""
    return mech.name.startswith("planar_3rrr")


def mode_labels(mech: ClosedMechanism) -> list[str]:
    """Working-mode labels in index order: elbow signs, e.g. ``+-+`` (3-RRR) or ``-+``."""
    k = 3 if is_3rrr(mech) else 2
    return [f"{w:0{k}b}".replace("0", "+").replace("1", "-") for w in range(2**k)]


def parse_mode(mech: ClosedMechanism, text: str | int | None) -> int | None:
    """A working mode given as an index or a sign label -> index (None stays None).

    Raises:
        InvalidInputError: neither a valid index nor a valid label.
    """
    if text is None:
        return None
    labels = mode_labels(mech)
    s = str(text).strip()
    if s in labels:
        return labels.index(s)
    if s.isdigit() and int(s) < len(labels):
        return int(s)
    raise InvalidInputError(
        f"mode {s!r} is not a working mode of {mech.name}; valid: 0..{len(labels) - 1} or "
        + ", ".join(labels)
    )


def _closed_form(mech: ClosedMechanism, pose: np.ndarray) -> tuple[np.ndarray, bool, Any]:
    """Working-mode drive angles (W, k), reachability and a per-mode (q_full, detA, detB) fn."""
    if is_3rrr(mech):
        g = p3.Geometry3RRR.from_params(mech.params)
        qs, ok = p3.inverse_position(g, pose)

        def one(qd: np.ndarray) -> tuple[np.ndarray, float, float]:
            a_mat, b_mat = p3.ab_matrices(g, pose, qd)
            da = np.linalg.det(a_mat) / (8 * np.prod(g.l2) * g.rp)
            db = np.linalg.det(b_mat) / (8 * np.prod(g.l1) * np.prod(g.l2))
            return p3.full_q(g, pose, qd), float(da), float(db)

        return qs, bool(ok), one
    g5 = fb.GeometryFiveBar.from_params(mech.params)
    qs, ok = fb.inverse_position(g5, pose)

    def one5(qd: np.ndarray) -> tuple[np.ndarray, float, float]:
        a_mat, b_mat = fb.ab_matrices(g5, pose, qd)
        da = np.linalg.det(a_mat) / (4 * np.prod(g5.l2))
        db = np.linalg.det(b_mat) / (4 * np.prod(g5.l1) * np.prod(g5.l2))
        return fb.full_q(g5, pose, qd), float(da), float(db)

    return qs, bool(ok), one5


def pose_singularities(
    mech: ClosedMechanism, pose: np.ndarray, mode: int | None = None, tol: float = SINGULAR_TOL
) -> dict[str, Any]:
    """Type-1 / type-2 verdict at an output pose, per working mode (or for one mode).

    Args:
        mech: closed mechanism.
        pose: output pose (3-RRR: x, y [m], φ [rad]; five-bar: x, y [m]).
        mode: working-mode index (:func:`mode_labels`), or None for every mode.
        tol: threshold on σ_min/σ_max (:data:`.velocity.SINGULAR_TOL`).

    Returns:
        ``{"mechanism", "pose", "output_coords", "tol", "modes": [...]}``; each mode has its
        label, q, closed-form ``det_A``/``det_B`` (normalised), Pinocchio singular values
        of the scaled A and B, ``measure_type1/2``, ``verdict`` and the screw test.

    Raises:
        InvalidInputError: pose of the wrong size or not finite.
        UnreachablePoseError: some leg cannot reach its platform point.
    """
    pose = mech.check_q(pose, mech.dof, "pose")
    qs, ok, one = _closed_form(mech, pose)
    if not ok:
        raise UnreachablePoseError(
            f"{mech.name}: pose {pose.tolist()} is outside the workspace (a leg cannot reach it)"
        )
    labels = mode_labels(mech)
    scale = np.array([mech.length_scale if c == "rz" else 1.0 for c in mech.output_coords])
    modes = []
    for w in range(len(labels)) if mode is None else [mode]:
        q, det_a, det_b = one(qs[w])
        vm = velocity_matrices(mech, q)
        c = classify(mech, q, tol)
        s = screw_test(mech, q, tol)
        modes.append(
            {
                "mode": labels[w],
                "index": w,
                "q": q,
                "residual": float(np.linalg.norm(mech.closure_residual(q))),
                "det_A": det_a,
                "det_B": det_b,
                "sigma_A": np.linalg.svd(vm.A / scale[None, :], compute_uv=False),
                "sigma_B": np.linalg.svd(vm.B / mech.length_scale, compute_uv=False),
                "measure_type1": c.measure_type1,
                "measure_type2": c.measure_type2,
                "type1": c.type1,
                "type2": c.type2,
                "verdict": c.label,
                "screw": {
                    "measure_type1": s.measure_type1,
                    "measure_type2": s.measure_type2,
                    "type1": s.type1,
                    "type2": s.type2,
                    "leg_measures": s.leg_measures,
                },
                "screw_agrees": bool(s.type1 == c.type1 and s.type2 == c.type2),
            }
        )
    return {
        "mechanism": mech.name,
        "pose": pose,
        "output_coords": list(mech.output_coords),
        "tol": tol,
        "modes": modes,
    }


def _five_bar_grid(g5: fb.GeometryFiveBar, n: int) -> tuple[np.ndarray, np.ndarray]:
    r = float(np.max(g5.l1 + g5.l2))
    d = float(g5.base[1, 0])
    return np.linspace(-r - d, r + d, n), np.linspace(-r, r, n)


def singularity_map(
    mech: ClosedMechanism, mode: int = 0, phi: float = 0.0, n: int = 121
) -> dict[str, Any]:
    """Normalised closed-form det A (type 2) and det B (type 1) on an (x, y) grid.

    3-RRR: constant orientation φ [rad]; five-bar: the point P (φ ignored). NaN outside
    the workspace. Returns x, y (n,), ``det_A``, ``det_B`` (n, n, rows = y) and
    summaries: reachable area [m²], sign changes of det A (type-2 curve crossings along
    rows) and the smallest |det A|, |det B| over the reachable samples.
    """
    if n < 5:
        raise InvalidInputError(f"grid size {n}; valid: >= 5 points per side")
    if is_3rrr(mech):
        g = p3.Geometry3RRR.from_params(mech.params)
        grid = ws.Grid.around(g, n)
        da, db = ws.det_maps(g, grid, phi, mode)
        x, y = grid.x, grid.y
    else:
        g5 = fb.GeometryFiveBar.from_params(mech.params)
        x, y = _five_bar_grid(g5, n)
        pts = np.stack(np.meshgrid(x, y), axis=-1)
        qs, ok = fb.inverse_position(g5, pts)
        a_mat, b_mat = fb.ab_matrices(g5, pts, np.nan_to_num(qs[..., mode, :]))
        da = np.linalg.det(a_mat) / (4 * np.prod(g5.l2))
        db = np.linalg.det(b_mat) / (4 * np.prod(g5.l1) * np.prod(g5.l2))
        da[~ok], db[~ok] = np.nan, np.nan
    finite = np.isfinite(da)
    cell = float((x[1] - x[0]) * (y[1] - y[0]))
    sign_changes = int(np.sum((da[:, 1:] * da[:, :-1]) < 0))
    return {
        "mechanism": mech.name,
        "mode": mode_labels(mech)[mode],
        "phi": phi if is_3rrr(mech) else None,
        "x": x,
        "y": y,
        "det_A": da,
        "det_B": db,
        "reachable_area": float(finite.sum()) * cell,
        "type2_sign_changes": sign_changes,
        "min_abs_det_A": float(np.min(np.abs(da[finite]))) if finite.any() else None,
        "min_abs_det_B": float(np.min(np.abs(db[finite]))) if finite.any() else None,
    }


def plot_singularity_map(result: dict[str, Any], path: str | Path) -> Path:
    """PNG: det A (red zero contour: type 2) and det B (blue zero contour: type 1)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x, y = np.asarray(result["x"]), np.asarray(result["y"])
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.4))
    for ax, key, colour, label in (
        (axes[0], "det_A", "tab:red", "type 2: det A = 0"),
        (axes[1], "det_B", "tab:blue", "type 1: det B = 0 (workspace boundary)"),
    ):
        z = np.asarray(result[key], dtype=float)
        lim = float(np.nanmax(np.abs(z))) if np.isfinite(z).any() else 1.0
        im = ax.pcolormesh(x, y, z, shading="auto", cmap="coolwarm", vmin=-lim, vmax=lim)
        fig.colorbar(im, ax=ax, label=f"normalised {key.replace('_', ' ')}")
        if np.isfinite(z).any() and np.nanmin(z) < 0 < np.nanmax(z):
            ax.contour(x, y, z, levels=[0.0], colors=colour, linewidths=1.6)
        ax.plot([], [], color=colour, label=label)
        ax.legend(loc="lower left", fontsize=8)
        ax.set(xlabel="x [m]", ylabel="y [m]", aspect="equal")
    where = f"φ = {np.degrees(result['phi']):.3g}°, " if result["phi"] is not None else ""
    fig.suptitle(f"{result['mechanism']}: {where}working mode {result['mode']}")
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def workspace_areas(
    mech: ClosedMechanism,
    phi: float = 0.0,
    phi_range: tuple[float, float] = (-np.pi, np.pi),
    phi_step: float = np.radians(2.0),
    n: int = 121,
) -> dict[str, Any]:
    """Workspace areas [m²] on an n × n grid (inverse-problem reachability, paper 004).

    3-RRR: ``constant_orientation`` W(φ); ``total`` = points reachable with every sampled
    φ in ``phi_range`` [rad] (step ``phi_step``); ``reachable`` = with some φ. Five-bar:
    the point workspace of P (``constant_orientation`` and ``total`` are that area).
    """
    if n < 5:
        raise InvalidInputError(f"grid size {n}; valid: >= 5 points per side")
    lo, hi = float(phi_range[0]), float(phi_range[1])
    if not (np.isfinite(lo) and np.isfinite(hi) and lo <= hi):
        raise InvalidInputError(f"phi range {lo},{hi}; valid: lo <= hi, finite [rad]")
    if is_3rrr(mech):
        g = p3.Geometry3RRR.from_params(mech.params)
        grid = ws.Grid.around(g, n)
        cell = float((grid.x[1] - grid.x[0]) * (grid.y[1] - grid.y[0]))
        phis = np.arange(lo, hi + 1e-12, phi_step) if hi > lo else np.array([lo])
        count = ws.orientation_count(g, grid, phis)
        w = ws.constant_orientation(g, grid, phi)
        return {
            "mechanism": mech.name,
            "phi": phi,
            "phi_range": [lo, hi],
            "orientations": len(phis),
            "grid": n,
            "cell_area": cell,
            "constant_orientation_area": float(w.sum()) * cell,
            "total_area": float((count == len(phis)).sum()) * cell,
            "reachable_area": float((count > 0).sum()) * cell,
        }
    g5 = fb.GeometryFiveBar.from_params(mech.params)
    x, y = _five_bar_grid(g5, n)
    ok = fb.inverse_position(g5, np.stack(np.meshgrid(x, y), axis=-1))[1]
    cell = float((x[1] - x[0]) * (y[1] - y[0]))
    area = float(ok.sum()) * cell
    return {
        "mechanism": mech.name,
        "phi": None,
        "phi_range": None,
        "orientations": 1,
        "grid": n,
        "cell_area": cell,
        "constant_orientation_area": area,
        "total_area": area,
        "reachable_area": area,
    }


def plot_workspace(mech: ClosedMechanism, path: str | Path, phi: float = 0.0, n: int = 121) -> Path:
    """PNG of the workspace: :func:`.plots.workspace_figure` (3-RRR) or the five-bar's."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if is_3rrr(mech):
        from rcm_pin.closed_loop.plots import workspace_figure

        return workspace_figure(p3.Geometry3RRR.from_params(mech.params), path, phi, n=n)
    m = singularity_map(mech, mode=1, n=n)
    return plot_singularity_map(m, path)


def nan_to_none(value: Any) -> Any:
    """Arrays/floats with NaN -> nested lists with None (strict JSON)."""
    if isinstance(value, np.ndarray) and value.dtype.kind == "f":
        return [nan_to_none(v) for v in value] if value.ndim else nan_to_none(float(value))
    if isinstance(value, float) and not np.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: nan_to_none(v) for k, v in value.items()}
    if isinstance(value, list):
        return [nan_to_none(v) for v in value]
    return value
