"""Design studies: sweep a mechanism's xacro arguments against its family's metrics.

* :mod:`.study`: what to vary, the metrics and constraints, the samplers, validation;
* :mod:`.evaluate`: one design -> one row (load, metrics), the unit of work;
* :mod:`.execute`: chunks on local processes or a Dask cluster, reruns that skip done work;
* :mod:`.store`: the Parquet table, the Pareto front;
* :mod:`.optimize`: multi-objective search with optuna (NSGA-II);
* :mod:`.plots`: metric maps over two arguments, the Pareto front.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from rcm_pin.lazy import lazy_exports

if TYPE_CHECKING:
    from rcm_pin.design.execute import SweepResult, run
    from rcm_pin.design.study import (
        Constraint,
        Design,
        Study,
        Vary,
        designs,
        parse_constraint,
        validate,
    )

#: The re-exports, imported on first access (PEP 562): a study is described with
#: :mod:`.study` alone; running it (:mod:`.execute`) needs the ``[design]`` extra.
_LAZY = {
    "Constraint": "study",
    "Design": "study",
    "Study": "study",
    "SweepResult": "execute",
    "Vary": "study",
    "designs": "study",
    "parse_constraint": "study",
    "run": "execute",
    "validate": "study",
}


__getattr__, __dir__ = lazy_exports(__name__, _LAZY)


__all__ = [
    "Constraint",
    "Design",
    "Study",
    "SweepResult",
    "Vary",
    "designs",
    "parse_constraint",
    "run",
    "validate",
]
