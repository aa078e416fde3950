"""The RCM (constant insertion point) mechanisms of papers 000 and 003: the family.

Bevel-gear and belt variants (six DOF, or four without the wrist pairs 26/27) and the
papers' two-mass dynamic model. Knowledge of the family, one module per idea:

* :mod:`.closed_form`: forward kinematics p = q3·e4, R = Rx(q1)·Ry(q2)·(wrist), with the
  papers' misprints (A_x1, e5) written down;
* :mod:`.analytic_ik`, :mod:`.ik_solutions`, :mod:`.ik_solve`, :mod:`.inverse`: every
  analytic inverse branch, vectorised, with degeneracy codes;
* :mod:`.velocity`: the differentiated position equations (second route);
* :mod:`.singularity`: named causes and paper 003's claims decided by rank;
* :mod:`.workspace`: analytic volume, the rig specification, sections;
* :mod:`.point`: the tool-centre point kinematics of the two-mass model and paper 000;
* :mod:`.two_mass`: Lagrange and d'Alembert forms of the two-mass model.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from rcm_pin.analysis.accuracy import AccuracyModel, AccuracyReport
from rcm_pin.analysis.capabilities import Branches, NumericPosition, ReferencePoses
from rcm_pin.analysis.singularity_model import Cause, NumericSingularity
from rcm_pin.analysis.workspace import WorkspaceModel
from rcm_pin.control.capabilities import (
    FrameJacobianTask,
    ScenarioSource,
    StopEvent,
    TaskKinematics,
)
from rcm_pin.interfaces.design import DesignMetric, MetricSource
from rcm_pin.lazy import lazy_modules
from rcm_pin.model.family import Branch, Family
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.output import Output

#: Design (xacro) parameters that enter the kinematics, per transmission.
BEVEL_PARAMS = ("l9", "a7_x", "a7_z", "z13", "z14", "z16", "z17", "z18", "z19", "z21", "z22")
BELT_PARAMS = ("l9", "a7_x", "a7_z", "d1", "d2", "d3", "d4")
#: Joints whose placement errors the accuracy analysis perturbs (the chain to the tool).
PLACEMENT_JOINTS = ("pair4", "pair7", "pair10", "pair12", "pair24")


class RcmPosition(NumericPosition):
    """Closed-form position problems of the family (the numeric route where none applies)."""

    def inverse(self, mech: Mechanism, target: np.ndarray, output: Output) -> Branches:
        """Analytic IK: every branch of a tool pose (4-/6-DOF) or a tool position."""
        from rcm_pin.mechanisms.rcm.inverse import solve_ik, solve_ik_position

        if output.coords == ("x", "y", "z"):
            res = solve_ik_position(mech, target)
            full = np.zeros((len(res.q), mech.nq))
            full[:, :3] = res.q
            return Branches.of(mech, [Branch(q, f"branch_{b}") for b, q in enumerate(full)])
        if output.coords == ("x", "y", "z", "rotation") and mech.nq in (4, 6):
            T = np.empty((3, 4))
            T[:, 3], T[:, :3] = target[:3], target[3:].reshape(3, 3)
            return Branches.of(
                mech, [Branch(q, f"branch_{b}") for b, q in enumerate(solve_ik(mech, T).q)]
            )
        return super().inverse(mech, target, output)


class RcmPoses(ReferencePoses):
    """Singularity maps around ``mid`` (off the zyz wrist), accuracy at ``regular``."""

    def regular(self, mech: Mechanism) -> np.ndarray:
        return mech.configurations["mid"]

    def accuracy(self, mech: Mechanism) -> np.ndarray:
        return mech.configurations["regular"]


class RcmTask(FrameJacobianTask):
    """The tool centre p = q3·e4(q1, q2) by the closed form (:mod:`.point`); Pinocchio's
    frame Jacobian for any other task."""

    def kinematics(self, mech: Mechanism, task: Output) -> TaskKinematics:
        if task.coords != ("x", "y", "z") or mech.nq < 3 or task.frame != mech.output.frame:
            return super().kinematics(mech, task)
        from rcm_pin.mechanisms.rcm import point

        return TaskKinematics(
            np.arange(3),
            point.point_position,
            point.point_jacobian,
            point.point_bias,
            point.point_ik,
            point.point_kinematics,
            closed_form=True,
        )


class RcmScenarios(ScenarioSource):
    """Paper 000's sinusoid and a rig circle; stop on leaving the regular region."""

    def scenarios(self, mech: Mechanism) -> dict[str, Any]:
        """Paper 000's sinusoid (Kn = 720, Kc = 12) and a circle inside the rig's workspace."""
        from rcm_pin.control.computed_torque import Gains
        from rcm_pin.control.references import TRAJECTORIES
        from rcm_pin.control.scenario import Scenario

        gains = Gains(720.0, 12.0)
        return {
            "paper000": Scenario(
                TRAJECTORIES["paper000"], gains, 2.0, "paper 000 Fig. 4 (needs --arg q3_upper=0.3)"
            ),
            "rig_circle": Scenario(
                TRAJECTORIES["rig_circle"], gains, 2.0, "20 mm circle at z = 0.09 m, 1 Hz"
            ),
        }

    def stop_events(self, mech: Mechanism) -> tuple[StopEvent, ...]:
        """The tool centre near A (q3 < 1 mm) or the axis near the base axis (cos q2 < 0.01)."""
        if mech.nq < 3:
            return ()
        return (
            StopEvent("q3 < 1 mm", lambda t, q, v: float(q[2] - 1e-3)),
            StopEvent("cos q2 < 0.01", lambda t, q, v: float(np.cos(q[1]) - 1e-2)),
        )


class RcmWorkspace(WorkspaceModel):
    """Volume by three routes, the rig specification, the boundary faces (:mod:`.workspace`)."""

    def summary(
        self, mech: Mechanism, samples: int | None, seed: int, **options: Any
    ) -> dict[str, Any]:
        from rcm_pin.mechanisms.rcm.workspace import summary

        return summary(mech, 200_000 if samples is None else samples, seed)

    def plot(self, mech: Mechanism, path: Path, samples: int, seed: int, **options: Any) -> Path:
        """Sections like paper 000 Fig. 7 with the rig specification overlaid."""
        from rcm_pin.mechanisms.rcm.workspace import plot_sections

        return plot_sections(mech, path, samples, seed)


class RcmMetrics(MetricSource):
    """Rig coverage, conditioning and RCM drift of a design (:mod:`.design`)."""

    def metrics(self) -> dict[str, DesignMetric]:
        from rcm_pin.mechanisms.rcm.design import METRICS

        return dict(METRICS)


class RcmSingularity(NumericSingularity):
    """Named causes: tool centre at A, output axis along the base axis, wrist axes aligned."""

    def causes(self, mech: Mechanism, q: np.ndarray) -> tuple[Cause, ...]:
        from rcm_pin.mechanisms.rcm.singularity import classify

        return tuple(classify(mech, q))


class RcmAccuracy(AccuracyModel):
    """Design parameters and part placements vs tool position and RCM offset."""

    def parameters(self, mech: Mechanism) -> tuple[str, ...]:
        """The kinematic xacro arguments of the variant (bevel: tooth counts; belt: pulleys)."""
        if mech.rebuild is None:
            return ()
        if mech.model_full.existJointName("shaft15"):
            return BEVEL_PARAMS
        if any(n.startswith("pulley") for n in mech.model_full.names):
            return BELT_PARAMS
        return ()

    def report(self, mech: Mechanism, q: np.ndarray) -> AccuracyReport:
        """The first-order table of :func:`.accuracy.report`."""
        from rcm_pin.mechanisms.rcm.accuracy import report, row

        return AccuracyReport.of(report(mech, q), row)


class RcmFamily(Family):
    """Hooks of the RCM mechanisms (module docstring)."""

    name = "rcm"
    description = "RCM mechanisms with bevel-gear or belt transmissions (papers 000/003)"
    capabilities = (
        RcmPosition(),
        RcmPoses(),
        RcmTask(),
        RcmScenarios(),
        RcmWorkspace(),
        RcmMetrics(),
        RcmSingularity(),
        RcmAccuracy(),
    )

    def configurations(self, mech: Mechanism) -> dict[str, np.ndarray]:
        """``home`` (zeros clipped to the limits), ``mid`` (the middle of the joint box,
        q5 = 0.5 off the zyz wrist singularity) and ``regular`` (``mid`` with q1 at half and
        q2 at 80 % of their upper limits, where the ratio errors act)."""
        home = np.clip(np.zeros(mech.nq), mech.lower, mech.upper)
        mid = 0.5 * (mech.lower + mech.upper)
        if mech.nq == 6:
            mid[4] = 0.5  # away from the zyz wrist singularity sin q5 = 0
        regular = mid.copy()
        regular[0], regular[1] = 0.5 * mech.upper[0], 0.8 * mech.upper[1]
        return {"home": home, "mid": mid, "regular": regular}


FAMILY = RcmFamily()

__all__ = [
    "BELT_PARAMS",
    "BEVEL_PARAMS",
    "FAMILY",
    "PLACEMENT_JOINTS",
    "RcmFamily",
]

# Each module of the family is an attribute of the package, imported on first access
# (``from rcm_pin.mechanisms import <family>`` is the public entry, docs/api.md).
__getattr__, __dir__ = lazy_modules(
    __name__,
    (
        "accuracy",
        "analytic_ik",
        "closed_form",
        "design",
        "ik_scalar",
        "ik_solutions",
        "ik_solve",
        "ik_tables",
        "inverse",
        "point",
        "singularity",
        "two_mass",
        "velocity",
        "workspace",
    ),
)
