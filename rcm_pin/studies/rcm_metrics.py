"""Figures of merit of the surgical task (:mod:`rcm_pin.studies.rcm_comparison`), per run.

Every number is recomputed from the returned joint trajectory q(t_k) (Mechanism
coordinates, step h = t_1 − t_0):

* RCM error: distance of p_T from the shaft line, by Pinocchio FK of the full model
  (max, RMS) [m]; tip error |p_tip − p_ref| (max, RMS) [m];
* joint velocity q̇ = Δq / h, its peak (max over joints and samples) [rad/s or m/s], and
  the largest step-to-step change of q̇ [rad/s] (a stair-step detector: a continuous
  velocity changes by O(h) per step);
* joint torque peak by RNEA with gravity, q̈ and q̇ by central differences [N·m or N];
* jerk: RMS over joints and samples of the third difference Δ³q / h³ [rad/s³];
* manipulability sqrt(det(J Jᵀ)) and condition number of the tip Jacobian under the RCM
  constraint (:func:`rcm_pin.control.rcm_task.manipulability`) over the path samples and
  over a grid of the cone (3 depths × (axis + 8 directions at θ/2 + 8 at θ)): min and max
  over the grid points reached, and the count of points not reached (−1: not computed);
* time per control step (QP or analytic IK): median and 95th percentile [s].

Units of the Jacobian are mixed for a prismatic joint (m/m beside m/rad); the figures are
a comparison of trends, not of absolute values across kinds of joints.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from rcm_pin.analysis.position import inverse
from rcm_pin.control.rcm_loop import position
from rcm_pin.control.rcm_task import RcmTool, line_distance, manipulability, rcm_state
from rcm_pin.control.rcm_task import update_kinematics as update
from rcm_pin.dynamics.tree import inverse_dynamics
from rcm_pin.errors import RcmPinError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.studies.rcm_comparison import RcmSetup, RcmTrack, controller


def fk_shaft(mech: Mechanism, tool: RcmTool, q: np.ndarray) -> tuple[np.ndarray, ...]:
    """(p_s, a, p_tip) of every row of ``q`` (Mechanism coordinates) by Pinocchio FK."""
    data = mech.model.createData()
    out = np.empty((3, len(q), 3))
    for k, qk in enumerate(np.atleast_2d(q)):
        pin.framesForwardKinematics(mech.model, data, mech.to_pin(qk))
        Ms, Mt = data.oMf[tool.axis_frame], data.oMf[tool.tip_frame]
        a = Ms.rotation[:, tool.axis]
        out[:, k] = Ms.translation, a, Mt.translation + tool.tip_offset * a
    return out[0], out[1], out[2]


def state_at(s: RcmSetup, q: np.ndarray) -> Any:
    """:class:`~rcm_pin.control.rcm_task.RcmState` at Mechanism coordinates ``q``."""
    data = s.mech.model.createData()
    update(s.mech.model, data, s.mech.to_pin(q))
    return rcm_state(s.mech.model, data, s.tool)


@dataclass(frozen=True)
class RcmMetrics:
    """The figures of one run (module docstring; SI units)."""

    name: str
    path: str
    rcm: str
    samples: int
    rcm_max: float
    rcm_rms: float
    tip_max: float
    tip_rms: float
    velocity_peak: float
    velocity_jump: float
    torque_peak: float
    jerk_rms: float
    manipulability_min: float
    condition_max: float
    cone_manipulability_min: float
    cone_condition_max: float
    cone_unreached: int
    step_median: float
    step_p95: float

    def to_json(self) -> dict[str, Any]:
        """Plain dict."""
        return asdict(self)


def errors(track: RcmTrack) -> tuple[np.ndarray, np.ndarray]:
    """(RCM distance, tip error) of every sample by Pinocchio FK [m]."""
    s = track.setup
    p_s, a, tip = fk_shaft(s.mech, s.tool, track.q)
    return line_distance(p_s, a, np.asarray(s.tool.trocar)), np.linalg.norm(
        tip - track.p_ref, axis=1
    )


def torque_peak(track: RcmTrack) -> float:
    """max |τ| over joints and interior samples, RNEA with gravity [N·m or N]."""
    q, h = track.q, float(track.t[1] - track.t[0])
    v = (q[2:] - q[:-2]) / (2 * h)
    acc = (q[2:] - 2 * q[1:-1] + q[:-2]) / h**2
    mech = track.setup.mech
    return float(max(np.abs(inverse_dynamics(mech, qk, vk, ak)).max()
                     for qk, vk, ak in zip(q[1:-1], v, acc)))  # fmt: skip


def cone_grid(s: RcmSetup) -> np.ndarray:
    """Tip points of the cone grid (module docstring), world [m]."""
    lo, hi = s.cone.depth
    pts = []
    for rho in (lo + 0.1 * (hi - lo), 0.5 * (lo + hi), hi - 0.1 * (hi - lo)):
        pts.append([0.0, 0.0, rho])
        for theta in (0.5 * s.cone.half_angle, s.cone.half_angle):
            r, z = rho * np.sin(theta), rho * np.cos(theta)
            pts.extend([r * np.cos(phi), r * np.sin(phi), z] for phi in np.arange(8) * np.pi / 4)
    return s.cone.to_world(np.asarray(pts))


def _reach(s: RcmSetup, ctrl: Any, q: np.ndarray, p: np.ndarray) -> np.ndarray | None:
    """A configuration with the tip at ``p`` and the RCM met, or None."""
    if ctrl is None:
        try:
            sols = inverse(s.mech, p, ("x", "y", "z"), limits=True).solutions
        except RcmPinError:
            return None
        return min((x.q for x in sols), key=lambda x: float(np.linalg.norm(x - s.home)))
    for start in (q, s.home[s.chain.active]):  # type: ignore[union-attr]
        try:  # continuation from the previous point, then from home
            return position(ctrl, start, p, max_steps=1500)  # type: ignore[no-any-return]
        except RcmPinError:
            continue
    return None


def cone_manipulability(s: RcmSetup) -> tuple[float, float, int]:
    """(min manipulability, max condition number) over the points of :func:`cone_grid`
    the manipulator reaches with the RCM met (arms: positioned from the previous point,
    else from home), and the number of points it does not reach."""
    values, missed = [], 0
    q = s.home if s.chain is None else s.home[s.chain.active]
    ctrl = None if s.chain is None else controller(s, 1e-3)
    for p in cone_grid(s):
        reached = _reach(s, ctrl, q, p)
        if reached is None:
            missed += 1
            continue
        q = reached
        values.append(manipulability(state_at(s, q) if ctrl is None else ctrl.state(q)))
    return min(v[0] for v in values), max(v[1] for v in values), missed


def metrics(track: RcmTrack, *, cone: bool = True) -> RcmMetrics:
    """Every figure of one run (``cone=False`` skips the cone grid: NaN)."""
    s, q = track.setup, track.q
    h = float(track.t[1] - track.t[0])
    rcm, tip = errors(track)
    v = np.diff(q, axis=0) / h
    jerk = np.diff(q, n=3, axis=0) / h**3
    along = [manipulability(state_at(s, qk)) for qk in q[:: max(1, len(q) // 50)]]
    cm = cone_manipulability(s) if cone else (float("nan"), float("nan"), -1)
    return RcmMetrics(
        s.mech.name, track.path, "mechanical" if s.mechanical else "programmable", len(q),
        float(rcm.max()), float(np.sqrt(np.mean(rcm**2))), float(tip.max()),
        float(np.sqrt(np.mean(tip**2))), float(np.abs(v).max()),
        float(np.abs(np.diff(v, axis=0)).max()), torque_peak(track),
        float(np.sqrt(np.mean(jerk**2))) if len(jerk) else 0.0,
        min(a[0] for a in along), max(a[1] for a in along), cm[0], cm[1], cm[2],
        float(np.median(track.step_time)), float(np.percentile(track.step_time, 95)),
    )  # fmt: skip


COLUMNS = (
    ("RCM err max [m]", "rcm_max", ".1e"),
    ("RCM err RMS [m]", "rcm_rms", ".1e"),
    ("tip err max [m]", "tip_max", ".1e"),
    ("q̇ peak", "velocity_peak", ".3g"),
    ("Δq̇ per step max", "velocity_jump", ".1e"),
    ("τ peak", "torque_peak", ".3g"),
    ("jerk RMS", "jerk_rms", ".3g"),
    ("manip. min (path)", "manipulability_min", ".2e"),
    ("cond. max (path)", "condition_max", ".3g"),
    ("manip. min (cone)", "cone_manipulability_min", ".2e"),
    ("cond. max (cone)", "cone_condition_max", ".3g"),
    ("cone points unreached", "cone_unreached", "d"),
    ("step median [ms]", "step_median", "ms"),
)


def table(rows: list[RcmMetrics]) -> str:
    """Markdown table, one row per run."""
    head = "| manipulator | path | RCM | " + " | ".join(c[0] for c in COLUMNS) + " |"
    out = [head, "|" + " --- |" * (3 + len(COLUMNS))]
    for r in rows:
        cells = []
        for _, key, spec in COLUMNS:
            x = getattr(r, key)
            cells.append(f"{1e3 * x:.3f}" if spec == "ms" else format(x, spec))
        out.append(f"| {r.name} | {r.path} | {r.rcm} | " + " | ".join(cells) + " |")
    return "\n".join(out)


__all__ = [
    "COLUMNS",
    "RcmMetrics",
    "cone_grid",
    "cone_manipulability",
    "errors",
    "fk_shaft",
    "metrics",
    "state_at",
    "table",
    "torque_peak",
]
