"""Simulation scenarios: a reference with the gains, start and solver settings it needs.

A family lists its scenarios (its :class:`~rcm_pin.control.capabilities.ScenarioSource`:
paper 000's tool-centre sinusoid, the 3-RRR's platform circle, the five-bar's path across
its type-2 curve); any mechanism also has :func:`home_circle`, a small circle of its task about the
home configuration. :func:`run` starts at the reference's start (serial: the task's
inverse; closed: the working mode ``mode`` of the inverse problem at x_T(0) + ``offset``,
with ẋ_T(0)) and calls the one :func:`rcm_pin.control.simulate.simulate`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from rcm_pin.control.capabilities import scenario_source
from rcm_pin.control.computed_torque import ComputedTorque, DriveSwitching, Gains, drive_limits
from rcm_pin.control.references import CartesianTrajectory, Reference
from rcm_pin.control.result import SimulationResult
from rcm_pin.control.simulate import simulate
from rcm_pin.control.simulation_options import SimulationOptions
from rcm_pin.control.task import task_output
from rcm_pin.errors import InvalidInputError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.newton import constraint_rank
from rcm_pin.model.output_choice import require_output


@dataclass(frozen=True)
class Scenario:
    """Everything a simulation run needs besides the mechanism (SI units)."""

    reference: Reference
    gains: Gains
    duration: float
    description: str = ""
    mode: str | int = 0  # closed: working mode of the start configuration
    offset: tuple[float, ...] = ()  # initial task error
    switching: float | None = None  # closed: drive-switching band (None: main drives)
    limit: float | None = None  # one effort limit for every drive; None: the URDF limits
    use_limits: bool = True
    method: str = "DOP853"
    rtol: float = 1e-10
    atol: float = 1e-12
    max_step: float = np.inf
    samples: int | None = 1001

    def simulation_options(
        self, mech: Mechanism, *, allow_outside_limits: bool = False, backend: str = "python"
    ) -> SimulationOptions:
        """The options of a run of this scenario on ``mech``: its samples, tolerances,
        method and largest step; the task-error stop (0.5 [m, rad]) on serial plants only.

        Raises:
            InvalidInputError: an unknown backend.
        """
        return SimulationOptions(
            samples=self.samples,
            rtol=self.rtol,
            atol=self.atol,
            method=self.method,
            max_step=self.max_step,
            stop_error=0.5 if mech.loops is None else None,
            allow_outside_limits=allow_outside_limits,
            backend=backend,
        )


def home_circle(mech: Mechanism) -> Scenario:
    """A circle of radius L/10 in the first two task coordinates about the home pose, 1 Hz,
    from the home's working mode.

    Raises:
        UnknownFrameError: a closed mechanism without an output (no task to track).
    """
    from rcm_pin.analysis.position import forward

    require_output(mech, "a simulation (its task)")
    home = mech.home
    task = task_output(mech, None)
    inputs = home if mech.loops is None else home[mech.loops.drive_q]
    sol = forward(mech, inputs, q_guess=None if mech.loops is None else home).solutions[0]
    value = task.value(_placement(mech, sol.q))
    radius = 0.1 * (mech.loops.length_scale if mech.loops is not None else 0.1)
    amplitude = np.zeros(len(value))
    amplitude[: min(2, len(value))] = radius
    phase = np.zeros(len(value))
    phase[min(1, len(value) - 1)] = np.pi / 2
    centre = value - amplitude * np.sin(phase)
    ref = CartesianTrajectory(
        "home_circle",
        tuple(float(v) for v in centre),
        tuple(float(v) for v in amplitude),
        2 * np.pi,
        tuple(float(v) for v in phase),
    )
    return Scenario(
        ref,
        Gains.from_tau_zeta(0.05, 1.0),
        2.0,
        f"circle of radius {radius:.3g} (task units: m, rad) about the home pose, 1 Hz",
        mode=_home_mode(mech, value, sol.q),
    )


def _home_mode(mech: Mechanism, value: np.ndarray, q_home: np.ndarray) -> int:
    """Closed: the index of the working mode of ``value`` that is the home configuration
    (the circle starts on the home's branch), 0 for serial mechanisms."""
    if mech.loops is None or mech.family.configurations(mech):
        return 0  # a family's own scenarios and named poses choose their modes
    from rcm_pin.analysis.closed_position import difference
    from rcm_pin.analysis.position import inverse

    sols = inverse(mech, value).solutions
    gaps = [float(np.max(np.abs(difference(mech, s.q, q_home)))) for s in sols]
    return int(np.argmin(gaps)) if min(gaps) < 1e-6 else 0


def _placement(mech: Mechanism, q: np.ndarray) -> Any:
    import pinocchio as pin

    pin.forwardKinematics(mech.model, mech.data, mech.q_pin(q))
    return pin.updateFramePlacement(mech.model, mech.data, mech.output.frame_id)


def scenarios(mech: Mechanism) -> dict[str, Scenario]:
    """The family's scenarios, then ``home_circle``."""
    out = dict(scenario_source(mech).scenarios(mech))
    out.setdefault("home_circle", home_circle(mech))
    return out


def controller(
    mech: Mechanism,
    sc: Scenario,
    *,
    space: str = "task",
    feedforward: bool = True,
    printed_sign: bool = False,
) -> ComputedTorque:
    """The computed-torque controller of a scenario."""
    limits: Any = (
        sc.limit if sc.limit is not None else (drive_limits(mech) if sc.use_limits else None)
    )
    switching = DriveSwitching(sc.switching) if sc.switching is not None else None
    return ComputedTorque(
        mech,
        sc.reference,
        sc.gains,
        space=space,
        feedforward=feedforward,
        printed_sign=printed_sign,
        limits=limits,
        switching=switching,
    )


def start_state(mech: Mechanism, sc: Scenario) -> tuple[np.ndarray | None, np.ndarray | None]:
    """(q0, v0): None for serial (the simulation starts at the task inverse)."""
    if mech.loops is None:
        return None, None
    from rcm_pin.analysis.position import inverse
    from rcm_pin.dynamics.constrained import velocity_for_output

    x0, xd0, _ = sc.reference.evaluate(0.0)
    offset = np.zeros(len(x0)) if not sc.offset else np.asarray(sc.offset, dtype=float)
    sols = inverse(mech, np.asarray(x0) + offset).solutions
    labels = [s.mode for s in sols]
    idx = labels.index(sc.mode) if sc.mode in labels else sc.mode
    if not isinstance(idx, int) or not 0 <= idx < len(sols):
        raise InvalidInputError(
            f"working mode {sc.mode!r} of {mech.name}; valid: {', '.join(labels)} or 0.."
            f"{len(sols) - 1}"
        )
    q0 = sols[idx].q
    mobility = mech.nv - constraint_rank(mech.residual_and_jacobian(mech.q_pin(q0))[1])
    if mobility != mech.loops.dof:
        raise InvalidInputError(
            f"{mech.name}: mobility nv − rank J_c = {mobility} at the start but "
            f"{mech.loops.dof} drives; valid: a mechanism whose drives fix every joint "
            "(computed torque cannot hold a self-motion, e.g. two coaxial revolute joints "
            "closed by a 6d closure: close them with a 3d closure or one joint)"
        )
    return q0, velocity_for_output(mech, q0, np.asarray(xd0, dtype=float))


def run(
    mech: Mechanism,
    sc: Scenario,
    *,
    allow_outside_limits: bool = False,
    backend: str = "python",
    **law: Any,
) -> SimulationResult:
    """Simulate a scenario (module docstring); ``law`` goes to :func:`controller`,
    ``backend`` to :func:`~rcm_pin.control.simulate.simulate`.

    Raises:
        JointLimitError: the run leaves the joint range of ``mech`` (its xacro arguments
            set it), unless ``allow_outside_limits`` (then the result records it).
    """
    q0, v0 = start_state(mech, sc)
    ctrl = controller(mech, sc, **law)
    options = sc.simulation_options(
        mech, allow_outside_limits=allow_outside_limits, backend=backend
    )
    return simulate(mech, ctrl, sc.duration, q0, v0, options)


__all__ = ["Scenario", "controller", "home_circle", "run", "scenarios", "start_state"]
