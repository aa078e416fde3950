"""Registers the closed-loop mechanisms in the rcm-pin catalogue (``rcm-pin list``)."""

from __future__ import annotations

from rcm_pin.catalog import MechanismSpec, register

register(
    MechanismSpec(
        name="planar_3rrr",
        xacro="planar_3rrr.urdf.xacro",
        description="planar 3-RRR parallel mechanism, base pairs driven, 3 DOF (paper 004)",
        kind="closed",
        tool_frame="platform",
    )
)
register(
    MechanismSpec(
        name="five_bar",
        xacro="five_bar.urdf.xacro",
        description="planar five-bar RR-RR, 2 DOF, main + 2 extra drives (paper 004 Fig. 13)",
        kind="closed",
        tool_frame="P",
    )
)
