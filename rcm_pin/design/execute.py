"""Running a study: chunks of designs on local processes or on a Dask cluster.

Work is split into chunks of ``chunk`` designs (default 8: a few seconds of work for the
mechanisms of the catalogue, ~0.4-0.8 s a design, mostly rendering its xacro), so that
scheduling costs little next to the work and a lost worker loses one chunk only.

* local (default): ``workers`` processes (default: every core) through
  ``concurrent.futures.ProcessPoolExecutor`` (forked from a fork server that has
  imported rcm_pin), or the calling process for ``workers=1``;
* Dask: ``scheduler="tcp://HOST:PORT"`` sends the chunks to that cluster's workers
  (``distributed.Client.map`` with retries); a worker that dies mid-run has its chunks
  rescheduled by the scheduler, so every design is computed and appears once.

Rows are sorted by design key, so the table is the same, bit for bit, however it ran.

With an output folder a run holds the folder's lock (:func:`rcm_pin.processes.folder_lock`:
a second run on it exits with :class:`~rcm_pin.errors.FolderBusyError` naming the holder's
PID), commits each finished chunk to the store as it comes (:mod:`.store`), and computes
only the designs whose (key, code hash) the store lacks; so a run killed at any point, or
whose Dask scheduler is lost (:class:`~rcm_pin.errors.ComputationLostError`), loses at most
its unfinished chunks, and a rerun computes only those.
"""

from __future__ import annotations

import asyncio
import contextlib
import os
import time
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import CancelledError, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from tqdm import tqdm

from rcm_pin.design import store
from rcm_pin.design.evaluate import evaluate_chunk, model_hash
from rcm_pin.design.scheduler import check_scheduler
from rcm_pin.design.study import Design, Study, designs, validate
from rcm_pin.errors import ComputationLostError, InvalidInputError, require
from rcm_pin.processes import folder_lock, process_pool, remove_temporaries

if TYPE_CHECKING:
    import pandas as pd
else:
    pd = require("design", "pandas")

#: Designs per task.
CHUNK = 8
#: Seconds to wait for a Dask scheduler to answer.
CONNECT_TIMEOUT = 10.0
#: Task retries on a Dask cluster (a worker lost mid-task).
RETRIES = 3


@dataclass(frozen=True)
class SweepResult:
    """A finished study.

    Attributes:
        frame: every design of the study (its table rows, sorted by key).
        computed: designs computed in this run.
        reused: designs taken from the folder's table (a rerun).
        seconds: wall time of the computation [s].
        path: the Parquet table written (None without an output folder).
    """

    frame: pd.DataFrame
    computed: int
    reused: int
    seconds: float
    path: Path | None


def chunks(items: list[Design], size: int) -> list[list[Design]]:
    """Consecutive chunks of ``size`` designs."""
    if size < 1:
        raise InvalidInputError(f"chunk size {size}; valid: >= 1")
    return [items[i : i + size] for i in range(0, len(items), size)]


def _code(parts: list[list[Design]]) -> str | None:
    return model_hash(parts[0][0].mechanism) if parts and parts[0] else None


def _local(
    parts: list[list[Design]], metrics: tuple[str, ...], workers: int
) -> Iterator[list[dict[str, Any]]]:
    if workers == 1 or len(parts) <= 1:  # no process pool for a single task
        for part in parts:
            yield evaluate_chunk(part, metrics)
        return
    code = _code(parts)
    with process_pool(workers, ["rcm_pin.design.evaluate"]) as pool:
        futures = [pool.submit(evaluate_chunk, part, metrics, code) for part in parts]
        try:
            for future in as_completed(futures):
                yield future.result()
        except BaseException:  # stopped (an error, Ctrl-C): drop the chunks not started
            for future in futures:
                future.cancel()
            raise


def _dask(
    parts: list[list[Design]], metrics: tuple[str, ...], scheduler: str
) -> Iterator[list[dict[str, Any]]]:
    distributed = require("design", "distributed")
    Client, dask_completed = distributed.Client, distributed.as_completed

    check_scheduler(scheduler)  # a non-Dask server: a typed error, not a huge allocation
    try:
        client = Client(scheduler, timeout=CONNECT_TIMEOUT, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as exc:
        raise InvalidInputError(
            f"--scheduler {scheduler!r}: no Dask scheduler answered ({exc}); valid: the "
            "address of a running scheduler, e.g. tcp://127.0.0.1:8786"
        ) from None
    code, done = _code(parts), 0
    lost = (
        distributed.comm.CommClosedError,
        distributed.client.FutureCancelledError,
        distributed.KilledWorker,
        CancelledError,
        asyncio.CancelledError,
        TimeoutError,
    )
    try:
        futures = client.map(
            evaluate_chunk, parts, metrics=metrics, expected=code, retries=RETRIES, pure=False
        )
        for future in dask_completed(futures, loop=client.loop):
            rows = future.result()
            done += 1
            yield rows
    except lost as exc:  # a design's own error is a row; these are the cluster's
        raise ComputationLostError(
            f"the Dask scheduler {scheduler} or its workers were lost after {done} of "
            f"{len(parts)} chunks ({type(exc).__name__}: {' '.join(str(exc).split())}); the "
            "finished chunks are kept in --out; valid: rerun the same study once the cluster "
            "is back (it computes only the missing designs)"
        ) from None
    finally:
        with contextlib.suppress(Exception):  # a lost scheduler: nothing left to close
            client.close(timeout=2)


def compute(
    todo: list[Design],
    metrics: tuple[str, ...],
    scheduler: str | None = None,
    workers: int = 1,
    chunk: int = CHUNK,
    progress: bool | None = None,
    on_chunk: Callable[[int, int], None] | None = None,
    sink: Callable[[list[dict[str, Any]]], None] | None = None,
) -> list[dict[str, Any]]:
    """Rows of the given designs (in completion order), on processes or a Dask cluster;
    with ``sink``, each finished chunk's rows go to it instead (none are returned)."""
    parts = chunks(todo, chunk)
    source: Iterable[list[dict[str, Any]]] = (
        _dask(parts, metrics, scheduler) if scheduler else _local(parts, metrics, workers)
    )
    show = progress if progress is not None else bool(os.isatty(2))
    rows: list[dict[str, Any]] = []
    count = 0
    with tqdm(total=len(todo), disable=not show, unit="design") as bar:
        for part_rows in source:
            if sink is not None:
                sink(part_rows)
            else:
                rows.extend(part_rows)
            count += len(part_rows)
            bar.update(len(part_rows))
            if on_chunk is not None:
                on_chunk(count, len(todo))
    return rows


def check_workers(workers: int | None) -> int:
    """The worker count (default: every core).

    Raises:
        InvalidInputError: fewer than one.
    """
    workers = (os.cpu_count() or 1) if workers is None else workers
    if workers < 1:
        raise InvalidInputError(f"{workers} workers; valid: >= 1")
    return workers


def run(
    study: Study,
    out: Path | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    chunk: int = CHUNK,
    progress: bool | None = None,
    on_chunk: Callable[[int, int], None] | None = None,
) -> SweepResult:
    """Compute a study (validated first) and return its table.

    Args:
        out: folder of the Parquet table; designs already in it are not recomputed.
        scheduler: a Dask scheduler address; None runs on local processes.
        workers: local processes (default: every core; 1: in this process).
        chunk: designs per task.
        progress: a progress bar (default: when stderr is a terminal).
        on_chunk: called as ``on_chunk(done, total)`` [designs] after each finished chunk.

    Raises:
        InvalidInputError: a bad study (:func:`rcm_pin.design.study.validate`), a missing
            output folder, no scheduler at the address, a bad worker count.
        FolderBusyError: another run holds the output folder's lock.
        ComputationLostError: the Dask scheduler or its workers were lost mid-run (the
            finished chunks are kept in ``out``).
        CodeMismatchError: a worker's code hash differs from this process's.
    """
    study = validate(study)
    metrics = tuple(dict.fromkeys([*study.metrics, *(c.metric for c in study.constraints)]))
    if out is not None and not Path(out).is_dir():
        raise InvalidInputError(f"--out {out}: no such folder; valid: an existing folder")
    workers = check_workers(workers)
    with folder_lock(Path(out)) if out is not None else contextlib.nullcontext():
        if out is not None:  # temporaries of a killed run: no other run is writing (lock)
            for folder in (Path(out), Path(out) / store.PARTS):
                remove_temporaries(folder)
        old = store.read(Path(out)) if out is not None else pd.DataFrame()
        have = store.done(old, metrics)
        todo_all = designs(study)
        mhash = model_hash(study.mechanism)
        todo = [d for d in todo_all if (d.key, mhash) not in have]
        start = time.perf_counter()

        def commit(rows: list[dict[str, Any]]) -> None:
            store.write_part(Path(out), rows)  # type: ignore[arg-type]

        sink = commit if out is not None else None
        rows = compute(todo, metrics, scheduler, workers, chunk, progress, on_chunk, sink)
        seconds = time.perf_counter() - start
        if out is not None:
            merged = store.latest(store.read(Path(out)), mhash, metrics)
            path: Path | None = store.compact(Path(out), merged)
        else:
            merged, path = store.table(rows), None
    keys = {d.key for d in todo_all}
    mine = merged[merged["key"].isin(keys)] if not merged.empty else merged
    records = mine.drop(columns="feasible", errors="ignore").to_dict("records")
    frame = store.table(records, study.constraints)
    return SweepResult(frame, len(todo), len(todo_all) - len(todo), seconds, path)


__all__ = ["CHUNK", "SweepResult", "check_workers", "chunks", "compute", "run"]
