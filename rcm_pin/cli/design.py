"""``rcm-pin sweep | optimize``: design studies over a mechanism's xacro arguments."""

from __future__ import annotations

import argparse
import contextlib
import io
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

from rcm_pin.cli._common import emit, output_path, parse_xacro_args

if TYPE_CHECKING:
    from rcm_pin.design import Study

#: Samplers of ``--sampler`` (rcm_pin.design.study.SAMPLERS; the design layer, pandas and
#: optuna are imported only when a study runs, so that every other command starts fast).
SAMPLERS = ("grid", "lhs", "random")


def _study_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("name", metavar="NAME", help="a xacro mechanism of the catalogue")
    p.add_argument(
        "--vary", action="append", required=True, metavar="ARG=LO:HI[:N]",
        help="a xacro argument to vary (repeatable; N values on a grid, default 5)",
    )  # fmt: skip
    p.add_argument("--metric", action="append", required=True, metavar="M", help="repeatable")
    p.add_argument("--constraint", action="append", default=[], metavar="M>=V", help="M>=V or M<=V")
    p.add_argument("--arg", action="append", metavar="KEY=VALUE", help="a fixed xacro argument")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--scheduler", metavar="ADDR", help="Dask scheduler, e.g. tcp://HOST:8786")
    p.add_argument("--workers", type=int, help="local processes (default: every core)")
    p.add_argument("--chunk", type=int, default=8, help="designs per task (default 8)")
    p.add_argument("--out", type=Path, help="folder of the table and the plots")
    p.add_argument("--json", action="store_true", help="print one JSON document")


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommands of this module."""
    p = sub.add_parser("sweep", help="evaluate a grid / Latin hypercube / random set of designs")
    _study_options(p)
    p.add_argument("--sampler", choices=SAMPLERS, default="grid")
    p.add_argument("--samples", type=int, default=0, help="designs of lhs / random")
    p.set_defaults(func=cmd_sweep)
    p = sub.add_parser("optimize", help="NSGA-II (optuna) over the varied arguments")
    _study_options(p)
    p.add_argument("--trials", type=int, default=64, help="designs evaluated in all")
    p.add_argument("--population", type=int, default=16, help="designs per generation")
    p.set_defaults(func=cmd_optimize)


def _study(args: argparse.Namespace, sampler: str = "grid", samples: int = 0) -> Study:
    from rcm_pin.design import Study
    from rcm_pin.design.study import parse_constraint, parse_vary

    if args.scheduler and args.workers:
        from rcm_pin.errors import InvalidInputError

        raise InvalidInputError("--scheduler and --workers conflict; valid: one of them")
    if args.scheduler:  # before any work: a non-Dask server must not reach distributed
        from rcm_pin.design.scheduler import check_scheduler

        check_scheduler(args.scheduler)
    varies = tuple(parse_vary(v) for v in args.vary)
    if sampler != "grid" or all(v.n <= 1000 for v in varies):  # else: the per-argument bound
        check_size(math.prod(v.n for v in varies) if sampler == "grid" else samples, "designs")
    return Study(
        args.name,
        varies,
        tuple(args.metric),
        fixed=tuple(sorted(parse_xacro_args(args.arg).items())),
        constraints=tuple(parse_constraint(c) for c in args.constraint),
        sampler=sampler,  # type: ignore[arg-type]
        samples=samples,
        seed=args.seed,
    )


#: Wall time of one design on one core [s] (execute's docstring: 0.4-0.8 s, mostly the
#: rendering of its xacro).
SECONDS_PER_DESIGN = 0.6


def check_size(count: int, what: str) -> None:
    """Refuse more designs than :data:`rcm_pin.design.study.MAX_DESIGNS` while parsing
    (exact integers: a grid's product never wraps around).

    Raises:
        InvalidInputError: the count, its time estimate and the bound.
    """
    from rcm_pin.design.study import MAX_DESIGNS
    from rcm_pin.errors import InvalidInputError

    if count > MAX_DESIGNS:
        hours = count * SECONDS_PER_DESIGN / 3600
        raise InvalidInputError(
            f"{count} {what} would take about {hours:.3g} h on one core (about "
            f"{SECONDS_PER_DESIGN:g} s a design); valid: at most {MAX_DESIGNS} {what}"
        )


def _records(frame: Any) -> list[dict[str, Any]]:
    return [dict(r) for r in frame.to_dict("records")]


def cmd_sweep(args: argparse.Namespace) -> int:
    """``rcm-pin sweep``: every design's metrics; the table (and maps) into ``--out``."""
    from rcm_pin.design import run
    from rcm_pin.design.plots import metric_map

    out = output_path(args.out, "--out", directory=True) if args.out else None
    study = _study(args, args.sampler, args.samples)
    res = run(study, out, args.scheduler, args.workers, args.chunk)
    figures = []
    if out is not None and len(study.vary) == 2 and args.sampler == "grid":
        for m in study.metrics:
            x, y = study.vary[0].arg, study.vary[1].arg
            figures.append(str(metric_map(res.frame, x, y, m, out / f"map_{m}.png")))
    payload = {
        "mechanism": study.mechanism,
        "designs": len(res.frame),
        "computed": res.computed,
        "reused": res.reused,
        "seconds": res.seconds,
        "table": None if res.path is None else str(res.path),
        "figures": figures,
        "rows": _records(res.frame),
    }
    cols = [c for c in res.frame.columns if c not in ("key", "mechanism", "model_hash")]
    text = res.frame[cols].to_string(index=False)
    text += f"\n{res.computed} computed, {res.reused} reused in {res.seconds:.1f} s"
    emit(args, payload, text)
    return 0


def cmd_optimize(args: argparse.Namespace) -> int:
    """``rcm-pin optimize``: the Pareto front of the metrics (NSGA-II)."""
    from rcm_pin.design.optimize import optimize
    from rcm_pin.design.plots import pareto_front
    from rcm_pin.errors import require
    from rcm_pin.processes import atomic_write, folder_lock  # not at CLI start-up

    out = output_path(args.out, "--out", directory=True) if args.out else None
    if out is not None:
        require("design", "pyarrow")  # the table is written after the search: check first
    check_size(args.trials, "trials")
    study = _study(args)
    with folder_lock(out) if out is not None else contextlib.nullcontext():  # one run per --out
        res = optimize(
            study, args.trials, args.population, args.scheduler, args.workers, args.chunk
        )
        front = res.frame[res.frame["pareto"]]
        figures = []
        if out is not None:
            buffer = io.BytesIO()
            res.frame.to_parquet(buffer, index=False)
            atomic_write(out / "optimize.parquet", buffer.getvalue())
            if len(study.metrics) >= 2:
                a, b = study.metrics[:2]
                figures.append(str(pareto_front(res.frame, a, b, out / "pareto.png")))
    payload = {
        "mechanism": study.mechanism,
        "trials": res.trials,
        "generations": res.generations,
        "figures": figures,
        "pareto": _records(front),
    }
    cols = [c for c in front.columns if c.startswith("arg.") or c in study.metrics]
    emit(args, payload, front[cols].to_string(index=False))
    return 0
