"""The report's sections, in report order, listed once by explicit import.

A missing section is an import error, never a silent skip.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from rcm_pin.report.analysis import section as analysis
from rcm_pin.report.casadi import section as casadi
from rcm_pin.report.closed_loops import section as closed_loops
from rcm_pin.report.dynamics import section as dynamics
from rcm_pin.report.framework import Section
from rcm_pin.report.position import section as position
from rcm_pin.report.scenes import section as scenes
from rcm_pin.report.velocity import section as velocity

#: (name used by ``--only``, section function) in report order.
SECTIONS: tuple[tuple[str, Callable[[Path], Section]], ...] = (
    ("rcm_pin.report.position", position),
    ("rcm_pin.report.velocity", velocity),
    ("rcm_pin.report.analysis", analysis),
    ("rcm_pin.report.dynamics", dynamics),
    ("rcm_pin.report.casadi (ocp)", casadi),
    ("rcm_pin.report.closed_loops", closed_loops),
    ("rcm_pin.report.scenes", scenes),
)

__all__ = ["SECTIONS"]
