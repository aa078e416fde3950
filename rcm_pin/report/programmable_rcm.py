"""Report section: a programmable RCM on ordinary arms beside the mechanical RCM.

The same surgical task (:mod:`rcm_pin.studies.surgical_paths`: the circle, 4 s at 1 kHz,
with the insertion depth changing) for rcm_bevel (mechanical RCM, analytic IK) and for
panda and ur5 (programmable RCM: one QP per 1 ms step, :mod:`rcm_pin.control.rcm_qp`, at
the trocar chosen by reachability and manipulability); figures of merit by
:mod:`rcm_pin.studies.rcm_metrics`; the CasADi routes (:mod:`ocp.rcm`,
:mod:`ocp.rcm_tracking`) on the arms; a plot and a side-by-side Meshcat animation.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from ocp.rcm import RcmIK
from ocp.rcm_tracking import RcmTrackingOCP
from rcm_pin.control.rcm_loop import track
from rcm_pin.report.framework import Section
from rcm_pin.studies.rcm_comparison import (
    COMPARED,
    RcmTrack,
    choose_trocar,
    controller,
    make_setup,
    run,
    start_configuration,
)
from rcm_pin.studies.rcm_metrics import errors, metrics, table
from rcm_pin.studies.surgical_paths import PATHS, surgical_path

FIGURE = "programmable_rcm.png"
ANIMATION = "programmable_rcm.html"
GOALS = "RCM error ≤ 1e-6 m (QP, 1 kHz), ≤ 1e-9 m (NLP); tip error ≤ 1e-4 m; QP step ≤ 0.2 ms"


def nlp_figures(name: str) -> dict[str, float]:
    """RCM IK (exact and 1 mm tolerance) at every path checkpoint (1 Hz samples of the
    three paths, continuation) and the tracking OCP on 0.5 s of the circle at 100 Hz."""
    s = make_setup(name)
    assert s.chain is not None
    out = {"ik_rcm": 0.0, "ik_tip": 0.0, "tol_rcm": 0.0, "tol_tip": 0.0}
    exact, loose = RcmIK(s.chain.model, s.chain.tool), RcmIK(s.chain.model, s.chain.tool,
                                                             tolerance=1e-3)  # fmt: skip
    q = s.home[s.chain.active]
    for path in PATHS:
        for p in surgical_path(path, s.cone, rate=1.0).p:
            r, rt = exact.solve(p, q), loose.solve(p, q)
            q = r.ik.q
            for key, value in (("ik_rcm", r.rcm_error), ("ik_tip", r.tip_error),
                               ("tol_rcm", rt.rcm_error), ("tol_tip", rt.tip_error)):  # fmt: skip
                out[key] = max(out[key], value)
    sp = surgical_path("circle", s.cone, rate=100.0, duration=0.5)
    q0 = start_configuration(s, sp.p[0])
    guess = track(controller(s, 0.01), q0, sp.p).q
    ocp = RcmTrackingOCP(
        s.chain.model, s.chain.tool, n_intervals=len(sp.t) - 1, dt=0.01, drive_limits=True
    )
    res = ocp.solve(sp.p, q0, guess=guess)
    out.update(ocp_rcm=float(res.rcm_error.max()), ocp_tip=float(res.tip_error.max()),
               ocp_time=res.solve_time, ocp_iterations=float(res.iterations),
               ocp_tau=float(np.abs(res.tau).max()))  # fmt: skip
    return out


def plot(tracks: list[RcmTrack], path: Path) -> None:
    """RCM error, tip error and joint speeds over time, one colour per manipulator."""
    fig, axes = plt.subplots(1, 3, figsize=(15, 4))
    for tr in tracks:
        rcm, tip = errors(tr)
        label = f"{tr.setup.mech.name} ({'mechanical' if tr.setup.mechanical else 'QP'})"
        axes[0].semilogy(tr.t, np.maximum(rcm, 1e-18), label=label)
        axes[1].semilogy(tr.t, np.maximum(tip, 1e-18), label=label)
        speed = np.linalg.norm(np.diff(tr.q, axis=0), axis=1) / np.diff(tr.t)
        axes[2].plot(tr.t[1:], speed, label=label)
    for ax, title in zip(axes, ("RCM error [m]", "tip error [m]", "|q̇| [rad/s, m/s]")):
        ax.set_title(title)
        ax.set_xlabel("t [s]")
        ax.grid(True, alpha=0.3)
    axes[0].axhline(1e-6, color="k", lw=0.8, ls="--")
    axes[1].axhline(1e-4, color="k", lw=0.8, ls="--")
    axes[0].legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def side_by_side(tracks: list[RcmTrack], path: Path, fps: float = 20.0) -> Path:
    """One HTML page with one recorded Meshcat animation per run, side by side.

    One Meshcat viewer per run on one page (:func:`rcm_pin.viz.scene.panes_html`): the
    JavaScript once, every mesh once (no hidden collision copies), the animation as
    transforms, the commands gzip-compressed (49 MB of ``iframe`` s before, about 9 MB now).
    """
    from rcm_pin.viz import Viewer
    from rcm_pin.viz.scene import panes_html

    panes = []
    for tr in tracks:
        every = max(1, round(1.0 / (fps * float(tr.t[1] - tr.t[0]))))
        with Viewer(tr.setup.mech) as viewer:
            viewer.animate(tr.q[::every], 1.0 / fps, repetitions=100)
            panes.append((tr.setup.mech.name, viewer.scene_commands()))
    path.write_text(panes_html(panes, title="programmable RCM beside the mechanical RCM"))
    return path


def report_section(out_dir: Path, names: tuple[str, ...] = COMPARED, animation: bool = True) -> str:
    """The markdown of the section (module docstring); writes the figure and animation."""
    out_dir.mkdir(parents=True, exist_ok=True)
    tracks = [run(make_setup(n), "circle") for n in names]
    rows = [metrics(tr) for tr in tracks]
    plot(tracks, out_dir / FIGURE)
    lines = [
        "## Programmable RCM on ordinary arms beside the mechanical RCM",
        "",
        "The tool tip follows a circle of radius 15 mm inside a 30° cone below the trocar, "
        "one turn in 4 s (minimum-jerk phase, peak tip speed about 45 mm/s) with the "
        "insertion depth changing by ±10 mm, sampled at 1 kHz. A mechanical RCM keeps its shaft "
        "through its remote centre by construction and solves each sample by its analytic "
        "IK; the arms carry a 0.3 m shaft along the z axis of their tool frame and keep "
        "it through the trocar in software: per 1 ms step one QP (tip and point-to-line RCM "
        "rows as equalities, a posture pull in the redundancy, joint position and velocity "
        "limits; qpsolvers with daqp); the λ-parametrised RCM point of Aghakhani et al. "
        "(ICRA 2013) is the second formulation, checked against this one in the tests. "
        "The RCM error is the distance of the trocar from the "
        "shaft line, recomputed from the joint trajectory by Pinocchio forward kinematics.",
        "",
        f"Goals: {GOALS}.",
        "",
        table(rows),
        "",
        "Velocity and torque peaks: largest joint entry (RNEA with gravity, the arms' own "
        "inertias); Δq̇ per step: the largest step-to-step change of a joint speed (a stair "
        "step would show as a jump of the order of the speed itself); manipulability "
        "sqrt(det(J Jᵀ)) of the tip Jacobian restricted to the RCM constraint's null space, "
        "along the path and over a 51-point grid of the cone (over the points reached; "
        "unreached: grid points the arm did not reach with the RCM met from its working "
        "posture, by continuation or from home). A mechanical RCM's step is one call of "
        "the analytic inverse through rcm_pin.inverse (all branches, each checked by "
        "Pinocchio FK).",
        "",
        "**Trocar of the arms**: 9 candidates around the shaft of the home posture (0.10, "
        "0.15, 0.20 m below the tool frame, −0.1 / 0 / +0.1 m radially); reachable when the "
        "arm reaches every checkpoint of the three paths in turn with the RCM met inside its "
        "limits; the largest smallest RCM-constrained manipulability wins.",
        "",
    ]
    for name in names:
        mech_row = next(t for t in tracks if t.setup.mech.name == name).setup
        if mech_row.mechanical:
            continue
        _, scored = choose_trocar(name)
        reach = sum(v > 0 for _, v in scored)
        lines.append(
            f"- {name}: trocar {np.round(mech_row.tool.trocar, 4).tolist()} m; {reach} of "
            f"{len(scored)} candidates reachable; best smallest manipulability "
            f"{max(v for _, v in scored):.3e}."
        )
    lines += ["", "**CasADi routes** (IPOPT): RCM IK at the 1 Hz checkpoints of the three "
              "paths (exact equality, and a 1 mm tolerance), and the tracking OCP with the "
              "RCM as a path constraint (and the drive limits) on 0.5 s of the circle at "
              "100 Hz:", ""]  # fmt: skip
    for name in names:
        if make_setup(name).mechanical:
            continue
        f = nlp_figures(name)
        lines.append(
            f"- {name}: IK exact RCM {f['ik_rcm']:.1e} m, tip {f['ik_tip']:.1e} m; tolerance "
            f"1e-3: RCM {f['tol_rcm']:.1e} m, tip {f['tol_tip']:.1e} m; OCP RCM "
            f"{f['ocp_rcm']:.1e} m, tip {f['ocp_tip']:.1e} m, τ peak {f['ocp_tau']:.3g} N·m "
            f"within the URDF effort limits ({f['ocp_iterations']:.0f} "
            f"iterations, {f['ocp_time']:.2f} s)."
        )
    lines += ["", f"![RCM error, tip error and joint speeds]({FIGURE})", ""]
    if animation:
        side_by_side(tracks, out_dir / ANIMATION)
        lines.append(f"Side-by-side Meshcat animation: [{ANIMATION}]({ANIMATION}).")
    return "\n".join(lines) + "\n"


def section(out_dir: Path) -> Section:
    """The programmable-RCM section of ``rcm-pin reproduce``."""
    sec = Section.from_markdown(report_section(out_dir), "Programmable RCM")
    return Section(sec.title, sec.body, (FIGURE,))


__all__ = ["FIGURE", "report_section", "section", "side_by_side"]
