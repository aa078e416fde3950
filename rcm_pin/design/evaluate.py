"""Evaluating designs: load each design's mechanism, compute its metrics, one row each.

:func:`evaluate_chunk` is the unit of work a process or a Dask worker runs: a top-level
function of plain data (picklable), deterministic (the metrics are seeded), so a chunk
gives bit-identical rows wherever it runs. A design that cannot be built (e.g. a limit
pair reversed by the sweep) is a row with ``status`` holding the typed error's message and
NaN metrics, never a crash of the sweep.
"""

from __future__ import annotations

import os
import socket
from typing import Any

from rcm_pin.catalog import load
from rcm_pin.design.metrics import metric_source
from rcm_pin.design.provenance import code_hash
from rcm_pin.design.study import Design
from rcm_pin.errors import CodeMismatchError, RcmPinError

#: Status of a design whose metrics were computed.
OK = "ok"


def model_hash(mechanism: str) -> str:
    """The code hash of the mechanism's rows (:func:`rcm_pin.design.provenance.code_hash`:
    the sources its metrics import, the xacro files, the package versions)."""
    return code_hash(mechanism)


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


def evaluate_chunk(
    designs: list[Design], metrics: tuple[str, ...], expected: str | None = None
) -> list[dict[str, Any]]:
    """Rows of a chunk of designs, in the chunk's order.

    Args:
        expected: the client's code hash of the chunk's mechanism; this process checks its
            own before computing anything.

    Raises:
        CodeMismatchError: this process's code hash is not ``expected`` (other sources or
            package versions than the client's): it refuses the chunk.
    """
    if expected is not None and designs:
        mine = model_hash(designs[0].mechanism)
        if mine != expected:
            raise CodeMismatchError(
                f"worker {socket.gethostname()}:{os.getpid()} runs code hash {mine} for "
                f"{designs[0].mechanism}, the client {expected}; valid: workers with the "
                "client's rcm-pin sources and package versions (restart them)"
            )
    return [evaluate(d, metrics) for d in designs]


__all__ = ["OK", "evaluate", "evaluate_chunk", "model_hash"]
