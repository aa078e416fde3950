"""The results table of a study: Parquet (pandas + pyarrow), one row per design.

Columns: ``key`` (the design's hash), ``mechanism``, ``arg.<name>`` for every xacro
argument the study sets, one column per metric, ``status`` (``ok`` or the error),
``model_hash`` (:func:`rcm_pin.design.evaluate.model_hash`) and ``feasible`` (every
constraint holds). A rerun of the same study into the same folder computes only the
designs whose (key, model_hash) is not in the table yet.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from rcm_pin.design.study import Constraint
from rcm_pin.errors import InvalidInputError, require

if TYPE_CHECKING:
    import pandas as pd
else:
    pd = require("design", "pandas")

#: File name of the table inside a study's output folder.
TABLE = "designs.parquet"


def table(rows: list[dict[str, Any]], constraints: tuple[Constraint, ...] = ()) -> pd.DataFrame:
    """Rows -> DataFrame sorted by key (the order a rerun or a cluster reproduces)."""
    frame = pd.DataFrame(rows)
    if frame.empty:
        return frame
    feasible = frame["status"] == "ok"
    for c in constraints:
        feasible &= frame[c.metric].map(c.holds).astype(bool)
    frame["feasible"] = feasible
    return frame.sort_values("key", kind="stable").reset_index(drop=True)


def read(folder: Path) -> pd.DataFrame:
    """The folder's table, or an empty frame.

    Raises:
        InvalidInputError: the file exists but is not a Parquet table of designs.
        MissingExtraError: pyarrow is not installed (checked before a study runs: a run
            with an output folder reads it first and writes it at the end).
    """
    require("design", "pyarrow")  # pandas' Parquet engine
    path = Path(folder) / TABLE
    if not path.is_file():
        return pd.DataFrame()
    try:
        frame = pd.read_parquet(path)
    except (OSError, ValueError) as exc:
        raise InvalidInputError(f"{path} is not a designs table ({exc})") from None
    if "key" not in frame or "model_hash" not in frame:
        raise InvalidInputError(f"{path} is not a designs table; valid: a folder of rcm-pin sweep")
    return frame


def done(frame: pd.DataFrame, metrics: tuple[str, ...]) -> set[tuple[str, str]]:
    """(key, model_hash) of the designs whose every metric is already in the table."""
    if frame.empty or any(m not in frame for m in metrics):
        return set()
    complete = frame[list(metrics)].notna().all(axis=1) | (frame["status"] != "ok")
    return set(zip(frame["key"][complete], frame["model_hash"][complete], strict=True))


def write(folder: Path, frame: pd.DataFrame) -> Path:
    """Write the table (index-free) and return its path."""
    path = Path(folder) / TABLE
    require("design", "pyarrow")  # pandas' Parquet engine
    frame.to_parquet(path, index=False)
    return path


def merge(old: pd.DataFrame, new: pd.DataFrame) -> pd.DataFrame:
    """Old rows replaced by new rows of the same key, sorted by key."""
    if old.empty:
        return new
    if new.empty:
        return old
    keep = old[~old["key"].isin(new["key"])]
    out = pd.concat([keep, new], ignore_index=True)
    return out.sort_values("key", kind="stable").reset_index(drop=True)


def pareto(frame: pd.DataFrame, goals: Mapping[str, str]) -> np.ndarray:
    """Boolean mask of the feasible designs no other feasible design dominates."""
    ok = frame["feasible"].to_numpy(bool)
    values = np.column_stack(
        [frame[m].to_numpy(float) * (-1.0 if g == "max" else 1.0) for m, g in goals.items()]
    )  # every objective minimised
    mask = np.zeros(len(frame), dtype=bool)
    idx = np.flatnonzero(ok)
    for i in idx:
        others = values[idx]
        dominated = np.any(np.all(others <= values[i], axis=1) & np.any(others < values[i], axis=1))
        mask[i] = not dominated
    return mask


__all__ = ["TABLE", "done", "merge", "pareto", "read", "table", "write"]
