"""Report section: paper 004's control example and the model-mismatch table.

The run and the table are :mod:`rcm_pin.studies.control_3dof` (reference, τ from the
0.06 s transient, computed torque on the closed-loop model); the figure shows the errors
beside the linear error dynamics and the drive forces (the paper's Fig. 9).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rcm_pin.report.framework import Comparison, Section, comparison_table
from rcm_pin.studies.control_3dof import (
    AMPLITUDE,
    NAME,
    ControlRun,
    ControlSettings,
    linear_error,
    mismatch_table,
    run,
    settling_factor,
)

#: The paper's bound on the change of the error under model mismatch [%].
PAPER_PERCENT = 3.0


def _figure(r: ControlRun, s: ControlSettings, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    lin = linear_error(r.t, s)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.2))
    for i, lab in enumerate("xyz"):
        axes[0].plot(r.t, 1e3 * r.error[:, i], lw=2, label=f"Δ{lab} simulated")
        axes[0].plot(r.t, 1e3 * lin[:, i], "k--", lw=1)
        axes[1].plot(r.t, r.forces[:, i], label=f"F{i + 1}")
    axes[0].axvline(s.transient, color="grey", lw=0.8)
    axes[0].set_title(
        f"position error [mm] (τ = {s.tau * 1e3:.2f} ms, ζ = {s.zeta:g}; dashed: linear)"
    )
    axes[1].set_title("drive forces [N]")
    for ax in axes:
        ax.set_xlabel("t [s]")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def section(out_dir: Path) -> Section:
    """The example's run, its check against the linear error dynamics, the mismatch table."""
    s = ControlSettings()
    r = run(s)
    fig = out_dir / "control_3dof.png"
    _figure(r, s, fig)
    rows = mismatch_table(ControlSettings(duration=0.25, samples=101))
    lines = [
        f"{NAME}: x_T, y_T, z_T = {AMPLITUDE} sin ωt [m], ω = {s.omega:.4g} rad/s; "
        f"τ²Δ̈ + 2ζτΔ̇ + Δ = 0 with ζ = {s.zeta:g}; transient time (|Δ| ≤ 5 % of |Δ(0)| for "
        f"good, Δ̇(0) = 0) {s.transient:g} s → τ = {s.transient:g}/{settling_factor():.4f} = "
        f"{s.tau:.6g} s. Initial error {s.offset} m.",
        "",
        f"- max |Δ − Δ_linear| = {r.linear_deviation(s):.2e} m (acceptance 1e-9), max closure "
        f"residual {r.closure_residual:.1e} m, peak drive force {np.max(np.abs(r.forces)):.2f} N, "
        f"{r.nfev} evaluations.",
        "",
        comparison_table(
            [
                Comparison(
                    "transient time, measured on the simulated error (5 % band)",
                    0.06,
                    r.transient_time(),
                    "s",
                    "",
                    1e-4,  # linear interpolation between 2.5 ms samples
                )
            ]
        ),
        "",
        "Model mismatch (controller's model vs the nominal plant, 0.25 s runs). Change of the "
        'error: max_t |Δ_mm − Δ₀| / max_t |Δ₀|; the paper\'s "at most 3 %" read as that ratio.',
        "",
        "| case | max ‖Δ‖ after transient [mm] | change of the error [%] | paper [%] "
        "| verdict | peak force [N] |",
        "| --- | ---: | ---: | ---: | --- | ---: |",
    ]
    for row in rows:
        lines.append(
            f"| {row['case']} | {row['error_after_transient_mm']:.4f} | "
            f"{row['change_percent']:.2f} | ≤ {PAPER_PERCENT:g} | "
            f"{'within' if row['change_percent'] <= PAPER_PERCENT else '**exceeds**'} | "
            f"{row['peak_force_N']:.2f} |"
        )
    lines += [
        "",
        "Reading: the output mass ±10 % stays well inside 3 %; neglecting the slider masses and "
        "a 1 mm length error exceed it here (the length error shifts the controller's own "
        "measure of x by ~1 mm, a steady offset the feedback cannot see). The percentages "
        "are relative to the chosen initial error (its norm is the peak of Δ₀); the mm column "
        "is not.",
    ]
    return Section("Paper 004: control of the translational 3-PPaPa", "\n".join(lines), (fig.name,))
