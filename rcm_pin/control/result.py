"""The result of :func:`rcm_pin.control.simulate.simulate`: one type for every mechanism."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import pinocchio as pin

from rcm_pin.model.mechanism import Mechanism

if TYPE_CHECKING:
    from rcm_pin.control.computed_torque import ComputedTorque, Gains
    from rcm_pin.control.hot_path import SampledEfforts


@dataclass(frozen=True, eq=False)
class SimulationResult:
    """A simulated run.

    Attributes:
        mechanism: plant name.
        t: times (N,) [s].
        q: coordinates (N, n) [rad, m].
        v: velocities (N, nv) [rad/s, m/s].
        tau: generalised efforts applied (N, nv) [N·m, N] (drives' columns non-zero).
        saturated: whether a drive limit clipped τ at each sample (N,).
        x: task value (N, dim) [m, rad] (tool position, or the loop output).
        x_ref: desired task value (N, dim) (NaN without a controller).
        xd: task rate (N, dim).
        xd_ref: desired task rate (N, dim).
        alternate: whether the extra drives were active (N,) (drive switching).
        measure: type-2 measure of the main drives (N,) (NaN without switching).
        closure_residual: max |e(q)| of the closures (N,) [m] (0 for serial plants).
        status: ``"completed"`` or the stop condition that ended the run.
        gains: controller gains (None for a free run).
        wall_time: integration wall time [s].
        nfev: right-hand-side evaluations.
        outside_limits: joints outside their range in a run with
            ``allow_outside_limits`` (joint, side, first time [s], limit, farthest value
            [rad, m]); empty otherwise.
    """

    mechanism: str
    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    tau: np.ndarray
    saturated: np.ndarray
    x: np.ndarray
    x_ref: np.ndarray
    xd: np.ndarray
    xd_ref: np.ndarray
    alternate: np.ndarray
    measure: np.ndarray
    closure_residual: np.ndarray
    status: str
    gains: Gains | None
    wall_time: float
    nfev: int
    outside_limits: tuple[dict[str, Any], ...] = ()

    @property
    def error(self) -> np.ndarray:
        """Tracking error e = x_ref − x (N, dim)."""
        return self.x_ref - self.x

    @property
    def error_rate(self) -> np.ndarray:
        """ė = ẋ_ref − ẋ (N, dim)."""
        return self.xd_ref - self.xd

    @property
    def completed(self) -> bool:
        """Whether the run reached its duration."""
        return self.status == "completed"

    def steady_error(self, t_from: float) -> np.ndarray:
        """max |e| per coordinate over t ≥ t_from (dim,)."""
        mask = self.t >= t_from
        if not mask.any():
            return np.full(self.x.shape[1], np.nan)
        return np.asarray(np.max(np.abs(self.error[mask]), axis=0))

    def rms_error(self) -> float:
        """RMS of |e| over the run."""
        return float(np.sqrt(np.mean(np.sum(self.error**2, axis=1))))

    def summary(self, t_steady: float | None = None) -> dict[str, Any]:
        """JSON-ready summary (status, errors, peak efforts, run statistics)."""
        t_steady = self.t[-1] / 2 if t_steady is None else t_steady
        return {
            "mechanism": self.mechanism,
            "status": self.status,
            "duration": float(self.t[-1]),
            "gains": None if self.gains is None else {"Kn": self.gains.kn, "Kc": self.gains.kc},
            "rms_error": self.rms_error(),
            "steady_error": self.steady_error(t_steady).tolist(),
            "steady_from": float(t_steady),
            "peak_effort": np.max(np.abs(self.tau), axis=0).tolist(),
            "saturated_fraction": float(np.mean(self.saturated)),
            "max_closure_residual": float(np.max(self.closure_residual)),
            "wall_time": self.wall_time,
            "nfev": self.nfev,
            "outside_limits": list(self.outside_limits),
        }

    # -------------------------------------------------------------- construction
    @staticmethod
    def task_value(plant: Mechanism, controller: ComputedTorque, q: np.ndarray) -> np.ndarray:
        """The task value of the plant at q."""
        kin = controller.kinematics
        if kin is not None:
            return kin.position(q)
        task, model, data = controller.task_output, plant.model, plant.data
        pin.forwardKinematics(model, data, q)
        return task.value(pin.updateFramePlacement(model, data, task.frame_id))

    @classmethod
    def build(
        cls,
        plant: Mechanism,
        controller: ComputedTorque | None,
        t: np.ndarray,
        q: np.ndarray,
        v: np.ndarray,
        status: str,
        wall: float,
        nfev: int,
        at_samples: SampledEfforts,
    ) -> SimulationResult:
        """The result from the efforts and task state at every sample (``at_samples``, see
        :mod:`rcm_pin.control.hot_path`), the references and the closure residuals."""
        N = len(t)
        res = np.zeros(N)
        if plant.loops is not None:
            for i in range(N):
                res[i] = np.max(np.abs(plant.closure_residual(q[i])))
        dim = 0 if controller is None else controller.task_output.dim
        if controller is None:
            x_ref = xd_ref = np.full((N, dim), np.nan)
        else:
            x_ref, xd_ref = _sample(controller, t)
        s = at_samples
        return cls(
            plant.name,
            t,
            q,
            v,
            s.tau,
            s.saturated,
            s.x,
            x_ref,
            s.xd,
            xd_ref,
            s.alternate,
            s.measure,
            res,
            status,
            None if controller is None else controller.gains,
            wall,
            nfev,
        )


def _sample(controller: ComputedTorque, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Reference values and rates at the sample times (vectorised where the reference is)."""
    ref = controller.reference
    position = getattr(ref, "position", None)
    velocity = getattr(ref, "velocity", None)
    if callable(position) and callable(velocity):
        return np.asarray(position(t)), np.asarray(velocity(t))
    rows = [ref.evaluate(float(ti)) for ti in t]
    return np.array([r[0] for r in rows]), np.array([r[1] for r in rows])


__all__ = ["SimulationResult"]
