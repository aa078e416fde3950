"""What a mechanism family may know beyond its URDF: the hooks generic code asks for.

Generic algorithms (``rcm_pin.analysis``, ``dynamics``, ``control``, ``viz``) never test a
mechanism's name. They ask the mechanism's :class:`Family` for a hook; a hook that returns
``None`` means "this family has no closed form here", and the generic numeric route runs.
Each family module in ``rcm_pin.mechanisms`` subclasses :class:`Family` and overrides the
hooks its papers give (workspace summaries, stop conditions of simulations, ...) and lists
its implementations of the capabilities the consuming layers define (``capabilities``:
analytic position problems, the paper's A and B matrices, named singularity causes, ...).

The base class is also the family of a URDF loaded by path that names no family.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np

if TYPE_CHECKING:
    from rcm_pin.model.mechanism import Mechanism
    from rcm_pin.model.metric import DesignMetric
    from rcm_pin.model.output import Output


T = TypeVar("T")


@dataclass(frozen=True)
class Branch:
    """One closed-form solution of a position problem.

    Attributes:
        q: Mechanism coordinates (n,) [rad, m] (for closed mechanisms a seed that the
            generic code polishes on Pinocchio's closures).
        label: branch / working-mode label (e.g. ``"+-+"``, ``"branch 3"``).
    """

    q: np.ndarray
    label: str


#: A simulation stop condition: (description, g(t, q, v)); the run stops where g crosses 0.
StopEvent = tuple[str, Callable[[float, np.ndarray, np.ndarray], float]]


@dataclass(frozen=True)
class TaskKinematics:
    """Closed-form kinematics of a task (output coordinates) over some coordinates.

    Attributes:
        joints: coordinate indices the task depends on (the others do not move it).
        position: q (n,) -> task value (dim,).
        jacobian: q -> ∂x/∂q_joints (dim, len(joints)).
        bias: (q, q̇) -> J̇ q̇ (dim,).
        inverse: task value -> q_joints of the principal branch (None: not available).
        batch: (q (N, n), q̇ (N, nv)) -> (x (N, dim), J (N, dim, len(joints)), J̇ q̇
            (N, dim)) vectorised over states, the same values as the three one-state
            functions (None: they are called per state).
    """

    joints: np.ndarray
    position: Callable[[np.ndarray], np.ndarray]
    jacobian: Callable[[np.ndarray], np.ndarray]
    bias: Callable[[np.ndarray, np.ndarray], np.ndarray]
    inverse: Callable[[np.ndarray], np.ndarray] | None = None
    batch: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]] | None = (
        None
    )


class Family:
    """Base family: no closed forms, every hook answers ``None`` (numeric routes)."""

    name = "generic"
    description = "any URDF: numeric routes only"
    #: Whether the family's mechanisms have loop closures.
    closed = False
    #: Options of ``rcm-pin workspace`` its workspace uses (``samples``, ``n``, ``phi``,
    #: ``phi_range``); the others are refused, never ignored. The numeric route samples.
    workspace_options: tuple[str, ...] = ("samples",)

    #: The family's implementations of capabilities the consuming layers define (e.g.
    #: ``rcm_pin.analysis.capabilities.PositionSolver``); each layer's resolver takes the
    #: one here or its numeric default. ``model`` knows none of their types.
    capabilities: tuple[object, ...] = ()

    def capability(self, kind: type[T]) -> T | None:
        """The family's implementation of capability ``kind`` (None: the layer's default)."""
        return next((c for c in self.capabilities if isinstance(c, kind)), None)

    # ---------------------------------------------------------------- named poses
    def configurations(self, mech: Mechanism) -> dict[str, np.ndarray]:
        """Named configurations (Mechanism coordinates); ``home`` is the default pose."""
        return {}

    # ---------------------------------------------------------------- workspace
    def workspace_summary(self, mech: Mechanism, **options: Any) -> dict[str, Any] | None:
        """Closed-form workspace figures (volumes, areas, the rig specification)."""
        return None

    def plot_workspace(self, mech: Mechanism, path: Path, **options: Any) -> Path | None:
        """A PNG of the workspace drawn from the closed forms."""
        return None

    def mesh_dirs(self, mech: Mechanism) -> list[str]:
        """Folders that resolve the URDF's ``package://`` mesh paths (for the viewer)."""
        return []

    # ---------------------------------------------------------------- design
    def design_metrics(self) -> dict[str, DesignMetric]:
        """Figures of merit of a whole design, by name (:mod:`rcm_pin.design` sweeps them)."""
        return {}

    # ---------------------------------------------------------------- control
    def task_kinematics(self, mech: Mechanism, task: Output) -> TaskKinematics | None:
        """Closed-form kinematics of a control task (None: Pinocchio's frame Jacobian)."""
        return None

    def scenarios(self, mech: Mechanism) -> dict[str, Any]:
        """Named simulation scenarios (:class:`rcm_pin.control.scenario.Scenario`)."""
        return {}

    def stop_events(self, mech: Mechanism) -> list[StopEvent]:
        """Conditions that end a simulation (leaving the regular region)."""
        return []


__all__ = ["Branch", "Family", "StopEvent", "TaskKinematics"]
