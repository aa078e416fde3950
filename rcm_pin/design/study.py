"""A design study: the xacro arguments to vary, the metrics, the constraints, the sampler.

A *design* is a catalogue mechanism plus xacro arguments. A *study* varies some arguments
over ranges (``Vary``), keeps others fixed, and asks the family's metrics
(:func:`rcm_pin.design.metrics.metric_source`) of every design. Samplers:

* ``grid``: the Cartesian product of ``n`` equally spaced values per argument (ends
  included);
* ``lhs``: a Latin hypercube of ``samples`` designs (scipy.stats.qmc, seeded);
* ``random``: ``samples`` uniform designs (seeded).

:func:`validate` refuses a bad study before any work (empty or reversed range, unknown
argument or metric, a range leaving the argument's documented bounds, a bad constraint)
with a typed error that lists what is valid.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import re
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from rcm_pin.catalog.table import get_entry
from rcm_pin.design.metrics import metric_source
from rcm_pin.errors import InvalidInputError, UnknownMechanismError, XacroArgumentError
from rcm_pin.interfaces.design import DesignMetric
from rcm_pin.model.xacro_ranges import ArgSpec, declared_specs

Sampler = Literal["grid", "lhs", "random"]
SAMPLERS = ("grid", "lhs", "random")
#: Largest number of designs in one study.
MAX_DESIGNS = 1_000_000
_CONSTRAINT = re.compile(r"^\s*(?P<metric>\w+)\s*(?P<op><=|>=)\s*(?P<value>[-+.\deE]+)\s*$")


@dataclass(frozen=True)
class Vary:
    """One varied argument: ``lo..hi`` [the argument's unit], ``n`` values on a grid."""

    arg: str
    lo: float
    hi: float
    n: int = 5


@dataclass(frozen=True)
class Constraint:
    """``metric <= value`` or ``metric >= value``: designs that break it are infeasible."""

    metric: str
    op: str
    value: float

    def holds(self, x: float) -> bool:
        """Whether a metric value satisfies the constraint (NaN never does)."""
        return bool(x <= self.value) if self.op == "<=" else bool(x >= self.value)


@dataclass(frozen=True)
class Design:
    """A mechanism and its xacro arguments (sorted (name, text) pairs)."""

    mechanism: str
    args: tuple[tuple[str, str], ...]

    @property
    def key(self) -> str:
        """A stable hash of the design (16 hex digits)."""
        text = json.dumps([self.mechanism, self.args])
        return hashlib.sha256(text.encode()).hexdigest()[:16]


@dataclass(frozen=True)
class Study:
    """What to vary and what to measure (module docstring)."""

    mechanism: str
    vary: tuple[Vary, ...]
    metrics: tuple[str, ...]
    fixed: tuple[tuple[str, str], ...] = ()
    constraints: tuple[Constraint, ...] = ()
    sampler: Sampler = "grid"
    samples: int = 0
    seed: int = 0
    available: dict[str, DesignMetric] = field(default_factory=dict, compare=False, repr=False)


def parse_vary(text: str) -> Vary:
    """``ARG=LO:HI:N`` (grid) or ``ARG=LO:HI`` -> :class:`Vary`.

    Raises:
        InvalidInputError: another form, or numbers that do not parse.
    """
    m = re.fullmatch(r"\s*(\w+)\s*=\s*([^:]+):([^:]+)(?::(\d+))?\s*", text)
    try:
        if m is None:
            raise ValueError
        return Vary(m[1], float(m[2]), float(m[3]), int(m[4]) if m[4] else 5)
    except ValueError:
        raise InvalidInputError(
            f"--vary {text!r}; valid: ARG=LO:HI:N (N values on a grid) or ARG=LO:HI"
        ) from None


def parse_constraint(text: str) -> Constraint:
    """``METRIC>=VALUE`` or ``METRIC<=VALUE`` -> :class:`Constraint`."""
    m = _CONSTRAINT.match(text)
    try:
        if m is None:
            raise ValueError
        return Constraint(m["metric"], m["op"], float(m["value"]))
    except ValueError:
        raise InvalidInputError(
            f"--constraint {text!r}; valid: METRIC>=VALUE or METRIC<=VALUE"
        ) from None


def _check_range(v: Vary, spec: ArgSpec, source: str) -> None:
    if not (np.isfinite(v.lo) and np.isfinite(v.hi)) or v.lo >= v.hi:
        raise InvalidInputError(f"--vary {v.arg}={v.lo:g}:{v.hi:g} is empty; valid: LO < HI")
    if not 1 <= v.n <= 1000:
        raise InvalidInputError(f"--vary {v.arg}: {v.n} grid values; valid: 1..1000")
    if spec.kind != "number":
        raise XacroArgumentError(
            f"{v.arg} of {source} is not a number ({spec.valid()}); valid: a numeric argument"
        )
    for end in (v.lo, v.hi):
        if not spec.contains(end):
            raise XacroArgumentError(
                f"--vary {v.arg}={v.lo:g}:{v.hi:g} leaves the argument's range in {source}; "
                f"valid: {spec.valid()}"
            )


def validate(study: Study) -> Study:
    """The study with its metrics resolved, or a typed error before any work.

    Raises:
        UnknownMechanismError: not a xacro mechanism of the catalogue.
        XacroArgumentError: an unknown argument, or a range outside its documented bounds.
        InvalidInputError: empty range, unknown metric or constraint, bad sampler or count.
    """
    entry = get_entry(study.mechanism)
    if not entry.xacro:
        raise UnknownMechanismError(
            f"{study.mechanism} has no xacro arguments to vary; valid: a xacro mechanism of "
            "the catalogue (`rcm-pin list`)"
        )
    specs = declared_specs(entry.xacro_path)
    if not study.vary:
        raise InvalidInputError("the study varies nothing; valid: at least one --vary ARG=LO:HI")
    for name in [v.arg for v in study.vary] + [k for k, _ in study.fixed]:
        if name not in specs or name in entry.fixed_args:
            free = sorted(set(specs) - set(entry.fixed_args))
            raise XacroArgumentError(
                f"unknown xacro argument {name!r} for {study.mechanism}; valid: {', '.join(free)}"
            )
    for v in study.vary:
        _check_range(v, specs[v.arg], entry.xacro)
    available = metric_source(entry.family).metrics()
    if not available:
        raise InvalidInputError(f"{study.mechanism}'s family has no design metrics")
    wanted = list(study.metrics) + [c.metric for c in study.constraints]
    for name in wanted or ["(none)"]:
        if name not in available:
            raise InvalidInputError(
                f"unknown metric {name!r} for {study.mechanism}; valid: {', '.join(available)}"
            )
    if study.sampler not in SAMPLERS:
        raise InvalidInputError(f"sampler {study.sampler!r}; valid: {', '.join(SAMPLERS)}")
    count = _count(study)
    if not 1 <= count <= MAX_DESIGNS:
        raise InvalidInputError(f"{count} designs; valid: 1..{MAX_DESIGNS}")
    return Study(**{**study.__dict__, "available": available})


def _count(study: Study) -> int:
    if study.sampler == "grid":
        return int(np.prod([v.n for v in study.vary]))
    return study.samples


def unit_points(study: Study) -> np.ndarray:
    """Designs as points of the unit cube (N, d), in a fixed order."""
    d = len(study.vary)
    if study.sampler == "grid":
        axes = [np.linspace(0.0, 1.0, v.n) if v.n > 1 else np.array([0.5]) for v in study.vary]
        return np.array(list(itertools.product(*axes)), dtype=float).reshape(-1, d)
    if study.sampler == "lhs":
        from scipy.stats import qmc  # lazy: scipy.stats takes ~0.3 s to import

        return np.asarray(qmc.LatinHypercube(d=d, seed=study.seed).random(study.samples))
    return np.random.default_rng(study.seed).random((study.samples, d))


def designs(study: Study) -> list[Design]:
    """Every design of the study (validated first)."""
    study = validate(study)
    lo = np.array([v.lo for v in study.vary])
    hi = np.array([v.hi for v in study.vary])
    values = lo + unit_points(study) * (hi - lo)
    out = []
    for row in values:
        args = dict(study.fixed)
        args.update({v.arg: f"{x:.12g}" for v, x in zip(study.vary, row, strict=True)})
        out.append(Design(study.mechanism, tuple(sorted(args.items()))))
    return out


__all__ = [
    "SAMPLERS",
    "Constraint",
    "Design",
    "Study",
    "Vary",
    "designs",
    "parse_constraint",
    "parse_vary",
    "unit_points",
    "validate",
]
