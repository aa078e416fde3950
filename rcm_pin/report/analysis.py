"""Report section: singularities (paper 003's claims), workspace (paper 000 Fig. 7), accuracy."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rcm_pin.analysis import singularity
from rcm_pin.catalog import load
from rcm_pin.mechanisms.rcm import accuracy, workspace
from rcm_pin.mechanisms.rcm.singularity import paper_claims
from rcm_pin.report.framework import Comparison, Section, comparison_table


def section(out_dir: Path) -> Section:
    """Singularity verdicts by rank, workspace volume and rig-spec check, RCM sensitivities."""
    mech = load("rcm_bevel")
    claims = paper_claims(mech)
    lines = [
        "| claim (003) | q | rank full / position | verdict | why |",
        "| --- | --- | --- | --- | --- |",
    ]
    for c in claims:
        q = ", ".join(f"{v:.4g}" for v in c["q"])  # type: ignore[attr-defined]
        lines.append(
            f"| {c['claim']} | ({q}) | {c['rank_full']}/{c['rank_position']} "
            f"(regular {c['rank_full_regular']}/{c['rank_position_regular']}) | {c['verdict']} "
            f"| {c['explanation']} |"
        )
    ws_png = out_dir / "workspace_sections.png"
    workspace.plot_sections(mech, ws_png)
    spec = workspace.spec_check(mech)
    mc, err = workspace.volume_monte_carlo(mech, 20_000)
    rows = [
        Comparison(
            "workspace volume, Monte Carlo of abs(det J_p) (Pinocchio)",
            None,
            mc,
            "m³",
            f"standard error {err:.2g}",
        ),
        Comparison("workspace volume, analytic ∫ q3² cos q2", None, spec.workspace_volume, "m³"),
        Comparison("rig spec volume (60° cone, 0.05..0.12 m)", None, spec.spec_volume, "m³"),
        Comparison(
            "largest contained cone half-angle",
            60.0,
            float(np.rad2deg(spec.max_half_angle)),
            "deg",
            "the q1, q2 box touches the cone along 4 generators",
            tolerance=1e-6,
        ),
    ]
    grid_png = out_dir / "singularity_grid.png"
    xs, ys, vals = singularity.grid(
        mech, [0.3, 0.0, 0.08, 0.1, 0.5, 0.2], 1, 4, 61, span=((-np.pi, np.pi), (-np.pi, np.pi))
    )
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 5))
    im = ax.pcolormesh(xs, ys, vals, shading="auto")
    fig.colorbar(im, ax=ax, label="manipulability (6x6) = |q3² cos q2 sin q5|")
    ax.set(
        xlabel="q2 [rad]",
        ylabel="q5 [rad]",
        title="rcm_bevel (zyz): zero lines cos q2 = 0, sin q5 = 0",
    )
    fig.tight_layout()
    fig.savefig(grid_png, dpi=100)
    plt.close(fig)
    q_acc = np.array([0.5 * mech.upper[0], 0.8 * mech.upper[1], 0.085, 0.0, 0.5, 0.0])
    acc = accuracy.report(mech, q_acc)["rows"]
    top = [r for r in acc if r["rcm_per_error"] > 1e-9][:8]
    acc_lines = [
        "| error | unit | tool centre moves [mm] | RCM line misses A by [mm] |",
        "| --- | --- | ---: | ---: |",
    ]
    for r in top:
        acc_lines.append(
            f"| {r['parameter']} | {r['kind']} | {r['tool_per_error'] * 1e3:.3g} "
            f"| {r['rcm_per_error'] * 1e3:.3g} |"
        )
    body = f"""
### Singularities (paper 003's claims decided by rank)

Tolerance: σi counts when σi > 1e-9·σ1. det J = q3²·cos q2·sin q5 (zyz wrist).

{chr(10).join(lines)}

Also singular (not claimed by the papers): the wrist with e6 ∥ e4 (sin q5 = 0 for the zyz
wrist, cos q5 = 0 for rpy); the paper's own velocity example sits on the zyz one.
Map of the manipulability over (q2, q5): `singularity_grid.png`.

### Workspace (paper 000 Fig. 7)

{comparison_table(rows)}

Rig spec: contained = {spec.contains}; angular margin {np.rad2deg(spec.angular_margin):.3g}°,
inner margin {spec.inner_margin * 1e3:.3g} mm, outer margin {spec.outer_margin * 1e3:.3g} mm
(zero margins: the default limits were chosen to contain the spec exactly); the workspace is
{100 * (spec.workspace_volume / spec.spec_volume - 1):.1f} % larger than the spec (the corners of
the q1–q2 box). Sections: `workspace_sections.png`.

### Accuracy (linear theory of paper 004), q = {np.round(q_acc, 3).tolist()}

Consistent design changes of l9, a7_x, a7_z (re-rendered) keep the output axis through A;
errors that break the equal-rotation transmission or a single part's placement do not. The
largest, per 0.1 mm / 0.1° / 0.1 % of a ratio:

{chr(10).join(acc_lines)}
"""
    return Section("Singularities, workspace and accuracy", body, (ws_png.name, grid_png.name))
