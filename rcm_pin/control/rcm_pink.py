"""The RCM task and the tool-tip task as pink tasks (pin-pink's ``Task`` interface).

pink solves one QP per control step on the configuration displacement Δq,

    min_Δq  Σ_tasks ½ |J Δq + α e|²_W + ½ μ |Δq|²
    s.t.    J_c Δq = −α_c e_c      (tasks passed as ``constraints``)
            joint position and velocity limits (pink's ``ConfigurationLimit``,
            ``VelocityLimit``),

through qpsolvers (here with daqp). :class:`RcmTask` is the point-to-line distance
formulation of :mod:`rcm_pin.control.rcm_task` (two rows, full rank, so it can be a hard
equality); :class:`ToolTipTask` asks the tip to be at a world point (three rows).
pink, mink and placo ship no RCM task; this is the one missing piece.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from rcm_pin.control.rcm_task import RcmState, RcmTool, rcm_state
from rcm_pin.errors import require

if TYPE_CHECKING:
    import pink
    from pink.tasks import Task
else:  # the [arms] extra (MissingExtraError without it)
    pink = require("arms", "pink")
    Task = require("arms", "pink.tasks").Task


class _ToolTaskBase(Task):  # type: ignore[misc]
    """Shared cache: one :func:`rcm_state` per configuration update."""

    def __init__(self, tool: RcmTool, cost: float = 1.0, gain: float = 1.0) -> None:
        super().__init__(cost=cost, gain=gain, lm_damping=0.0)
        self.tool = tool
        self._key: tuple[int, bytes] | None = None
        self._state: RcmState | None = None

    def state(self, configuration: pink.Configuration) -> RcmState:
        """The RCM geometry of ``configuration`` (cached on its q)."""
        key = (id(configuration), configuration.q.tobytes())
        if self._key != key or self._state is None:
            self._state = rcm_state(configuration.model, configuration.data, self.tool)
            self._key = key
        return self._state


class RcmTask(_ToolTaskBase):
    """Keep the tool axis through the trocar: e = (b_1ᵀ(p_T − p_s), b_2ᵀ(p_T − p_s)) [m]."""

    def compute_error(self, configuration: pink.Configuration) -> np.ndarray:
        """e (2,) [m]."""
        return self.state(configuration).e

    def compute_jacobian(self, configuration: pink.Configuration) -> np.ndarray:
        """∂e/∂q (2, nv)."""
        return self.state(configuration).J_dist

    def __repr__(self) -> str:
        return f"RcmTask(trocar={self.tool.trocar}, axis={self.tool.axis_name})"


class ToolTipTask(_ToolTaskBase):
    """Put the tool tip at ``target`` (3,) [m]: e = p_tip − target."""

    def __init__(self, tool: RcmTool, cost: float = 1.0, gain: float = 1.0) -> None:
        super().__init__(tool, cost, gain)
        self.target = np.zeros(3)

    def set_target(self, target: Any) -> None:
        """The tip target [m] (world)."""
        self.target = np.asarray(target, dtype=float).reshape(3)

    def compute_error(self, configuration: pink.Configuration) -> np.ndarray:
        """p_tip − target (3,) [m]."""
        return np.asarray(self.state(configuration).p_tip - self.target, dtype=float)

    def compute_jacobian(self, configuration: pink.Configuration) -> np.ndarray:
        """J_tip (3, nv)."""
        return self.state(configuration).J_tip

    def __repr__(self) -> str:
        return f"ToolTipTask(target={self.target.tolist()})"


__all__ = ["RcmTask", "ToolTipTask"]
