"""One ``simulate`` for serial and closed mechanisms (scipy ``solve_ivp``).

The plant integrates the state y = (q, q̇):

* serial: q̈ = M(q)⁻¹ (τ − b(q, q̇)) by Cholesky (``pin.aba`` refuses mimic joints, see
  :mod:`rcm_pin.dynamics.tree`);
* closed: the KKT system of :mod:`rcm_pin.dynamics.constrained` with Baumgarte
  stabilisation of the closures.

The right-hand side and the efforts at the output samples run the prepared, unvalidated
routes of :mod:`rcm_pin.control.hot_path` (serial) and
:mod:`rcm_pin.control.closed_hot_path` (closed): the same formulas, checked against the
public functions in tests; the inputs are validated once, here. ``backend="compiled"``
runs the right-hand side as one compiled CasADi function instead, serial or closed
(:mod:`rcm_pin.control.backends`: the same to rounding, the trajectory to the tolerances).

Efforts come from a :class:`~rcm_pin.control.computed_torque.ComputedTorque` (whose model
may differ from the plant) or are zero. The run stops at the family's stop conditions
(:meth:`~rcm_pin.control.capabilities.ScenarioSource.stop_events`: leaving the regular
region; serial and closed plants alike), when the task error exceeds ``stop_error`` and
at any further ``events`` (terminal); these and the other run options are one
:class:`~rcm_pin.control.simulation_options.SimulationOptions`. Output: every ``samples``
uniform times, or the solver's own steps with ``samples=None``.

Joint range: a run that starts or gets outside the plant's joint limits (``plant.lower``,
``plant.upper``, 1e-9 slack) stops with a :class:`~rcm_pin.errors.JointLimitError` (CLI
exit status 2) naming the time [s], the joint and the limit it passes. With
``allow_outside_limits=True`` (CLI ``--allow-outside-limits``) it continues and the
result records every excursion (``SimulationResult.outside_limits``).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from rcm_pin.control.backends import compiled_rhs
from rcm_pin.control.capabilities import EventFunction, StopCondition, scenario_source
from rcm_pin.control.closed_backend import samples_of
from rcm_pin.control.closed_hot_path import ClosedPlant
from rcm_pin.control.computed_torque import ComputedTorque
from rcm_pin.control.hot_path import SerialPlant, free_samples
from rcm_pin.control.result import SimulationResult
from rcm_pin.control.simulation_options import SimulationOptions
from rcm_pin.dynamics.inertia import require_inertia
from rcm_pin.errors import InvalidInputError, JointLimitError
from rcm_pin.model.mechanism import Mechanism

Accel = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]

#: The default options (a frozen dataclass: one shared instance is safe).
DEFAULTS = SimulationOptions()
#: Shortest simulated time [s]: below it the sample times are not distinct floats (a
#: subnormal duration gave an unsorted t_eval).
MIN_DURATION = 1e-9


def _plant_accel(mech: Mechanism, baumgarte: tuple[float, float]) -> Accel:
    """q̈(q, q̇, τ) of the plant, prepared once (no per-call validation)."""
    return SerialPlant(mech).accel if mech.loops is None else ClosedPlant(mech, baumgarte).accel


def initial_state(mech: Mechanism, controller: ComputedTorque) -> np.ndarray:
    """q at the reference's start (or x_T(0)): the task's closed-form inverse (other
    coordinates 0), else a bounded least-squares solve (:mod:`rcm_pin.analysis.serial_ik`)
    from the family's home configuration.

    Raises:
        InvalidInputError: a closed mechanism (pass q0), or the start is not reached.
    """
    kin = controller.kinematics
    ref = controller.reference
    start = np.asarray(ref.start if ref.start is not None else ref.evaluate(0.0)[0], dtype=float)
    if kin is None:
        raise InvalidInputError(f"{mech.name}: a closed mechanism needs q0; valid: pass q0")
    if kin.inverse is not None:
        q = np.zeros(mech.nq)
        q[kin.joints] = kin.inverse(start)
        return q
    from rcm_pin.analysis.serial_ik import TOL, solve_one

    q, err = solve_one(mech, start, controller.task_output, mech.home)
    if err > TOL:
        raise InvalidInputError(
            f"{mech.name}: the reference start {start.tolist()} is not reached from the home "
            f"configuration (error {err:.2e}); valid: pass q0"
        )
    return q


def simulate(
    plant: Mechanism,
    controller: ComputedTorque | None,
    duration: float,
    q0: np.ndarray | None = None,
    v0: np.ndarray | None = None,
    options: SimulationOptions = DEFAULTS,
) -> SimulationResult:
    """Integrate the plant under a controller (or with τ = 0 when ``controller`` is None).

    Args:
        plant: the "true" mechanism.
        controller: computed-torque controller (its model may differ from the plant).
        duration: simulated time [s].
        q0: initial coordinates; default: the task inverse at the reference's start.
        v0: initial velocities; default zero.
        options: integration and run options (:class:`SimulationOptions`: samples,
            tolerances, method, stop conditions, closure stabilisation, joint range,
            backend).

    Raises:
        InvalidInputError: duration ≤ 0, bad q0 / v0, no q0 and no way to find one, a
            plant whose motions carry no inertia (:mod:`rcm_pin.dynamics.inertia`), or
            ``"compiled"`` where it is not available (an unknown backend is refused by
            :class:`SimulationOptions`).
        JointLimitError: the run starts or gets outside the joint limits (module
            docstring), unless ``options.allow_outside_limits``.
    """
    if not (np.isfinite(duration) and duration >= MIN_DURATION):
        raise InvalidInputError(f"duration {duration} is invalid; valid: >= {MIN_DURATION:g} [s]")
    o = options
    # (refuses an uncovered pair before any other work; python_rhs is defined below)
    fast = None
    if o.backend != "python":
        fast = compiled_rhs(plant, controller, o.baumgarte, lambda t, y: python_rhs(t, y))
    n, nv = plant.nq, plant.nv
    if q0 is None:
        if controller is None:
            raise InvalidInputError("q0 is required without a controller")
        q0 = initial_state(plant, controller)
    q0 = plant.check_q(q0, "q0")
    require_inertia(plant, q0)
    bounds = [] if o.allow_outside_limits else _limit_events(plant, q0)
    v0 = np.zeros(nv) if v0 is None else plant.check_v(v0, "v0")
    accel = _plant_accel(plant, o.baumgarte)
    law = None if controller is None else controller.hot_path_law(plant)
    bar = None
    if o.progress:
        from tqdm import tqdm

        bar = tqdm(
            total=duration,
            desc=f"simulate {plant.name}",
            bar_format="{l_bar}{bar}| {n:.2f}/{total:.2f} s simulated [{elapsed}]",
        )
    shown = [0.0]
    zero = np.zeros(nv)
    tau_of = (lambda t, q, v: zero) if law is None else law.tau
    step = duration / 200

    def python_rhs(t: float, y: np.ndarray) -> np.ndarray:
        q, v = y[:n], y[n:]
        return np.concatenate((v, accel(q, v, tau_of(t, q, v))))

    integrand = python_rhs if fast is None else fast

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        if bar is not None and t > shown[0] + step:
            bar.update(round(t - shown[0], 6))
            shown[0] = t
        return integrand(t, y)

    stops: list[StopCondition] = list(scenario_source(plant).stop_events(plant))
    if controller is not None and law is not None and o.stop_error is not None:
        ctrl, task, limit, reference = (
            controller,
            controller.task_output,
            o.stop_error,
            law.reference,
        )

        def error(t: float, q: np.ndarray, v: np.ndarray) -> float:
            x = SimulationResult.task_value(plant, ctrl, q)
            return float(limit - np.linalg.norm(reference(t)[0] - x))

        unit = "m" if not task.angular.any() else "m, rad"
        stops.append((f"|e| > {o.stop_error} {unit}", error))
    stops += list(o.events)
    handlers: list[Callable[[float, np.ndarray], float]] = []
    for _, fn in stops:

        def handler(t: float, y: np.ndarray, fn: EventFunction = fn) -> float:
            return fn(t, y[:n], y[n:])

        handler.terminal = True  # type: ignore[attr-defined]
        handlers.append(handler)
    handlers += [b[0] for b in bounds]
    t_eval = None if o.samples is None else np.linspace(0.0, duration, o.samples)
    from scipy.integrate import solve_ivp  # lazy: scipy.integrate is slow to import

    start = time.perf_counter()
    sol = solve_ivp(
        integrand if bar is None else rhs,  # (no wrapper call without a progress bar)
        (0.0, duration),
        np.concatenate([q0, v0]),
        method=o.method,
        t_eval=t_eval,
        rtol=o.rtol,
        atol=o.atol,
        events=handlers or None,
        max_step=o.max_step,
    )
    wall = time.perf_counter() - start
    if bar is not None:
        bar.update(max(round(duration - shown[0], 6), 0.0))
        bar.close()
    status = "completed"
    for (_, i, side), te in zip(bounds, (sol.t_events or [])[len(stops) :]):
        if len(te):
            raise JointLimitError(_left_range(plant, float(te[0]), i, side))
    if sol.status == 1:
        status = "stopped: " + next(nm for (nm, _), te in zip(stops, sol.t_events) if len(te))
    elif sol.status < 0:
        status = f"failed: {sol.message}"
    q, v = np.ascontiguousarray(sol.y[:n].T), np.ascontiguousarray(sol.y[n:].T)
    samples_at = free_samples(len(sol.t), nv) if law is None else samples_of(fast, law, sol.t, q, v)
    result = SimulationResult.build(
        plant, controller, sol.t, q, v, status, wall, int(sol.nfev), samples_at
    )
    if o.allow_outside_limits:
        result = replace(result, outside_limits=outside_limits(plant, result.t, result.q))
    return result


#: Slack of the joint-range check [rad, m].
LIMIT_TOL = 1e-9


def _left_range(plant: Mechanism, t: float, i: int, side: str, q: float | None = None) -> str:
    """The message of a run outside the joint range (``q``: the value at the start)."""
    unit = "rad" if plant.revolute[i] else "m"
    limit = plant.upper[i] if side == "upper" else plant.lower[i]
    where = "above" if side == "upper" else "below"
    what = (
        f"starts outside its joint range at t = 0 s: {plant.coordinate_names[i]} = {q:.6g} "
        f"{unit} {where} its {side} limit {limit:.6g} {unit}"
        if q is not None
        else f"leaves its joint range at t = {t:.6g} s: {plant.coordinate_names[i]} passes "
        f"its {side} limit {limit:.6g} {unit}"
    )
    return (
        f"{plant.name} {what}; valid: a run within [{plant.lower[i]:.6g}, "
        f"{plant.upper[i]:.6g}] {unit} (the limits come from the xacro arguments, "
        "--arg KEY=VALUE), or allow_outside_limits=True (--allow-outside-limits) to "
        "continue and record it"
    )


def _limit_events(plant: Mechanism, q0: np.ndarray) -> list[tuple[Callable[..., float], int, str]]:
    """Terminal events (handler, joint, side) at every finite joint limit.

    Raises:
        JointLimitError: q0 is already outside.
    """
    out: list[tuple[Callable[..., float], int, str]] = []
    for i in range(plant.nq):
        for side, sign, limit in (("upper", 1.0, plant.upper[i]), ("lower", -1.0, plant.lower[i])):
            if not np.isfinite(limit):
                continue
            if sign * (q0[i] - limit) > LIMIT_TOL:
                raise JointLimitError(_left_range(plant, 0.0, i, side, float(q0[i])))

            def event(
                t: float, y: np.ndarray, i: int = i, s: float = sign, b: float = limit
            ) -> float:
                return LIMIT_TOL - s * (y[i] - b)

            event.terminal = True  # type: ignore[attr-defined]
            event.direction = -1  # type: ignore[attr-defined]
            out.append((event, i, side))
    return out


def outside_limits(plant: Mechanism, t: np.ndarray, q: np.ndarray) -> tuple[dict[str, Any], ...]:
    """Every joint outside its range in the samples: first time [s], the limit, the
    farthest value [rad, m]."""
    out = []
    for i, name in enumerate(plant.coordinate_names):
        for side, excess in (
            ("upper", q[:, i] - plant.upper[i]),
            ("lower", plant.lower[i] - q[:, i]),
        ):
            bad = excess > LIMIT_TOL
            if bad.any():
                k = int(np.argmax(excess))
                out.append({
                    "joint": name, "side": side, "time_s": float(t[int(np.argmax(bad))]),
                    "limit": float(plant.upper[i] if side == "upper" else plant.lower[i]),
                    "farthest": float(q[k, i]),
                })  # fmt: skip
    return tuple(out)


__all__ = ["LIMIT_TOL", "SimulationOptions", "initial_state", "outside_limits", "simulate"]
