"""The same surgical task for a mechanical RCM and for arms with a programmable RCM.

A mechanism with an RCM in its URDF (``mech.rcm``) keeps its shaft through the remote
centre by construction: its trocar is that point, the insertion direction is its shaft
axis at ``home``, its shaft is the RCM axis frame's axis and its tip the tool frame's
origin; each tip sample is solved by the family's analytic inverse (:func:`rcm_pin.inverse`
on the tool position, the branch nearest the previous sample), or, for a family without
one (a user's file), by least squares from the previous sample. An arm without one gets a
shaft of length :data:`TOOL_LENGTH` along the z axis of its tool frame, the insertion
direction straight down, and follows the path with the RCM QP of
:mod:`rcm_pin.control.rcm_qp` at the control rate.

**Choice of the arm's trocar** (:func:`choose_trocar`): candidates on a 3 × 3 grid around
the shaft of the arm's ``home`` posture (depths 0.10, 0.15, 0.20 m along the shaft from
the tool frame, horizontal offsets of −0.1, 0, +0.1 m away from the base); a candidate is
*reachable* when the arm, from ``home``, reaches every checkpoint of the three paths in
turn with the shaft through it, inside its joint limits (:func:`rcm_pin.control.rcm_qp.position`);
among the reachable ones the one with the largest smallest manipulability
``sqrt(det(J Jᵀ))`` of the tip Jacobian under the RCM constraint over the checkpoints
wins (ties: the first in grid order).
"""

from __future__ import annotations

import functools
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from rcm_pin.analysis.capabilities import PositionSolver
from rcm_pin.analysis.position import inverse
from rcm_pin.analysis.reach import reach_bound
from rcm_pin.analysis.serial_ik import solve_near
from rcm_pin.catalog import load
from rcm_pin.control.rcm_loop import position, track
from rcm_pin.control.rcm_qp import ChainModel, RcmQP, chain_model
from rcm_pin.control.rcm_task import RcmTool, make_tool, manipulability, trocar_point
from rcm_pin.control.rcm_task import update_kinematics as update
from rcm_pin.errors import InvalidInputError, UnreachablePoseError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.studies.surgical_paths import PATHS, Cone, surgical_path

#: Shaft of the arms' instrument beyond their tool frame [m].
TOOL_LENGTH = 0.3
#: The manipulators compared: the mechanical RCM and the two arms.
COMPARED = ("rcm_bevel", "panda", "ur5")
#: Sampling rate of the paths' checkpoints in the trocar choice [Hz] (one per second).
CHECKPOINT_RATE = 1.0


@dataclass(frozen=True)
class RcmSetup:
    """One manipulator ready for the surgical task.

    Attributes:
        mech: the mechanism.
        tool: the shaft, tip and trocar on ``mech.model``.
        cone: the cone of tip paths below the trocar.
        mechanical: whether the RCM is mechanical (analytic IK) or programmable (QP).
        chain: the arm's tool chain (None for a mechanical RCM).
        home: Mechanism coordinates the run starts from.
    """

    mech: Mechanism
    tool: RcmTool
    cone: Cone
    mechanical: bool
    chain: ChainModel | None
    home: np.ndarray

    @property
    def tool_frame(self) -> str:
        """Name of the shaft's frame."""
        return str(self.mech.model.frames[self.tool.axis_frame].name)


@dataclass(frozen=True)
class RcmTrack:
    """A run of the surgical task (Mechanism coordinates).

    Attributes:
        t: (N + 1,) [s]; q: (N + 1, nq); p_ref: (N + 1, 3) [m]; step_time: (N,) [s],
        the wall time of each control step (QP or analytic IK).
    """

    setup: RcmSetup
    path: str
    t: np.ndarray
    q: np.ndarray
    p_ref: np.ndarray
    step_time: np.ndarray


def reach(mech: Mechanism, frame_id: int, extra: float) -> float:
    """Upper bound of the distance from the base the shaft can reach [m]: the reach bound
    of the frame (:func:`rcm_pin.analysis.reach.reach_bound`) plus ``extra``."""
    return reach_bound(mech, str(mech.model.frames[frame_id].name), extra)


def _arm(
    mech: Mechanism, trocar: tuple[float, float, float], frame: str | None = None, axis: str = "z"
) -> RcmSetup:
    home = np.asarray(mech.home, dtype=float)
    frame = str(mech.model.frames[mech.tool_frame_id].name) if frame is None else frame
    chain = chain_model(mech, frame, axis, TOOL_LENGTH, trocar, home)  # checks frame, axis
    fid = mech.model.getFrameId(frame)
    bound = reach(mech, fid, TOOL_LENGTH)
    if np.linalg.norm(trocar) > bound:
        raise UnreachablePoseError(
            f"{mech.name}: trocar {list(trocar)} is {np.linalg.norm(trocar):.3f} m from the "
            f"base, beyond the arm's reach with its tool ({bound:.3f} m); valid: a trocar "
            f"within {bound:.3f} m of the base"
        )
    full = RcmTool(fid, chain.tool.axis, fid, TOOL_LENGTH, trocar, frame)
    return RcmSetup(mech, full, Cone(trocar, (0.0, 0.0, -1.0)), False, chain, home)


def _mechanical(mech: Mechanism, trocar: Any) -> RcmSetup:
    assert mech.rcm is not None
    home = np.asarray(mech.home, dtype=float)
    update(mech.model, mech.data, mech.to_pin(home))
    apex = tuple(float(x) for x in mech.data.oMf[mech.rcm.point_frame_id].translation)
    if trocar is not None and not np.allclose(trocar_point(trocar), apex, rtol=0, atol=1e-12):
        raise InvalidInputError(
            f"{mech.name} has a mechanical RCM at {list(apex)}; its trocar cannot move; "
            "valid: omit the trocar or give that point"
        )
    d = mech.data.oMf[mech.rcm.axis_frame_id].rotation[:, mech.rcm.axis]
    name = str(mech.model.frames[mech.rcm.axis_frame_id].name)
    tool = RcmTool(mech.rcm.axis_frame_id, mech.rcm.axis, mech.tool_frame_id, 0.0, apex, name)  # type: ignore[arg-type]
    return RcmSetup(mech, tool, Cone(apex, tuple(d)), True, None, home)  # type: ignore[arg-type]


def make_setup(
    name_or_mech: str | Mechanism, trocar: Any = None, *, frame: str | None = None,
    axis: str = "z",
) -> RcmSetup:  # fmt: skip
    """The task set-up of a catalogue name or Mechanism (module docstring); an arm's
    shaft is the ``axis`` of ``frame`` (default: its tool frame's z axis).

    Raises:
        UnknownFrameError: an arm without ``frame`` (the message lists its frames).
        UnreachablePoseError: an arm's trocar beyond its reach.
        InvalidInputError: a trocar other than a mechanical RCM's own point, or a
            mechanism that is neither a serial arm nor an RCM mechanism.
    """
    mech = load(name_or_mech) if isinstance(name_or_mech, str) else name_or_mech
    if mech.rcm is not None:
        if frame is not None or axis != "z":
            raise InvalidInputError(
                f"{mech.name} has a mechanical RCM: its shaft is fixed by the mechanism; "
                "valid: omit the tool frame and axis (load with rcm_axis_frame= / rcm_axis=)"
            )
        return _mechanical(mech, trocar)
    if trocar is None:
        tool = str(mech.model.frames[mech.tool_frame_id].name)
        if frame is not None or axis != "z":
            make_tool(mech.model, frame or tool, axis)  # UnknownFrameError for a missing frame
            if (frame or tool, axis) != (tool, "z"):
                raise InvalidInputError(
                    "the trocar is chosen for the tool frame's z axis only; valid: give "
                    "the trocar with another frame or axis"
                )
        return choose_trocar(name_or_mech)[0]
    return _arm(mech, trocar_point(trocar), frame, axis)


def checkpoints(cone: Cone) -> np.ndarray:
    """Tip checkpoints of the trocar choice: every path sampled at :data:`CHECKPOINT_RATE`."""
    pts = [surgical_path(p, cone, rate=CHECKPOINT_RATE).p for p in PATHS]
    return np.vstack(pts)


def controller(s: RcmSetup, dt: float, **options: Any) -> RcmQP:
    """The arm's RCM QP at step ``dt`` [s], its posture pull towards ``home``."""
    assert s.chain is not None
    return RcmQP(s.chain.model, s.chain.tool, dt, posture=s.home[s.chain.active], **options)


def start_configuration(s: RcmSetup, p0: np.ndarray) -> np.ndarray:
    """Chain configuration with the tip at ``p0`` and the RCM met (positioned from home)."""
    assert s.chain is not None
    ctrl = controller(s, 1e-3)
    return position(ctrl, s.home[s.chain.active], p0, settle=True)


def score(s: RcmSetup) -> float:
    """Smallest RCM-constrained manipulability over the checkpoints [m^3] (raises
    UnreachablePoseError when a checkpoint is out of reach)."""
    assert s.chain is not None
    ctrl = controller(s, 1e-3)
    q = s.home[s.chain.active]
    worst = np.inf
    for p in checkpoints(s.cone):
        q = position(ctrl, q, p, max_steps=1500)
        worst = min(worst, manipulability(ctrl.state(q))[0])
    return float(worst)


Scored = tuple[RcmSetup, tuple[tuple[tuple[float, ...], float], ...]]


def choose_trocar(name_or_mech: str | Mechanism) -> Scored:
    """The arm's set-up at the best trocar, and every candidate with its score (−1:
    unreachable) (module docstring); a Mechanism is used as loaded (a file's never looked
    up by name), a name is loaded once and cached."""
    if isinstance(name_or_mech, str):
        return _choose_named(name_or_mech)
    return _choose(name_or_mech)


@functools.lru_cache(maxsize=8)
def _choose_named(name: str) -> Scored:
    return _choose(load(name))


def _choose(mech: Mechanism) -> Scored:
    home = np.asarray(mech.home, dtype=float)
    update(mech.model, mech.data, mech.to_pin(home))
    M = mech.data.oMf[mech.tool_frame_id]
    a, p_s = M.rotation[:, 2], M.translation
    radial = np.array([p_s[0], p_s[1], 0.0]) / max(np.hypot(p_s[0], p_s[1]), 1e-9)
    scored, best = [], None
    for depth in (0.10, 0.15, 0.20):
        for off in (-0.1, 0.0, 0.1):
            cand = tuple(float(x) for x in p_s + depth * a + off * radial)
            try:
                setup = _arm(mech, cand)  # type: ignore[arg-type]
                value = score(setup)
            except UnreachablePoseError:
                scored.append((cand, -1.0))
                continue
            scored.append((cand, value))
            if best is None or value > best[1]:
                best = (setup, value)
    if best is None:
        raise UnreachablePoseError(
            f"{mech.name}: no trocar candidate around the home posture is reachable for the "
            "surgical paths; valid: pass a trocar explicitly"
        )
    return best[0], tuple(scored)


def run(s: RcmSetup, path: str, *, rate: float = 1000.0, duration: float | None = None,
        method: str = "qp") -> RcmTrack:  # fmt: skip
    """Follow ``path`` at ``rate`` [Hz] (``method``: ``qp`` or ``pink`` for arms).

    Raises:
        InvalidInputError: bad path, rate, duration or method.
        UnreachablePoseError: the path start cannot be reached with the RCM met.
    """
    if method not in ("qp", "pink"):
        raise InvalidInputError(f"method must be qp or pink; got {method!r}")
    sp = surgical_path(path, s.cone, rate=rate, duration=duration)
    if s.mechanical:
        return _run_mechanical(s, sp.t, sp.p, path)
    assert s.chain is not None
    ctrl = controller(s, 1.0 / rate)
    q0 = start_configuration(s, sp.p[0])
    out = track(ctrl, q0, sp.p, method=method)  # type: ignore[arg-type]
    return RcmTrack(s, path, sp.t, s.chain.to_mechanism(out.q), sp.p, out.step_time)


def _run_mechanical(s: RcmSetup, t: np.ndarray, p: np.ndarray, path: str) -> RcmTrack:
    mech = s.mech
    qs, times = np.empty((len(p), mech.nq)), np.empty(len(p) - 1)
    prev, closed_form = s.home, mech.family.capability(PositionSolver) is not None  # type: ignore[type-abstract]
    for k, target in enumerate(p):
        start = time.perf_counter()
        if not closed_form:  # numeric: continuation from the previous sample
            q = solve_near(mech, target, mech.output.subset(("x", "y", "z")), prev)
        else:
            sols = inverse(mech, target, ("x", "y", "z"), limits=True).solutions
            q = min((sol.q for sol in sols), key=lambda x: float(np.linalg.norm(x - prev)))
        if k:
            times[k - 1] = time.perf_counter() - start
        qs[k] = prev = q
    return RcmTrack(s, path, t, qs, p, times)


__all__ = [
    "CHECKPOINT_RATE",
    "COMPARED",
    "TOOL_LENGTH",
    "RcmSetup",
    "RcmTrack",
    "checkpoints",
    "choose_trocar",
    "controller",
    "make_setup",
    "reach",
    "run",
    "score",
    "start_configuration",
]
