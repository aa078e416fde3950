"""The central object: a Pinocchio model with mimic joints, its coupling and frames.

``q`` everywhere in the public API is the *Mechanism coordinate vector*: the papers'
q1..qn in their numbering (``Mechanism.coordinate_names``), mapped to Pinocchio's q by
``Mechanism.q_index``. Mimic (transmission) joints carry no coordinate; the no-mimic
parse of the same URDF has every joint and is reached through the coupling

    q_full = G·q_pin + offset,   v_full = G·v_pin,

read from the URDF's ``<mimic>`` tags independently of Pinocchio's own mimic support.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np
import pinocchio as pin

from rcm_pin.catalog import MechanismSpec, get_spec
from rcm_pin.closed_form import WristType
from rcm_pin.errors import InvalidInputError, UnknownFrameError, XacroArgumentError
from rcm_pin.render import render_xacro, validate_args


@dataclass(frozen=True)
class Coupling:
    """Affine map from independent Pinocchio coordinates to every URDF joint.

    Attributes:
        G: (nq_full, nq) matrix; column j holds the multipliers of the joints that
            follow independent coordinate j (1 for the coordinate's own joint).
        Gv: (nv_full, nv) the same map on velocities (equals G unless the model has
            continuous joints, whose q has two entries and v one).
        offset: (nq_full,) mimic offsets.
        full_names: joint names of the no-mimic model in its q order.
    """

    G: np.ndarray
    Gv: np.ndarray
    offset: np.ndarray
    full_names: tuple[str, ...]

    def q_full(self, q_pin: np.ndarray) -> np.ndarray:
        """Configuration of the no-mimic model: G·q + offset."""
        return np.asarray(q_pin) @ self.G.T + self.offset

    def v_full(self, v_pin: np.ndarray) -> np.ndarray:
        """Velocity (or acceleration) of the no-mimic model: G·v."""
        return np.asarray(v_pin) @ self.Gv.T


@dataclass(frozen=True, eq=False)
class Mechanism:
    """A loaded mechanism.

    Attributes:
        name: catalogue name or URDF file stem.
        urdf: the URDF text it was built from.
        args: the xacro arguments used (empty for a plain URDF).
        model: Pinocchio model parsed with ``mimic=True``.
        data: its data (mutable scratch space; a Mechanism is not thread-safe).
        model_full: the same URDF parsed without mimic (every joint independent).
        coupling: q_full = G·q_pin + offset.
        coordinate_names: ``("q1", ..., "qn")``.
        joint_names: URDF joint of each coordinate.
        q_index: Pinocchio q index of each coordinate.
        tool_frame_id: Pinocchio frame id of the tool centre.
        rcm_frame_id: frame id of the remote centre (-1 when none).
        lower: lower joint limits in coordinate order [rad or m].
        upper: upper joint limits in coordinate order [rad or m].
        spec: the catalogue entry (None for a plain URDF).
    """

    name: str
    urdf: str
    args: dict[str, str]
    model: pin.Model
    data: pin.Data
    model_full: pin.Model
    coupling: Coupling
    coordinate_names: tuple[str, ...]
    joint_names: tuple[str, ...]
    q_index: np.ndarray
    tool_frame_id: int
    rcm_frame_id: int
    lower: np.ndarray
    upper: np.ndarray
    spec: MechanismSpec | None = None

    @property
    def nq(self) -> int:
        """Number of independent coordinates."""
        return len(self.coordinate_names)

    @property
    def wrist_type(self) -> WristType:
        """``"zyz"`` or ``"rpy"`` for six-DOF RCM mechanisms, None without a wrist."""
        if self.nq < 6 or self.spec is None or not self.spec.rcm_frame:
            return None
        return "rpy" if self.args.get("wrist_type", "zyz") == "rpy" else "zyz"

    def to_pin(self, q: np.ndarray) -> np.ndarray:
        """Mechanism coordinates -> Pinocchio q (works on (..., n) arrays)."""
        q = np.asarray(q, dtype=float)
        out = np.empty(q.shape[:-1] + (self.model.nq,))
        out[..., self.q_index] = q
        return out

    def from_pin(self, q_pin: np.ndarray) -> np.ndarray:
        """Pinocchio q -> Mechanism coordinates."""
        return np.asarray(q_pin, dtype=float)[..., self.q_index]

    def q_pin(self, q: np.ndarray) -> np.ndarray:
        """Validated Pinocchio configuration of one coordinate vector (the hot path).

        A float64 array of the right shape is checked for NaN with one dot product and
        passed through without a copy when Pinocchio's order is the papers' order.

        Raises:
            InvalidInputError: wrong shape or NaN / infinite entries.
        """
        if not (type(q) is np.ndarray and q.shape == (self.nq,) and q.dtype == np.float64):
            q = self.check_q(q)
        elif not math.isfinite(q.dot(q)):
            q = self.check_q(q)  # raises with the full message
        if self.identity_order:
            return q
        return self.to_pin(q)

    @cached_property
    def identity_order(self) -> bool:
        """Whether Pinocchio's q order equals the Mechanism coordinate order."""
        return bool(self.model.nq == self.nq and np.array_equal(self.q_index, np.arange(self.nq)))

    def check_q(self, q: np.ndarray, name: str = "q") -> np.ndarray:
        """Validate a coordinate vector: shape (n,) and finite.

        Raises:
            InvalidInputError: wrong length or NaN / infinite entries.
        """
        arr = np.asarray(q, dtype=float)
        if arr.shape != (self.nq,):
            raise InvalidInputError(
                f"{name} has shape {arr.shape}; valid: ({self.nq},) for "
                f"{self.name} coordinates {', '.join(self.coordinate_names)}"
            )
        if not np.all(np.isfinite(arr)):
            raise InvalidInputError(f"{name} has NaN or infinite entries: {arr}")
        return arr

    def frame_id(self, frame: str) -> int:
        """Pinocchio id of a frame by name.

        Raises:
            UnknownFrameError: the message lists the model's frames.
        """
        if not self.model.existFrame(frame):
            names = sorted({f.name for f in self.model.frames})
            raise UnknownFrameError(
                f"unknown frame {frame!r} in {self.name}; valid: {', '.join(names)}"
            )
        return int(self.model.getFrameId(frame))


def load(name_or_path: str | Path, **xacro_args: object) -> Mechanism:
    """Load a shipped mechanism by name, or any URDF / xacro file by path.

    Args:
        name_or_path: a name from :func:`rcm_pin.mechanisms` (``rcm_bevel``,
            ``rcm_bevel_4dof``, ``rcm_belt``, ...) or a ``.urdf`` / ``.xacro`` path.
        **xacro_args: xacro arguments (validated against the file's declarations).

    Returns:
        The :class:`Mechanism` (closed-loop catalogue entries return their own type).

    Raises:
        UnknownMechanismError: unknown name (lists the valid ones).
        XacroArgumentError: unknown or malformed xacro argument.
    """
    path = Path(name_or_path)
    if path.suffix in {".urdf", ".xacro"} or path.exists():
        if path.suffix == ".xacro":
            urdf = render_xacro(path, xacro_args)
        else:
            if xacro_args:
                raise XacroArgumentError(f"xacro arguments given for plain URDF {path}")
            urdf = path.read_text()
        return from_urdf(urdf, name=path.name.split(".")[0], args=xacro_args)
    spec = get_spec(str(name_or_path))
    if spec.kind == "closed":
        from rcm_pin.closed_loop import load_closed

        # Closed-loop catalogue entries have their own type (rcm_pin.closed_loop).
        return load_closed(spec.name, **xacro_args)  # type: ignore[no-any-return,return-value]
    for key in spec.fixed_args:
        if key in xacro_args:
            raise XacroArgumentError(
                f"xacro argument {key!r} is fixed by mechanism {spec.name} "
                f"({key}={spec.fixed_args[key]}); load {spec.xacro} variants by path instead"
            )
    args: dict[str, object] = dict(
        validate_args(spec.xacro_path, {**spec.fixed_args, **xacro_args})
    )
    _check_positive(spec, args)
    urdf = render_xacro(spec.xacro_path, args)
    return from_urdf(urdf, name=spec.name, args=args, spec=spec)


def _check_positive(spec: MechanismSpec, args: dict[str, object]) -> None:
    for key in spec.positive_args:
        if key in args and float(str(args[key])) <= 0.0:
            raise XacroArgumentError(
                f"xacro argument {key}={args[key]} must be > 0 for {spec.name}; "
                f"valid: a positive number"
            )


def from_urdf(
    urdf: str,
    name: str = "urdf",
    args: dict[str, object] | None = None,
    spec: MechanismSpec | None = None,
) -> Mechanism:
    """Build a :class:`Mechanism` from URDF text (see :func:`load`)."""
    model = pin.buildModelFromXML(urdf, mimic=True)
    model_full = pin.buildModelFromXML(urdf)
    coupling = coupling_from_urdf(urdf, model, model_full)
    joint_names = spec.coordinates if spec and spec.coordinates else _independent(model)
    missing = [j for j in joint_names if not model.existJointName(j)]
    if missing:
        raise UnknownFrameError(
            f"joints {missing} not in the URDF of {name}; valid: {', '.join(model.names[1:])}"
        )
    q_index = np.array([model.joints[model.getJointId(j)].idx_q for j in joint_names])
    tool = spec.tool_frame if spec else model.frames[-1].name
    rcm = spec.rcm_frame if spec else ""
    mech = Mechanism(
        name=name,
        urdf=urdf,
        args={k: str(v) for k, v in (args or {}).items()},
        model=model,
        data=model.createData(),
        model_full=model_full,
        coupling=coupling,
        coordinate_names=tuple(f"q{i + 1}" for i in range(len(joint_names))),
        joint_names=tuple(joint_names),
        q_index=q_index,
        tool_frame_id=int(model.getFrameId(tool)) if model.existFrame(tool) else -1,
        rcm_frame_id=int(model.getFrameId(rcm)) if rcm and model.existFrame(rcm) else -1,
        lower=model.lowerPositionLimit[q_index].copy(),
        upper=model.upperPositionLimit[q_index].copy(),
        spec=spec,
    )
    if mech.tool_frame_id < 0:
        mech.frame_id(tool)  # raises UnknownFrameError with the valid names
    return mech


def _independent(model: pin.Model) -> list[str]:
    return [model.names[i] for i in range(1, model.njoints) if model.joints[i].nq > 0]


def coupling_from_urdf(urdf: str, model: pin.Model, model_full: pin.Model) -> Coupling:
    """Read ``<mimic>`` tags and build the coupling q_full = G·q_pin + offset.

    Only one-DOF joints (revolute, prismatic) may mimic or be mimicked, as in URDF.
    """
    root = ET.fromstring(urdf)
    mimic: dict[str, tuple[str, float, float]] = {}
    for joint in root.iter("joint"):
        tag = joint.find("mimic")
        if tag is not None:
            mimic[joint.attrib["name"]] = (
                tag.attrib["joint"],
                float(tag.attrib.get("multiplier", 1.0)),
                float(tag.attrib.get("offset", 0.0)),
            )
    G = np.zeros((model_full.nq, model.nq))
    Gv = np.zeros((model_full.nv, model.nv))
    offset = np.zeros(model_full.nq)
    for jid in range(1, model_full.njoints):
        jname = model_full.names[jid]
        jf = model_full.joints[jid]
        if jname in mimic:
            primary, multiplier, off = mimic[jname]
            jp = model.joints[model.getJointId(primary)]
            G[jf.idx_q, jp.idx_q] = multiplier
            Gv[jf.idx_v, jp.idx_v] = multiplier
            offset[jf.idx_q] = off
        else:
            jm = model.joints[model.getJointId(jname)]
            for k in range(jm.nq):
                G[jf.idx_q + k, jm.idx_q + k] = 1.0
            for k in range(jm.nv):
                Gv[jf.idx_v + k, jm.idx_v + k] = 1.0
    full_names = tuple(
        model_full.names[j] for j in range(1, model_full.njoints) if model_full.joints[j].nq
    )
    return Coupling(G=G, Gv=Gv, offset=offset, full_names=full_names)
