"""Report section: the MuJoCo export (issue 28), its solver settings and the same scenario
stepped on MuJoCo against the rigid simulation.

For each mechanism: the timestep and the constraint drift over 0.2 s that the export's rule
predicts (:mod:`rcm_pin.export.settings`), then the default scenario of ``rcm-pin simulate``
run twice with the same computed-torque law: on Pinocchio (rigid closures) and on the
exported MJCF (``simulate --engine mujoco``, the law held for 1 ms). The table shows the
largest equality residual of the MuJoCo run against the predicted drift, and the largest
difference of the coordinates between the two runs, to which the 1 ms hold of the law
contributes (five_bar: 8.4e-5 with a 1 ms hold, 2.1e-5 with 0.25 ms: ``docs/mujoco.md``).
"""

from __future__ import annotations

import importlib.util
import warnings
from pathlib import Path
from typing import Any

import rcm_pin
from rcm_pin.control.scenario import run, scenarios
from rcm_pin.report.framework import Section

#: The mechanisms of the section and their xacro arguments: a closed planar loop, a closed
#: 3-DOF parallel mechanism and a serial RCM arm with mimic transmissions (its insertion
#: range widened to the paper's trajectory, which MuJoCo's joint ranges would otherwise
#: stop: the rigid run's default range is the paper's rig, 0.05..0.12 m).
NAMES: dict[str, dict[str, Any]] = {
    "five_bar": {},
    "planar_3rrr": {},
    "rcm_bevel": {"q3_upper": 0.3},
}


def section(out_dir: Path) -> Section:
    """The settings and the two runs per mechanism (MuJoCo missing: the section says so)."""
    title = "MuJoCo export: the same scenario on the exported model"
    if importlib.util.find_spec("mujoco") is None:
        return Section(title, "MuJoCo is not installed: `pip install 'rcm-pin[mujoco]'`.\n")
    from rcm_pin.export.settings import choose
    from rcm_pin.export.simulate import simulate_mujoco

    lines = [
        "`rcm-pin export NAME --mjcf OUT.xml` writes the mechanism as MJCF: mimic joints as "
        "joint equalities, closures as `connect` / `weld`, solver settings chosen so that the "
        "predicted constraint drift over 0.2 s stays under 1e-6 (`docs/mujoco.md`). The "
        "default scenario of each mechanism, the same computed-torque law on both plants:",
        "",
        "| mechanism | scenario | dt [s] | predicted drift 0.2 s | max equality residual "
        "| max \\|q_MuJoCo − q_rigid\\| [rad, m] | law held [s] |",
        "| --- | --- | ---: | ---: | ---: | ---: | ---: |",
    ]
    for name, args in NAMES.items():
        mech = rcm_pin.load(name, **args)
        scenario, sc = next(iter(scenarios(mech).items()))
        settings = choose(mech)
        rigid = run(mech, sc)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the export's documented inertia floor
            on_mujoco = simulate_mujoco(mech, sc, compare=rigid)
        lines.append(
            f"| {name} | {scenario} | {settings.timestep:g} | {settings.predicted_drift:.1e} "
            f"| {on_mujoco.max_equality_residual:.1e} | {on_mujoco.max_difference:.1e} "
            f"| {on_mujoco.control_period:g} |"
        )
    return Section(title, "\n".join(lines) + "\n")


__all__ = ["NAMES", "section"]
