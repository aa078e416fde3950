"""MuJoCo export: any mechanism as an MJCF file, and the checks that prove it right.

* :mod:`.mjcf`: :func:`to_mjcf` writes the file (plain XML, no MuJoCo needed);
* :mod:`.settings`: the solver-settings rule, the drift prediction and the inertia floor;
* :mod:`.check`: loads a file in MuJoCo (the ``mujoco`` extra) and compares its mass
  matrix, bias and constrained dynamics with rcm-pin's, and measures a free motion's drift;
* :mod:`.simulate`: a scenario of ``rcm-pin simulate`` with MuJoCo as the plant.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from rcm_pin.lazy import lazy_exports

if TYPE_CHECKING:
    from rcm_pin.export.check import (
        MujocoModel,
        free_motion_drift,
        load_mujoco,
        rigid_limit_error,
        tree_error,
    )
    from rcm_pin.export.mjcf import MjcfExport, to_mjcf
    from rcm_pin.export.settings import SolverSettings
    from rcm_pin.export.simulate import MujocoRun, simulate_mujoco

_LAZY = {
    "MjcfExport": "mjcf",
    "MujocoModel": "check",
    "MujocoRun": "simulate",
    "SolverSettings": "settings",
    "free_motion_drift": "check",
    "load_mujoco": "check",
    "rigid_limit_error": "check",
    "simulate_mujoco": "simulate",
    "to_mjcf": "mjcf",
    "tree_error": "check",
}

__getattr__, __dir__ = lazy_exports(__name__, _LAZY)

__all__ = [
    "MjcfExport",
    "MujocoModel",
    "MujocoRun",
    "SolverSettings",
    "free_motion_drift",
    "load_mujoco",
    "rigid_limit_error",
    "simulate_mujoco",
    "to_mjcf",
    "tree_error",
]
