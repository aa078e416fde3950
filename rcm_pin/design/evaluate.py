"""Evaluating designs: load each design's mechanism, compute its metrics, one row each.

:func:`evaluate_chunk` is the unit of work a process or a Dask worker runs: a top-level
function of plain data (picklable), deterministic (the metrics are seeded), so a chunk
gives bit-identical rows wherever it runs. A design that cannot be built (e.g. a limit
pair reversed by the sweep) is a row with ``status`` holding the typed error's message and
NaN metrics, never a crash of the sweep.
"""

from __future__ import annotations

import hashlib
import inspect
from functools import lru_cache
from pathlib import Path
from typing import Any

from rcm_pin.catalog import load
from rcm_pin.catalog.table import get_entry
from rcm_pin.design.metrics import metric_source
from rcm_pin.design.study import Design
from rcm_pin.errors import RcmPinError
from rcm_pin.model.resources import xacro_dir

#: Status of a design whose metrics were computed.
OK = "ok"


@lru_cache(maxsize=32)
def model_hash(mechanism: str) -> str:
    """Hash (16 hex digits) of what a design's figures depend on: every xacro source, the
    family's package and the model layer's sources."""
    family = type(get_entry(mechanism).family)
    family_file = Path(inspect.getfile(family))
    family_dir = family_file.parent if family_file.name == "__init__.py" else family_file
    files = sorted(xacro_dir().glob("*.xacro"))
    files += sorted(family_dir.rglob("*.py")) if family_dir.is_dir() else [family_dir]
    files += sorted((Path(__file__).parents[1] / "model").glob("*.py"))
    digest = hashlib.sha256()
    for f in files:
        digest.update(f.name.encode())
        digest.update(f.read_bytes())
    return digest.hexdigest()[:16]


def evaluate(design: Design, metrics: tuple[str, ...]) -> dict[str, Any]:
    """One row: the design's key, mechanism, arguments, metric values and status."""
    row: dict[str, Any] = {"key": design.key, "mechanism": design.mechanism}
    row.update({f"arg.{k}": float(v) for k, v in design.args})
    try:
        mech = load(design.mechanism, trusted=False, **dict(design.args))
        available = metric_source(mech.family).metrics()
        for name in metrics:
            row[name] = float(available[name].evaluate(mech))
        row["status"] = OK
    except RcmPinError as exc:
        row.update({name: float("nan") for name in metrics if name not in row})
        row["status"] = f"{type(exc).__name__}: {exc}"
    row["model_hash"] = model_hash(design.mechanism)
    return row


def evaluate_chunk(designs: list[Design], metrics: tuple[str, ...]) -> list[dict[str, Any]]:
    """Rows of a chunk of designs, in the chunk's order."""
    return [evaluate(d, metrics) for d in designs]


__all__ = ["OK", "evaluate", "evaluate_chunk", "model_hash"]
