"""The report's sections, in report order, listed once by module.

A section is the function ``section(out_dir) -> Section`` of its module. The modules are
imported when a section runs (:func:`section_function`), so that a rerun whose sections all
come from the cache imports none of them; a missing module is an import error when it
runs, never a silent skip (tests import every one).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from pathlib import Path

from rcm_pin.report.framework import Section

#: (name used by ``--only``, module of the section function) in report order.
SECTIONS: tuple[tuple[str, str], ...] = (
    ("rcm_pin.report.position", "rcm_pin.report.position"),
    ("rcm_pin.report.velocity", "rcm_pin.report.velocity"),
    ("rcm_pin.report.analysis", "rcm_pin.report.analysis"),
    ("rcm_pin.report.dynamics", "rcm_pin.report.dynamics"),
    ("rcm_pin.report.casadi (ocp)", "rcm_pin.report.casadi"),
    ("rcm_pin.report.closed_loops", "rcm_pin.report.closed_loops"),
    ("rcm_pin.report.spherical", "rcm_pin.report.spherical"),
    ("rcm_pin.report.translational", "rcm_pin.report.translational"),
    ("rcm_pin.report.scenes", "rcm_pin.report.scenes"),
    ("rcm_pin.report.eye_linkage", "rcm_pin.report.eye_linkage"),
    ("rcm_pin.report.programmable_rcm", "rcm_pin.report.programmable_rcm"),
    ("rcm_pin.report.design", "rcm_pin.report.design"),
    ("rcm_pin.report.vibrations", "rcm_pin.report.vibrations"),
    ("rcm_pin.report.control_3dof", "rcm_pin.report.control_3dof"),
    ("rcm_pin.report.mujoco", "rcm_pin.report.mujoco"),
)


def section_function(module: str) -> Callable[[Path], Section]:
    """The ``section`` function of a section module (imported now)."""
    fn: Callable[[Path], Section] = importlib.import_module(module).section
    return fn


__all__ = ["SECTIONS", "section_function"]
