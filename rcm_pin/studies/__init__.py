"""Worked studies: the generic tools combined on named mechanisms, one module per study.

A study may load mechanisms by name: paper 004's five-bar drive switching, vibrations and
control, the 3-RRR platform tracking, the surgical task with a mechanical or programmable
RCM, paper 002's eye linkage (its printed numbers, its pitch four-bar on Pinocchio).

The public names are the study modules (``docs/api.md``), each one idea, imported on first
access: ``from rcm_pin.studies import five_bar_switching`` then
``five_bar_switching.simulate(...)``. Their functions keep the study's own short names
(``beats.run``, ``control_3dof.run``), which is why they are not re-exported here.
"""

from __future__ import annotations

from rcm_pin.lazy import lazy_modules

__all__ = [
    "beats",
    "comparison",
    "control_3dof",
    "eye_paper",
    "five_bar_switching",
    "four_bar_turn",
    "planar_tracking",
    "rcm_comparison",
    "rcm_metrics",
    "rig_design",
    "surgical_paths",
    "vibration_criterion",
    "working_mode",
]

__getattr__, __dir__ = lazy_modules(__name__, __all__)
