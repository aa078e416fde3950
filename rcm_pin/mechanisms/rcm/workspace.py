"""Workspace of the RCM mechanisms: sampling, volume (three routes), rig-spec check, plots.

The tool centre of an RCM mechanism is p = q3·e4(q1, q2), i.e. spherical coordinates
about A, so the reachable set of the joint box B = [q1] × [q2] × [q3] is bounded by

- two spheres |p| = q3_lower and |p| = q3_upper about A,
- two planes through the x axis, q1 = ±q1_limit: y·cos q1 + z·sin q1 = 0,
- a circular cone about the x axis, x = |p|·sin q2 (q2 = ±q2_limit; half-angle
  90° − q2_limit about ∓x).

Volume routes:

1. analytic: the Jacobian determinant of (q1, q2, q3) -> p is q3²·cos q2, so for
   |q2| ≤ π/2 and an injective box (q1 range ≤ 2π, q3 of one sign)
   V = Δq1·(sin q2u − sin q2l)·(q3u³ − q3l³)/3;
2. Monte Carlo: V ≈ vol(B)·mean|det J_p(q)| over uniform joint samples, with J_p the
   position rows of Pinocchio's tool Jacobian (independent of the formula);
3. voxel counting of the sampled tool centres (an upper estimate that converges as the
   voxels shrink and the samples grow).

Rig spec (docs/conventions.md): a cone of half-angle 60° about z with apex A, cut by the
spheres 0.05 m and 0.12 m. The largest cone about z contained in the workspace has
half-angle θ_max = min over boundary directions (bisection on the joint limits).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
from tqdm import tqdm

from rcm_pin.errors import InvalidInputError
from rcm_pin.mechanisms.rcm.closed_form import tool_position
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.rotations import FloatArray

#: Rig spec of paper 000 (docs/conventions.md).
SPEC_HALF_ANGLE = np.deg2rad(60.0)  # [rad]
SPEC_R_MIN = 0.05  # [m]
SPEC_R_MAX = 0.12  # [m]
#: Sample count above which a progress bar is shown.
PROGRESS_THRESHOLD = 200_000


def _require_rcm(mech: Mechanism) -> None:
    if mech.rcm is None or mech.family.name != "rcm":
        raise InvalidInputError(
            f"workspace analysis needs an RCM mechanism, got {mech.name}; valid: rcm_bevel, "
            "rcm_bevel_4dof, rcm_belt"
        )


def sample_joints(mech: Mechanism, n: int, seed: int = 0) -> FloatArray:
    """n uniform joint samples within the limits, shape (n, nq) (vectorised)."""
    if n < 1:
        raise InvalidInputError(f"sample count {n}; valid: >= 1")
    rng = np.random.default_rng(seed)
    return rng.uniform(mech.lower, mech.upper, size=(n, mech.nq))


def tool_centres(mech: Mechanism, qs: FloatArray, progress: bool | None = None) -> FloatArray:
    """Tool centres (n, 3) [m] by the closed form, in chunks with a tqdm bar for large n."""
    _require_rcm(mech)
    show = len(qs) > PROGRESS_THRESHOLD if progress is None else progress
    chunks = np.array_split(qs, max(1, len(qs) // 100_000))
    return np.concatenate(
        [tool_position(c) for c in tqdm(chunks, desc="workspace", disable=not show)]
    )


def volume_analytic(mech: Mechanism) -> float:
    """V = Δq1·(sin q2u − sin q2l)·(q3u³ − q3l³)/3 [m³] (conditions in the module doc)."""
    _require_rcm(mech)
    lo, hi = mech.lower, mech.upper
    if lo[1] < -np.pi / 2 or hi[1] > np.pi / 2 or lo[2] * hi[2] < 0 or hi[0] - lo[0] > 2 * np.pi:
        raise InvalidInputError(
            "the analytic volume needs |q2| <= pi/2, q3 of one sign and a q1 range <= 2 pi; "
            f"limits are {lo.tolist()} .. {hi.tolist()}"
        )
    return float(
        (hi[0] - lo[0]) * (np.sin(hi[1]) - np.sin(lo[1])) * abs(hi[2] ** 3 - lo[2] ** 3) / 3
    )


def volume_monte_carlo(mech: Mechanism, n: int, seed: int = 0) -> tuple[float, float]:
    """V ≈ vol(B)·mean|det J_p| with Pinocchio's J_p (first three coordinates) [m³].

    Returns:
        (estimate, standard error) [m³].
    """
    from rcm_pin.analysis.jacobians import tool_jacobian

    _require_rcm(mech)
    qs = sample_joints(mech, n, seed)
    dets = np.empty(n)
    for k in tqdm(range(n), desc="volume", disable=n <= PROGRESS_THRESHOLD):
        dets[k] = abs(np.linalg.det(tool_jacobian(mech, qs[k])[:3, :3]))
    box = float(np.prod(mech.upper[:3] - mech.lower[:3]))
    return box * float(dets.mean()), box * float(dets.std(ddof=1) / np.sqrt(n))


def volume_voxels(points: FloatArray, voxel: float) -> float:
    """Occupied-voxel volume of a point cloud [m³] (voxel edge ``voxel`` [m])."""
    if voxel <= 0:
        raise InvalidInputError(f"voxel edge {voxel}; valid: > 0")
    cells = np.unique(np.floor(points / voxel).astype(np.int64), axis=0)
    return float(len(cells) * voxel**3)


def _directions_in_limits(mech: Mechanism, theta: float, m: int = 3600) -> bool:
    phi = np.linspace(0, 2 * np.pi, m, endpoint=False)
    d = np.stack(
        [np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.full(m, np.cos(theta))], -1
    )
    q2 = np.arcsin(np.clip(d[:, 0], -1, 1))
    q1 = np.arctan2(-d[:, 1], d[:, 2])
    eps = 1e-12
    ok1 = (q1 >= mech.lower[0] - eps) & (q1 <= mech.upper[0] + eps)
    ok2 = (q2 >= mech.lower[1] - eps) & (q2 <= mech.upper[1] + eps)
    return bool(np.all(ok1 & ok2))


def max_contained_cone(mech: Mechanism) -> float:
    """Largest half-angle θ [rad] of a cone about z (apex A) whose directions all lie in the
    joint limits (bisection, 1e-10 rad)."""
    _require_rcm(mech)
    lo, hi = 0.0, np.pi / 2
    if not _directions_in_limits(mech, 0.0):
        return 0.0
    while hi - lo > 1e-10:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _directions_in_limits(mech, mid) else (lo, mid)
    return lo


@dataclass(frozen=True)
class SpecCheck:
    """Does the workspace contain the rig spec region, and by what margin.

    Attributes:
        contains: every spec point is reachable within the limits.
        angular_margin: θ_max − spec half-angle [rad] (≥ 0 when the cone fits).
        inner_margin: spec r_min − q3_lower [m].
        outer_margin: q3_upper − spec r_max [m].
        max_half_angle: θ_max [rad].
        fraction_reached: Monte Carlo fraction of spec points reached.
        spec_volume: analytic spec volume 2π(1 − cos θ)(r2³ − r1³)/3 [m³].
        workspace_volume: analytic workspace volume [m³].
    """

    contains: bool
    angular_margin: float
    inner_margin: float
    outer_margin: float
    max_half_angle: float
    fraction_reached: float
    spec_volume: float
    workspace_volume: float


def spec_check(
    mech: Mechanism,
    half_angle: float = SPEC_HALF_ANGLE,
    r_min: float = SPEC_R_MIN,
    r_max: float = SPEC_R_MAX,
    n: int = 100_000,
    seed: int = 1,
) -> SpecCheck:
    """Check the rig spec region (cone about z, between two spheres) against the workspace."""
    _require_rcm(mech)
    theta = max_contained_cone(mech)
    rng = np.random.default_rng(seed)
    # uniform in the spherical shell sector: r³ uniform, cos θ uniform, φ uniform
    r = np.cbrt(rng.uniform(r_min**3, r_max**3, n))
    ct = rng.uniform(np.cos(half_angle), 1.0, n)
    ph = rng.uniform(0, 2 * np.pi, n)
    st = np.sqrt(1 - ct**2)
    p = r[:, None] * np.stack([st * np.cos(ph), st * np.sin(ph), ct], -1)
    q3 = np.linalg.norm(p, axis=1)
    q2 = np.arcsin(np.clip(p[:, 0] / q3, -1, 1))
    q1 = np.arctan2(-p[:, 1], p[:, 2])
    qs = np.stack([q1, q2, q3], -1)
    eps = 1e-12
    inside = np.all((qs >= mech.lower[:3] - eps) & (qs <= mech.upper[:3] + eps), axis=1)
    inner, outer = r_min - mech.lower[2], mech.upper[2] - r_max
    spec_v = 2 * np.pi * (1 - np.cos(half_angle)) * (r_max**3 - r_min**3) / 3
    return SpecCheck(
        contains=bool(theta >= half_angle - 1e-9 and inner >= -1e-12 and outer >= -1e-12),
        angular_margin=0.0 if abs(theta - half_angle) < 1e-9 else float(theta - half_angle),
        inner_margin=float(inner),
        outer_margin=float(outer),
        max_half_angle=float(theta),
        fraction_reached=float(inside.mean()),
        spec_volume=float(spec_v),
        workspace_volume=volume_analytic(mech),
    )


def boundary_description(mech: Mechanism) -> list[str]:
    """The faces of the reachable set (module docstring), with the mechanism's limits."""
    lo, hi = mech.lower, mech.upper
    return [
        f"sphere |p| = {lo[2]:.4g} m (q3 = q3_lower)",
        f"sphere |p| = {hi[2]:.4g} m (q3 = q3_upper)",
        f"half-planes through the x axis at q1 = {np.rad2deg(lo[0]):.4g} deg and "
        f"{np.rad2deg(hi[0]):.4g} deg (y cos q1 + z sin q1 = 0)",
        f"cones about the x axis x = |p| sin q2 at q2 = {np.rad2deg(lo[1]):.4g} deg and "
        f"{np.rad2deg(hi[1]):.4g} deg",
    ]


def summary(mech: Mechanism, samples: int = 200_000, seed: int = 0) -> dict[str, object]:
    """Everything the CLI prints: volumes by three routes, spec check, boundary."""
    qs = sample_joints(mech, samples, seed)
    pts = tool_centres(mech, qs)
    mc, mc_err = volume_monte_carlo(mech, min(samples, 20_000), seed)
    voxel = 0.004  # [m]
    return {
        "mechanism": mech.name,
        "samples": samples,
        "volume_analytic": volume_analytic(mech),
        "volume_monte_carlo": mc,
        "volume_monte_carlo_stderr": mc_err,
        "volume_voxels": volume_voxels(pts, voxel),
        "voxel_edge": voxel,
        "extent_min": pts.min(axis=0),
        "extent_max": pts.max(axis=0),
        "boundary": boundary_description(mech),
        "spec": asdict(spec_check(mech)),
    }


def plot_sections(mech: Mechanism, path: Path, samples: int = 200_000, seed: int = 0) -> Path:
    """PNG of workspace sections like paper 000 Fig. 7: x–z and y–z slabs, top view, with the
    rig-spec cone and spheres overlaid."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pts = tool_centres(mech, sample_joints(mech, samples, seed))
    slab = 0.004  # [m]
    # constrained layout sizes the equal-aspect panels with room for every label (the
    # top view is taller than the sections: tight_layout clipped its x label).
    fig, axes = plt.subplots(1, 3, figsize=(15, 5.4), layout="constrained")
    views = [
        (0, 2, np.abs(pts[:, 1]) < slab, "section y ~ 0 (x-z plane)", "x [m]", "z [m]"),
        (1, 2, np.abs(pts[:, 0]) < slab, "section x ~ 0 (y-z plane)", "y [m]", "z [m]"),
        (0, 1, np.ones(len(pts), bool), "top view (projection on x-y)", "x [m]", "y [m]"),
    ]
    t = np.linspace(-SPEC_HALF_ANGLE, SPEC_HALF_ANGLE, 100)
    for ax, (i, j, mask, title, xl, yl) in zip(axes, views):
        ax.scatter(pts[mask, i], pts[mask, j], s=0.3, alpha=0.3, color="tab:blue")
        if j == 2:
            for r in (SPEC_R_MIN, SPEC_R_MAX):
                ax.plot(r * np.sin(t), r * np.cos(t), "r-", lw=1)
            for s in (-1, 1):
                ax.plot(
                    [0, s * SPEC_R_MAX * np.sin(SPEC_HALF_ANGLE)],
                    [0, SPEC_R_MAX * np.cos(SPEC_HALF_ANGLE)],
                    "r-",
                    lw=1,
                )
        else:
            c = np.linspace(0, 2 * np.pi, 200)
            rr = SPEC_R_MAX * np.sin(SPEC_HALF_ANGLE)
            ax.plot(rr * np.cos(c), rr * np.sin(c), "r-", lw=1)
        ax.plot(0, 0, "k+", ms=10)
        ax.set(title=title, xlabel=xl, ylabel=yl, aspect="equal")
        ax.grid(alpha=0.3)
    fig.suptitle(f"{mech.name}: reachable tool centres (blue), rig spec 60 deg cone (red), A (+)")
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


__all__ = [
    "SPEC_HALF_ANGLE",
    "SPEC_R_MAX",
    "SPEC_R_MIN",
    "SpecCheck",
    "boundary_description",
    "max_contained_cone",
    "plot_sections",
    "sample_joints",
    "spec_check",
    "summary",
    "tool_centres",
    "volume_analytic",
    "volume_monte_carlo",
    "volume_voxels",
]
