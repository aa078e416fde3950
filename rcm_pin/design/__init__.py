"""Design studies: sweep a mechanism's xacro arguments against its family's metrics.

* :mod:`.study`: what to vary, the metrics and constraints, the samplers, validation;
* :mod:`.evaluate`: one design -> one row (load, metrics), the unit of work;
* :mod:`.execute`: chunks on local processes or a Dask cluster, reruns that skip done work;
* :mod:`.store`: the Parquet table, the Pareto front;
* :mod:`.optimize`: multi-objective search with optuna (NSGA-II);
* :mod:`.plots`: metric maps over two arguments, the Pareto front.
"""

from rcm_pin.design.execute import SweepResult, run
from rcm_pin.design.study import Constraint, Design, Study, Vary, designs, validate

__all__ = ["Constraint", "Design", "Study", "SweepResult", "Vary", "designs", "run", "validate"]
