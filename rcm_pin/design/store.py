"""The results of a study: Parquet (pandas + pyarrow), one row per design.

**Layout** of an output folder: ``designs.parts/<sha256>.parquet``, one file per finished
chunk, written as the chunks finish (atomic rename, named by the SHA-256 of its bytes),
and ``designs.parquet``, the whole table, written (atomic rename) at the end of a run, when
the parts are also compacted into one. The parts are what a rerun reads; a part whose bytes
do not match its name (truncated, emptied, a flipped byte) is set aside as
``<name>.damaged`` with a :class:`StoreWarning` and its designs are computed again. A folder
of an older rcm-pin with ``designs.parquet`` alone is read from that file.

Columns: ``key`` (the design's hash), ``mechanism``, ``arg.<name>`` for every xacro
argument the study sets, one column per metric, ``status`` (``ok`` or the error),
``model_hash`` (:func:`rcm_pin.design.evaluate.model_hash`) and ``feasible`` (every
constraint holds). A rerun of the same study into the same folder computes only the
designs whose (key, model_hash) is not in the table yet.
"""

from __future__ import annotations

import hashlib
import io
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from rcm_pin.design.study import Constraint
from rcm_pin.errors import InvalidInputError, require
from rcm_pin.processes import atomic_write

if TYPE_CHECKING:
    import pandas as pd
else:
    pd = require("design", "pandas")

#: File name of the table inside a study's output folder.
TABLE = "designs.parquet"
#: Folder of the per-chunk files inside a study's output folder.
PARTS = "designs.parts"


class StoreWarning(UserWarning):
    """A damaged part of a study's store, set aside (its designs are recomputed)."""


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


def _parse(path: Path, data: bytes) -> pd.DataFrame:
    try:
        frame = pd.read_parquet(io.BytesIO(data))
    except (OSError, ValueError) as exc:
        raise InvalidInputError(f"{path} is not a designs table ({exc})") from None
    if "key" not in frame or "model_hash" not in frame:
        raise InvalidInputError(f"{path} is not a designs table; valid: a folder of rcm-pin sweep")
    return frame


def parts(folder: Path) -> list[Path]:
    """The part files of the folder's store, sorted by name."""
    return sorted((Path(folder) / PARTS).glob("*.parquet"))


def read(folder: Path) -> pd.DataFrame:
    """Every row of the folder's store (its verified parts), or an empty frame.

    Raises:
        InvalidInputError: the legacy ``designs.parquet`` (read when there are no parts)
            is not a Parquet table of designs.
        MissingExtraError: pyarrow is not installed (checked before a study runs).
    """
    require("design", "pyarrow")  # pandas' Parquet engine
    folder = Path(folder)
    if not (folder / PARTS).is_dir():
        path = folder / TABLE
        return _parse(path, path.read_bytes()) if path.is_file() else pd.DataFrame()
    frames = []
    for path in parts(folder):
        data = path.read_bytes()
        try:
            if hashlib.sha256(data).hexdigest() != path.stem:
                raise InvalidInputError(f"{path}: its bytes do not match its SHA-256 name")
            frames.append(_parse(path, data))
        except InvalidInputError as exc:
            path.replace(path.with_suffix(".damaged"))
            warnings.warn(f"{exc}; set aside, its designs are computed again", StoreWarning, 2)
    frames = [f for f in frames if not f.empty]
    if not frames:
        return pd.DataFrame()
    frame = pd.concat(frames, ignore_index=True).drop_duplicates(["key", "model_hash"])
    return frame.sort_values(["key", "model_hash"], kind="stable").reset_index(drop=True)


def write_part(folder: Path, rows: list[dict[str, Any]] | pd.DataFrame) -> Path | None:
    """Commit rows (a finished chunk) to the store as one part file (None: no rows)."""
    frame = rows if isinstance(rows, pd.DataFrame) else pd.DataFrame(rows)
    if frame.empty:
        return None
    buffer = io.BytesIO()
    frame.to_parquet(buffer, index=False)
    data = buffer.getvalue()
    (Path(folder) / PARTS).mkdir(exist_ok=True)
    return atomic_write(Path(folder) / PARTS / f"{hashlib.sha256(data).hexdigest()}.parquet", data)


def latest(frame: pd.DataFrame, code: str, metrics: tuple[str, ...]) -> pd.DataFrame:
    """One row per key: the one under ``code`` with every metric first, sorted by key."""
    if frame.empty:
        return frame
    have = [m for m in metrics if m in frame]
    complete = frame[have].notna().all(axis=1) if len(have) == len(metrics) else False
    complete = complete | (frame["status"] != "ok")
    score = -(2 * (frame["model_hash"] == code).astype(int) + complete.astype(int))
    ranked = frame.assign(_score=score).sort_values(["key", "_score", "model_hash"], kind="stable")
    return ranked.drop_duplicates("key").drop(columns="_score").reset_index(drop=True)


def compact(folder: Path, frame: pd.DataFrame) -> Path:
    """Replace the store's parts by one holding ``frame`` and write the whole table
    (:data:`TABLE`); returns the table's path. The new part is committed before the old
    ones go, so a kill at any point loses nothing."""
    old = parts(folder)
    frame = frame.drop(columns="feasible", errors="ignore")
    new = write_part(folder, frame)
    for path in old:
        if path != new:
            path.unlink(missing_ok=True)
    return write(folder, frame.assign(feasible=frame["status"] == "ok") if len(frame) else frame)


def done(frame: pd.DataFrame, metrics: tuple[str, ...]) -> set[tuple[str, str]]:
    """(key, model_hash) of the designs whose every metric is already in the table."""
    if frame.empty or any(m not in frame for m in metrics):
        return set()
    complete = frame[list(metrics)].notna().all(axis=1) | (frame["status"] != "ok")
    return set(zip(frame["key"][complete], frame["model_hash"][complete], strict=True))


def write(folder: Path, frame: pd.DataFrame) -> Path:
    """Write the table (index-free, atomic rename) and return its path."""
    require("design", "pyarrow")  # pandas' Parquet engine
    buffer = io.BytesIO()
    frame.to_parquet(buffer, index=False)
    return atomic_write(Path(folder) / TABLE, buffer.getvalue())


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


__all__ = [
    "PARTS",
    "TABLE",
    "StoreWarning",
    "compact",
    "done",
    "latest",
    "merge",
    "pareto",
    "parts",
    "read",
    "table",
    "write",
    "write_part",
]
