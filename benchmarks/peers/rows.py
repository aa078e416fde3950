"""The rows of the comparison (README.md, "What each row measures"), and the venvs' setup.

A row's case is made here, in the harness's process (rcm-pin imported): the model file
every contender loads, the reference, the initial state and a reference solution for the
accuracy figures; the workers of the peers' venvs get it as JSON and import no rcm-pin.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from harness import Contender, Row

#: The commands that make each peer's venv (README.md; ``$VENVS`` is ``--venvs``).
INSTALLS = {
    "crocoddyl": (
        "python3.11 -m venv $VENVS/crocoddyl && $VENVS/crocoddyl/bin/pip install "
        "pin==4.0.0 crocoddyl==3.2.1 mim-solvers==0.3.0 example-robot-data==5.0.0"
    ),
    "drake": "python3.11 -m venv $VENVS/drake && $VENVS/drake/bin/pip install drake==1.51.0",
}
#: paper 000's reference (rcm_pin.control.references.TRAJECTORIES["paper000"]).
PAPER000 = {"centre": [0.1, 0.1, 0.1], "amplitude": [0.01, 0.01, 0.01], "omega": 10.0,
            "phase": [0.0, 1.5707963267948966, 0.0]}  # fmt: skip


def _write(scratch: Path, name: str, text: str) -> str:
    path = scratch / name
    path.write_text(text)
    return str(path)


def tracking_case(limits: str) -> Any:
    """Paper 000's tracking OCP on rcm_two_mass, N = 100 (``limits``: none | urdf |
    binding = 0.8 × the exact solution's peak efforts)."""

    def make(scratch: Path) -> dict[str, Any]:
        import numpy as np

        from ocp import paper000 as paper

        _, mech = paper.build("rcm_two_mass", 100, drive_limits=False)
        lo, hi = paper.limits(mech, lock_wrist=False)
        lim = {"none": None, "urdf": mech.model.effortLimit.tolist(),
               "binding": (0.8 * paper.peak_efforts(mech)).tolist()}[limits]  # fmt: skip
        return {
            "mechanism": "rcm_two_mass", "urdf": _write(scratch, "rcm_two_mass.urdf", mech.urdf),
            "frame": "tool", "horizon": paper.HORIZON, "n_intervals": 100,
            "traj": PAPER000, "x0": paper.initial_state(mech).tolist(),
            "lower": lo.tolist(), "upper": hi.tolist(), "limits": limits, "effort_limits": lim,
            "position_weight": 1e6, "tol": 1e-12,
            "exact_peak_efforts": np.asarray(paper.peak_efforts(mech)).tolist(),
        }  # fmt: skip

    return make


def rcm_ik_case(arm: str, targets: int) -> Any:
    """The arm at its chosen trocar (``rcm_comparison.make_setup``), ``targets`` tip
    targets along the circle path after its start, the start configuration (tip on the
    path's first point, RCM met) and the arm's URDF for the peer: the joints outside the
    chain (the gripper's fingers) fixed, no visual or collision geometry (kinematics only,
    the same links and joints)."""

    def make(scratch: Path) -> dict[str, Any]:
        import xml.etree.ElementTree as ET

        from rcm_pin.studies.rcm_comparison import make_setup, start_configuration
        from rcm_pin.studies.surgical_paths import surgical_path

        s = make_setup(arm)
        assert s.chain is not None
        p = surgical_path("circle", s.cone, rate=targets / 4.0).p[: targets + 1]
        chain = [str(n) for n in list(s.chain.model.names)[1:]]
        root = ET.fromstring(s.mech.urdf)
        for link in root.iter("link"):
            for tag in ("visual", "collision"):
                for el in link.findall(tag):
                    link.remove(el)
        for joint in root.iter("joint"):
            if joint.get("type") != "fixed" and joint.get("name") not in chain:
                joint.set("type", "fixed")
                for tag in ("mimic", "limit", "axis", "dynamics"):
                    for el in joint.findall(tag):
                        joint.remove(el)
        tool = s.chain.tool
        return {
            "arm": arm, "urdf": _write(scratch, f"{arm}_kinematics.urdf", ET.tostring(
                root, encoding="unicode")), "joints": chain,
            "axis_frame": str(s.chain.model.frames[tool.axis_frame].name), "axis": tool.axis,
            "tip_offset": tool.tip_offset, "trocar": list(tool.trocar),
            "q0": start_configuration(s, p[0]).tolist(), "targets": p[1:].tolist(),
            "tol": 1e-12, "snopt_tol": 1e-10,
        }  # fmt: skip

    return make


def sim_case(scratch: Path) -> dict[str, Any]:
    """1 s of rcm_two_mass (q3 ≤ 0.3 m) under task-space computed torque on paper 000's
    reference (K_n = 720, K_c = 12, URDF drive limits), 101 samples, with a reference run
    at rtol 1e-12 / atol 1e-14 for Δq."""
    import numpy as np

    import rcm_pin
    from rcm_pin.control.computed_torque import ComputedTorque, Gains, drive_limits
    from rcm_pin.control.references import TRAJECTORIES
    from rcm_pin.control.simulate import SimulationOptions, initial_state, simulate

    mech = rcm_pin.load("rcm_two_mass", q3_upper=0.3)
    ctrl = ComputedTorque(
        mech, TRAJECTORIES["paper000"], Gains(720.0, 12.0), limits=drive_limits(mech)
    )
    tight = simulate(mech, ctrl, 1.0, options=SimulationOptions(rtol=1e-12, atol=1e-14,
                                                                samples=101))  # fmt: skip
    return {
        "mechanism": "rcm_two_mass", "xacro_args": {"q3_upper": 0.3},
        "urdf": _write(scratch, "rcm_two_mass_sim.urdf", mech.urdf), "frame": "tool",
        "joints": list(mech.model.names)[1:], "duration": 1.0, "samples": 101,
        "t": tight.t.tolist(), "q_ref": tight.q.tolist(), "traj": PAPER000,
        "kn": 720.0, "kc": 12.0, "limits": drive_limits(mech).tolist(),
        "q0": initial_state(mech, ctrl).tolist(), "rtol": 1e-10, "atol": 1e-12,
        "accuracy_drake": 1e-10, "dt_mujoco": 1e-3, "scratch": str(scratch),
        "reference_run": {"rtol": 1e-12, "atol": 1e-14, "status": tight.status,
                          "max_abs_q": float(np.abs(tight.q).max())},
    }  # fmt: skip


def closed_fk_case(name: str) -> Any:
    """A closed loop of the drives of ``name`` about its home configuration (±0.05 rad,
    200 poses), each pose warm-started from the previous solution; ``q_ref``: rcm-pin's
    solutions (Δq of the peer), ``residual_tol``: the closure tolerance both meet."""

    def make(scratch: Path) -> dict[str, Any]:
        import numpy as np

        import rcm_pin

        mech = rcm_pin.load(name)
        assert mech.loops is not None
        d0 = mech.home[mech.loops.drive_q]
        s = np.linspace(0.0, 2 * np.pi, 200, endpoint=False)[:, None]
        k = np.arange(len(d0))
        drives = d0 + 0.05 * np.sin(s * (1 + k % 2) + k)
        q, refs = mech.home, []
        for d in drives:
            q = rcm_pin.forward(mech, d, q_guess=q).solutions[0].q
            refs.append(q)
        return {"mechanism": name, "drives": drives.tolist(), "q_home": mech.home.tolist(),
                "q_ref": np.array(refs).tolist()}  # fmt: skip

    return make


#: The Crocoddyl side of the tracking rows (point it at another file to compare another
#: implementation of the same case; ``script_adapter.py`` wraps a ``run(rounds)`` script).
TRACK = "tracking_crocoddyl_worker.py"
#: The rows, in the order of the table.
ROWS: list[Row] = [
    Row("tracking_free", "tracking OCP, rcm_two_mass, paper-000 reference, N=100, no limits",
        (Contender("rcm-pin TrackingOCP (default)", "tracking_rcm.py",
                   case={"config": "default"}),
         Contender("rcm-pin TrackingOCP (compiled)", "tracking_rcm.py",
                   case={"config": "compiled"}),
         Contender("Crocoddyl FDDP", TRACK, "crocoddyl", True, {"solver": "fddp"})),
        tracking_case("none")),
    Row("tracking_urdf", "the same, URDF limits (inactive)",
        (Contender("rcm-pin TrackingOCP (default)", "tracking_rcm.py",
                   case={"config": "default"}),
         Contender("rcm-pin TrackingOCP (compiled)", "tracking_rcm.py",
                   case={"config": "compiled"}),
         Contender("Crocoddyl BoxFDDP", TRACK, "crocoddyl", True, {"solver": "boxfddp"})),
        tracking_case("urdf")),
    Row("tracking_binding", "the same, binding limits (0.8 × peak)",
        (Contender("rcm-pin TrackingOCP (default)", "tracking_rcm.py",
                   case={"config": "default"}),
         Contender("rcm-pin TrackingOCP (compiled)", "tracking_rcm.py",
                   case={"config": "compiled"}),
         Contender("Crocoddyl BoxFDDP", TRACK, "crocoddyl", True, {"solver": "boxfddp"}),
         Contender("mim-solvers CSQP", TRACK, "crocoddyl", True, {"solver": "csqp"})),
        tracking_case("binding")),
    Row("rcm_ik", "RCM inverse kinematics, panda, 100 warm-started targets along a circle",
        (Contender("rcm-pin RcmIK", "rcm_ik_rcm.py"),
         Contender("Drake InverseKinematics + SNOPT", "rcm_ik_drake_worker.py", "drake",
                   True)),
        rcm_ik_case("panda", 100), per=100),
    Row("rcm_step", "RCM differential step at 1 kHz (panda, circle)",
        (Contender("rcm-pin RcmQP.step (QP)", "rcm_step_rcm.py", case={"method": "qp"}),
         Contender("rcm-pin RcmQP.step_pink (pink)", "rcm_step_rcm.py",
                   case={"method": "pink"})),
        {"arm": "panda", "steps": 500}, per=500, unit="µs", note="no peer: rcm-pin only"),
    Row("sim", "1 s of computed-torque simulation, rcm_two_mass",
        (Contender("rcm-pin simulate (python)", "sim_rcm.py", case={"backend": "python"}),
         Contender("rcm-pin simulate (compiled)", "sim_rcm.py",
                   case={"backend": "compiled"}),
         Contender("Drake RK5 at 1e-10", "sim_drake.py", "drake", True),
         Contender("MuJoCo Euler 1 ms", "sim_mujoco.py", peer=True)),
        sim_case),
    Row("closed_fk_3rrr", "closed-loop direct kinematics along a path, warm, planar 3-RRR",
        (Contender("rcm-pin forward(q_guess=)", "closed_fk_rcm.py"),
         Contender("scipy root (hybr) on the same closures", "closed_fk_scipy.py",
                   peer=True)),
        closed_fk_case("planar_3rrr"), per=200, unit="µs"),
    Row("closed_fk_spherical", "the same, spherical 3-RRR",
        (Contender("rcm-pin forward(q_guess=)", "closed_fk_rcm.py"),
         Contender("scipy root (hybr) on the same closures", "closed_fk_scipy.py",
                   peer=True)),
        closed_fk_case("spherical_3rrr"), per=200, unit="µs"),
    Row("inverse", "rcm_pin.inverse, one rcm_bevel pose, all 8 branches",
        (Contender("rcm-pin inverse", "inverse_rcm.py"),
         Contender("the scalar analytic IK (floor)", "inverse_analytic.py", peer=True)),
        {"mechanism": "rcm_bevel", "poses": 200, "seed": 0}, per=200, unit="µs"),
    Row("closed_sim", "closed-plant simulate (3-RRR circle) per simulated second",
        (Contender("rcm-pin simulate (python)", "closed_sim_rcm.py", case={"backend": "python"}),
         Contender("rcm-pin simulate (compiled)", "closed_sim_rcm.py",
                   case={"backend": "compiled"}),
         Contender("its Pinocchio floor", "closed_sim_pinocchio.py", peer=True)),
        {"mechanism": "planar_3rrr", "scenario": "circle", "duration": 0.5}, per=0.5),
]  # fmt: skip

__all__ = ["INSTALLS", "PAPER000", "ROWS", "closed_fk_case", "sim_case", "tracking_case"]
