"""Closed-loop mechanisms on Pinocchio (issue 7, paper 004).

A closed mechanism is a URDF tree cut open at one pair per loop plus a closure list in a
LAAS-format YAML sidecar (:mod:`.sidecar`), turned into ``pin.RigidConstraintModel`` s
(:mod:`.core`, :mod:`.loader`). Solvers: position problems (:mod:`.position`), batched
Newton (:mod:`.batch`), velocities and singularities (:mod:`.velocity`, :mod:`.screws`),
dynamics and computed torque (:mod:`.dynamics`), closed forms of paper 004
(:mod:`.planar_3rrr`, :mod:`.five_bar`), workspace and plots (:mod:`.workspace`), the
five-bar drive-switching study (:mod:`.switching`) and the report section (:mod:`.report`).
"""

from rcm_pin.closed_loop.core import ClosedMechanism, Closure
from rcm_pin.closed_loop.loader import (
    CLOSED_MECHANISMS,
    check_rendered,
    from_urdf_and_sidecar,
    load_closed,
    write_rendered,
)
from rcm_pin.closed_loop.position import (
    PositionResult,
    PositionSolution,
    direct_position,
    direct_position_multistart,
    direct_position_path,
    inverse_position,
)
from rcm_pin.closed_loop.report import report_section

__all__ = [
    "CLOSED_MECHANISMS",
    "ClosedMechanism",
    "Closure",
    "PositionResult",
    "PositionSolution",
    "check_rendered",
    "direct_position",
    "direct_position_multistart",
    "direct_position_path",
    "from_urdf_and_sidecar",
    "inverse_position",
    "load_closed",
    "report_section",
    "write_rendered",
]
