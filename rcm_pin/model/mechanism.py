"""The central object: one :class:`Mechanism` for serial and closed mechanisms.

A Mechanism holds the Pinocchio model parsed with ``mimic=True``, the same URDF parsed
without mimic and the coupling between them (:mod:`rcm_pin.model.coupling`), the
*Mechanism coordinates* (the papers' q1..qn in their numbering, mapped to Pinocchio's q
by ``q_index``), the tool or output frame, the RCM point and axis where there is one,
the loop closures where there are some (:class:`rcm_pin.model.loops.Loops`), and the
family (:class:`rcm_pin.model.family.Family`) whose hooks the generic algorithms ask.

Serial mechanisms: the inputs are the coordinates; the output is the tool frame's pose.
Closed mechanisms: the coordinates are Pinocchio's q of the cut-open tree (every
independent joint, in Pinocchio order); the inputs are the drives; the output is the
output frame's coordinates of the sidecar.

Thread safety: the model is shared read-only; Pinocchio ``Data`` (scratch space of every
algorithm) is created per thread on first use (:attr:`Mechanism.data`), so one Mechanism
gives the same results from any number of threads.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError
from rcm_pin.model import configurations
from rcm_pin.model import joints as jt
from rcm_pin.model import loops as lp
from rcm_pin.model.coupling import Coupling
from rcm_pin.model.describe import describe
from rcm_pin.model.family import Family
from rcm_pin.model.output import Output
from rcm_pin.rotations import MAX_ABS, check_magnitude, numeric_array


def _plain_vector(q: Any, n: int) -> bool:
    """Whether ``q`` is a float64 (n,) array passing the checks of
    :meth:`Mechanism.check_q` at a glance: one ``math.hypot`` (it never overflows) fails on
    NaN, inf or a large entry, which then take the full checks and their messages."""
    return (
        type(q) is np.ndarray
        and q.dtype == np.float64
        and q.shape == (n,)
        and math.hypot(*q.tolist()) <= MAX_ABS
    )


@dataclass(frozen=True)
class RcmSpec:
    """The remote centre A and the axis that must pass through it.

    Attributes:
        point_frame_id: frame at A.
        axis_frame_id: frame whose ``axis`` (0, 1, 2 = x, y, z) is the insertion axis.
        axis: axis index in that frame.
    """

    point_frame_id: int
    axis_frame_id: int
    axis: int = 2


@dataclass(frozen=True, eq=False)
class Mechanism:
    """A loaded mechanism (module docstring).

    Attributes:
        name: catalogue name or URDF file stem.
        urdf: the URDF text it was built from.
        args: the xacro arguments used (empty for a plain URDF).
        model: Pinocchio model parsed with ``mimic=True``.
        model_full: the same URDF parsed without mimic (every joint independent).
        coupling: q_full = G·q_pin + offset.
        coordinate_names: ``("q1", ..., "qn")``.
        joint_names: URDF joint of each coordinate (``docs/joints.md``).
        q_index: Pinocchio q index of each coordinate (a continuous joint's cos entry).
        v_index: Pinocchio v index of each velocity coordinate.
        lower: lower limits in coordinate order [rad or m] (−inf: unbounded).
        upper: upper limits in coordinate order [rad or m] (inf: unbounded).
        revolute: (n,) bool, the coordinates that are angles [rad] (continuous included).
        output: the tool (serial) or output (closed) frame and its coordinates.
        family: the family whose hooks generic code calls.
        loops: closures and drives (None for a serial mechanism).
        rcm: the remote centre and its axis (None without one).
        rebuild: renders the same source with other xacro arguments (None for plain URDF).
        source: the xacro file it was rendered from (None for plain URDF).
        continuous: coordinates that are continuous joints' θ (cos θ, sin θ in Pinocchio q).
    """

    name: str
    urdf: str
    args: Mapping[str, str]
    model: pin.Model
    model_full: pin.Model
    coupling: Coupling
    coordinate_names: tuple[str, ...]
    joint_names: tuple[str, ...]
    q_index: np.ndarray
    v_index: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    revolute: np.ndarray
    output: Output
    family: Family = field(default_factory=Family)
    loops: lp.Loops | None = None
    rcm: RcmSpec | None = None
    rebuild: Callable[..., Mechanism] | None = field(default=None, repr=False)
    source: Path | None = None
    continuous: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    _local: threading.local = field(default_factory=threading.local, init=False, repr=False)

    __repr__ = describe  # one line: name, family, coordinates, frames, closures; no URDF

    @property
    def nq(self) -> int:
        """Number of coordinates."""
        return len(self.q_index)

    @property
    def nv(self) -> int:
        """Number of velocity coordinates (equals nq unless closed with continuous joints)."""
        return len(self.v_index)

    @property
    def is_closed(self) -> bool:
        """Whether the mechanism has loop closures."""
        return self.loops is not None

    @property
    def input_names(self) -> tuple[str, ...]:
        """What :func:`rcm_pin.forward` takes: the drives, or every coordinate."""
        return self.loops.drives if self.loops is not None else self.coordinate_names

    @property
    def tool_frame_id(self) -> int:
        """Frame id of the tool (serial) or output (closed) frame."""
        return self.output.frame_id

    @property
    def rcm_frame_id(self) -> int:
        """Frame id of the remote centre A (−1 when there is none)."""
        return -1 if self.rcm is None else self.rcm.point_frame_id

    @property
    def data(self) -> pin.Data:
        """Pinocchio data of the mimic model for the calling thread."""
        data = getattr(self._local, "data", None)
        if data is None:
            data = self._local.data = self.model.createData()
        return data

    @property
    def data_full(self) -> pin.Data:
        """Pinocchio data of the no-mimic model for the calling thread."""
        data = getattr(self._local, "data_full", None)
        if data is None:
            data = self._local.data_full = self.model_full.createData()
        return data

    @cached_property
    def identity_order(self) -> bool:
        """Whether Pinocchio's q is the coordinate vector itself."""
        return bool(self.model.nq == self.nq and np.array_equal(self.q_index, np.arange(self.nq)))

    @cached_property
    def _neutral(self) -> np.ndarray:
        return np.asarray(pin.neutral(self.model), dtype=float)

    def to_pin(self, q: np.ndarray) -> np.ndarray:
        """Coordinates -> Pinocchio q ((..., n) arrays; continuous θ -> cos θ, sin θ)."""
        return jt.to_pin(np.asarray(q, dtype=float), self._neutral, self.q_index, self.continuous)

    def from_pin(self, q_pin: np.ndarray) -> np.ndarray:
        """Pinocchio q -> Mechanism coordinates (continuous: atan2(sin, cos) [rad])."""
        return jt.from_pin(np.asarray(q_pin, dtype=float), self.q_index, self.continuous)

    def v_pin(self, v: np.ndarray) -> np.ndarray:
        """Velocity coordinates -> Pinocchio v (works on (..., nv) arrays)."""
        v = np.asarray(v, dtype=float)
        out = np.zeros(v.shape[:-1] + (self.model.nv,))
        out[..., self.v_index] = v
        return out

    def q_pin(self, q: np.ndarray) -> np.ndarray:
        """Validated Pinocchio configuration of one coordinate vector (the hot path).

        A float64 array of the right shape is checked for NaN and magnitude with one
        ``math.hypot`` and passed through without a copy when Pinocchio's order is the
        coordinate order.

        Raises:
            InvalidInputError: wrong shape or NaN / infinite entries.
        """
        if not _plain_vector(q, self.nq):
            q = self.check_q(q)  # raises with the full message, or accepts a long vector
        return q if self.identity_order else self.to_pin(q)

    def check_q(self, q: Any, name: str = "q", size: int | None = None) -> np.ndarray:
        """Validate a coordinate vector (or any vector of ``size``): shape, finiteness and
        magnitude (every entry within :data:`rcm_pin.rotations.MAX_ABS` [rad, m, rad/s, N·m]).

        Raises:
            InvalidInputError: not numeric (strings and complex numbers included), wrong
                length, NaN / infinite entries or an entry beyond ``MAX_ABS``.
        """
        n = self.nq if size is None else size
        if _plain_vector(q, n):  # the hot loops' own arrays (as in q_pin)
            return q.copy()
        arr = numeric_array(q, name)
        if arr.shape != (n,):
            what = ", ".join(self.coordinate_names) if size is None else f"{n} values"
            raise InvalidInputError(
                f"{name} has shape {arr.shape}; valid: ({n},) for {self.name} ({what})"
            )
        if not np.all(np.isfinite(arr)):
            raise InvalidInputError(f"{name} has NaN or infinite entries: {arr.tolist()}")
        return check_magnitude(arr, name)

    def check_v(self, v: Any, name: str = "v") -> np.ndarray:
        """Validate a velocity-coordinate vector (nv,)."""
        return self.check_q(v, name, self.nv)

    def frame_id(self, frame: str) -> int:
        """Pinocchio id of a frame by name.

        Raises:
            UnknownFrameError: the message lists the model's frames.
        """
        return lp.frame_index(self.model, frame)

    def joint_v(self, names: Sequence[str]) -> np.ndarray:
        """v indices of named one-DOF joints."""
        return np.array(
            [self.model.joints[lp.joint_index(self.model, n)].idx_v for n in names], dtype=int
        )

    @cached_property
    def _named(self) -> dict[str, np.ndarray]:
        return configurations.named_configurations(self)

    @property
    def configurations(self) -> dict[str, np.ndarray]:
        """Named configurations, ``home`` always there (:mod:`rcm_pin.model.configurations`)."""
        return {k: v.copy() for k, v in self._named.items()}

    @property
    def home(self) -> np.ndarray:
        """The default pose: the family's ``home``, else the one default (``configurations``)."""
        return self._named["home"].copy()

    def require_loops(self) -> lp.Loops:
        """The loop closures; InvalidInputError for a serial mechanism."""
        if self.loops is None:
            raise InvalidInputError(f"{self.name} has no loop closures; valid: a closed mechanism")
        return self.loops

    def closure_residual(self, q: np.ndarray) -> np.ndarray:
        """Kept closure rows e(q) [m, rad] at a full configuration (runs FK)."""
        return lp.closure_residual(self.model, self.data, self.require_loops(), q)

    def residual_and_jacobian(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Closure residual e (m,) and constraint Jacobian J_c (m, nv)."""
        return lp.residual_and_jacobian(self.model, self.data, self.require_loops(), q)

    def constraint_jacobian(self, q: np.ndarray) -> np.ndarray:
        """J_c (m, nv): J_c v = 0 along closed-loop motions."""
        return self.residual_and_jacobian(q)[1]

    def output_value(self, q: np.ndarray) -> np.ndarray:
        """Value of the output coordinates at Pinocchio configuration q (runs FK)."""
        pin.forwardKinematics(self.model, self.data, q)
        return self.output.value(
            pin.updateFramePlacement(self.model, self.data, self.output.frame_id)
        )

    def output_jacobian(self, q: np.ndarray) -> np.ndarray:
        """Tree Jacobian J_x (dim, nv) of the output coordinates (LOCAL_WORLD_ALIGNED)."""
        pin.computeJointJacobians(self.model, self.data, q)
        pin.updateFramePlacements(self.model, self.data)
        jac = pin.getFrameJacobian(self.model, self.data, self.output.frame_id, lp.LWA)
        return np.asarray(jac)[self.output.rows]

    def with_drives(self, drives: Sequence[str]) -> Mechanism:
        """A copy driven by other joints (e.g. the extra drives of the five-bar)."""
        return replace(self, loops=self.require_loops().with_drives(self.model, drives))

    def with_models(self, model: pin.Model, model_full: pin.Model) -> Mechanism:
        """A copy on modified Pinocchio models of the same structure (e.g. gravity)."""
        return replace(self, model=model, model_full=model_full)


__all__ = ["Mechanism", "RcmSpec"]
