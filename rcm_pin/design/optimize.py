"""Multi-objective design search with optuna's NSGA-II, evaluated like a sweep.

Why optuna: it is maintained, its ask-and-tell interface lets each generation be evaluated
as one batch of designs on the same executor as a sweep (local processes or a Dask
cluster), its NSGA-II sampler handles several objectives and constraints (a Pareto front,
not a weighted sum), and it is seeded. pymoo has the same algorithms but drives the
evaluation loop itself; cma is single-objective.

The objectives are the study's metrics (each with its goal, ``max`` or ``min``); the
constraints ``metric >= value`` / ``metric <= value`` are passed to NSGA-II as
``value − metric ≤ 0`` / ``metric − value ≤ 0`` (``Trial.set_constraint``). A design that
cannot be built is a failed trial. Designs are rounded to 12 significant digits, as in a sweep.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from rcm_pin.design import store
from rcm_pin.design.evaluate import OK
from rcm_pin.design.execute import CHUNK, check_workers, compute
from rcm_pin.design.study import Constraint, Design, Study, validate
from rcm_pin.errors import InvalidInputError, require

if TYPE_CHECKING:
    import optuna
    import pandas as pd
else:
    optuna = require("design", "optuna")


@dataclass(frozen=True)
class OptimizeResult:
    """Every evaluated design (its table, with a ``pareto`` column) and the counts."""

    frame: pd.DataFrame
    trials: int
    generations: int


def _violations(row: dict[str, Any], constraints: tuple[Constraint, ...]) -> list[float]:
    """``value − metric`` (for ``>=``) or ``metric − value`` (``<=``): feasible when ≤ 0."""
    out = []
    for c in constraints:
        x = row[c.metric]
        out.append(c.value - x if c.op == ">=" else x - c.value)
    return out


def optimize(
    study: Study,
    trials: int = 64,
    population: int = 16,
    scheduler: str | None = None,
    workers: int | None = None,
    chunk: int = CHUNK,
    progress: bool | None = False,
) -> OptimizeResult:
    """NSGA-II over the study's varied arguments (module docstring).

    Args:
        study: the arguments' ranges (``Vary.n`` is ignored), objectives (metrics),
            constraints, seed.
        trials: designs evaluated in all.
        population: designs per generation (one batch on the executor).

    Raises:
        InvalidInputError: a bad study, or trial / population counts below 2.
    """
    study = validate(study)
    if trials < 2 or population < 2:
        raise InvalidInputError(
            f"trials {trials}, population {population}; valid: both >= 2 (NSGA-II breeds pairs)"
        )
    workers = check_workers(workers)
    goals = {m: study.available[m].goal for m in study.metrics}
    metrics = tuple(dict.fromkeys([*study.metrics, *(c.metric for c in study.constraints)]))
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    sampler = optuna.samplers.NSGAIISampler(population_size=population, seed=study.seed)
    search = optuna.create_study(
        directions=["maximize" if g == "max" else "minimize" for g in goals.values()],
        sampler=sampler,
    )
    space: dict[str, optuna.distributions.BaseDistribution] = {
        v.arg: optuna.distributions.FloatDistribution(v.lo, v.hi) for v in study.vary
    }
    rows: list[dict[str, Any]] = []
    generations = 0
    while len(rows) < trials:
        batch = [search.ask(space) for _ in range(min(population, trials - len(rows)))]
        todo = []
        for trial in batch:
            args = dict(study.fixed)
            args.update({k: f"{trial.params[k]:.12g}" for k in space})
            todo.append(Design(study.mechanism, tuple(sorted(args.items()))))
        results = {r["key"]: r for r in compute(todo, metrics, scheduler, workers, chunk, progress)}
        for trial, design in zip(batch, todo, strict=True):
            row = results[design.key]
            rows.append(row)
            values = [row[m] for m in goals]
            if row["status"] != OK or not all(math.isfinite(x) for x in values):
                search.tell(trial, state=optuna.trial.TrialState.FAIL)
                continue
            for c, violation in zip(
                study.constraints, _violations(row, study.constraints), strict=True
            ):
                trial.set_constraint(f"{c.metric}{c.op}{c.value:g}", violation)
            search.tell(trial, values)
        generations += 1
    frame = store.table(rows, study.constraints).drop_duplicates("key").reset_index(drop=True)
    frame["pareto"] = store.pareto(frame, goals) if len(frame) else np.zeros(0, bool)
    return OptimizeResult(frame, len(rows), generations)


__all__ = ["OptimizeResult", "optimize"]
