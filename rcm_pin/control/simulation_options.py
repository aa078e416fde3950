"""The integration and run options of :func:`~rcm_pin.control.simulate.simulate`, validated once."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from rcm_pin.control.backends import check_backend
from rcm_pin.control.capabilities import StopCondition
from rcm_pin.errors import InvalidInputError

#: Most output samples of a run (memory: the result keeps each of its arrays per sample).
MAX_SAMPLES = 1_000_000


@dataclass(frozen=True)
class SimulationOptions:
    """How :func:`~rcm_pin.control.simulate.simulate` integrates and when it stops.

    Attributes:
        samples: output samples on a uniform grid over [0, duration] [-]; None: the
            solver's own steps.
        rtol: relative tolerance of ``solve_ivp`` [-].
        atol: absolute tolerance of ``solve_ivp`` [rad, m, rad/s, m/s].
        method: ``solve_ivp`` method (``"DOP853"``, ``"RK45"``, …).
        stop_error: stop when |x_T − x| exceeds this [m, rad] (diverging runs); None: no
            such stop.
        progress: show a tqdm bar over simulated time.
        max_step: largest solver step [s].
        events: further terminal stop conditions (description, g(t, q, v)); the run
            stops where g crosses 0.
        baumgarte: closure stabilisation of a closed plant (ω [rad/s], ζ [-]).
        allow_outside_limits: continue outside the joint limits and record it
            (``outside_limits`` of the result) instead of stopping.
        backend: ``"python"`` or ``"compiled"`` (:mod:`rcm_pin.control.backends`).

    Raises:
        InvalidInputError: an unknown backend (whether ``"compiled"`` covers a plant and
            controller is checked by ``simulate``), or ``samples`` outside 2 to
            :data:`MAX_SAMPLES`.
    """

    samples: int | None = 1001
    rtol: float = 1e-10
    atol: float = 1e-12
    method: str = "DOP853"
    stop_error: float | None = 0.5
    progress: bool = False
    max_step: float = np.inf
    events: Sequence[StopCondition] = ()
    baumgarte: tuple[float, float] = (50.0, 1.0)
    allow_outside_limits: bool = False
    backend: str = "python"

    def __post_init__(self) -> None:
        check_backend(self.backend)
        if self.samples is not None and not 2 <= self.samples <= MAX_SAMPLES:
            raise InvalidInputError(
                f"samples {self.samples}; valid: 2 to {MAX_SAMPLES} (memory: the result keeps "
                "each of its arrays per sample), or None for the solver's steps"
            )


__all__ = ["MAX_SAMPLES", "SimulationOptions"]
