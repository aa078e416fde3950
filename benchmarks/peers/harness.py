"""The engine of benchmarks/peers/run.py: rows of contenders, workers, interleaved rounds.

A :class:`Row` is one line of the comparison table: a case (a JSON-able dict, or a function
of a scratch folder that makes one, run in the harness's process) and its contenders.
Each :class:`Contender` is a worker module (``setup(case) -> state``,
``run_once(state) -> accuracy dict``, see ``worker.py``) run by the python of a venv:
``"project"`` is this interpreter, any other name is ``<venvs>/<name>/bin/python``. The
contenders with ``peer=True`` (the peers, or a floor) are the denominators of the row's
ratios (rcm-pin ÷ peer, at the accuracies reported beside them).

:func:`run_rows` starts one worker per contender, warms each up (``warmup`` rounds after
its ``setup``), then runs ``rounds`` interleaved rounds (A, B, A, B, ...: one timed
``run_once`` of each contender per round, so a drift of the machine's load hits all
alike) and returns the JSON document: per contender the times, their median and
[min–max], per operation in the row's unit, the last accuracy figures; per row the
ratios of the medians and their range [min_a/max_b, max_a/min_b]. A venv that does not
exist makes its contender ``"peer not installed"`` with the command that installs it; a
worker that fails (import error, exception) makes it ``"failed"`` with the message's tail.
Workers are killed with their process group when their row ends, and die with the
harness (deathsig).
"""

from __future__ import annotations

import contextlib
import json
import os
import select
import signal
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any

from rcm_pin.processes import PR_SET_PDEATHSIG, parent_death_signal

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
#: Seconds a worker may take to answer one request (a compiled OCP's first build: ~80 s).
TIMEOUT = 900.0
UNITS = {"s": 1.0, "ms": 1e3, "µs": 1e6}


def _death_signal() -> Callable[[], None]:
    """The ``preexec_fn`` that arms the parent-death signal in a worker: on Linux, libc's
    ``prctl`` resolved here, in the harness (``parent_death_signal`` looks libc up with
    ``ctypes.util.find_library``, which runs ``ldconfig``: not a thing to do between
    ``fork`` and ``exec``); elsewhere ``parent_death_signal`` itself (a no-op)."""
    if not sys.platform.startswith("linux"):
        return parent_death_signal
    import ctypes
    import ctypes.util

    prctl = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True).prctl

    def arm() -> None:
        prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)

    return arm


_ARM = _death_signal()


@dataclass(frozen=True)
class Contender:
    """One side of a row (module docstring); ``case`` is merged over the row's case."""

    label: str
    module: str
    venv: str = "project"
    peer: bool = False
    case: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class Row:
    """One line of the table: ``per`` operations per ``run_once``, shown in ``unit``."""

    key: str
    title: str
    contenders: tuple[Contender, ...]
    case: dict[str, Any] | Callable[[Path], dict[str, Any]] = field(default_factory=dict)
    per: float = 1
    unit: str = "ms"
    note: str = ""


class WorkerError(RuntimeError):
    """A worker failed, answered an error, or timed out."""


class Worker:
    """A worker process (``worker.py``) in its own session, dying with this process."""

    def __init__(self, python: str, module: str, log: Path, project: bool) -> None:
        env = dict(os.environ, RCM_PIN_PEERS_PARENT=str(os.getpid()))
        env.pop("PYTHONPATH", None)
        if project:  # the project's python imports this checkout's rcm_pin and ocp
            env["PYTHONPATH"] = os.pathsep.join(
                [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])]
            )
        self.log = log
        self._err: IO[bytes] = open(log, "wb")  # noqa: SIM115 (closed in close())
        self.proc = subprocess.Popen(
            [python, str(HERE / "worker.py"), module],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=self._err,
            env=env,
            start_new_session=True,
            preexec_fn=_ARM,  # the parent-death signal survives exec
        )
        try:
            self.hello = self._read(TIMEOUT)
        except WorkerError:
            self.close()
            raise

    def _read(self, timeout: float) -> dict[str, Any]:
        assert self.proc.stdout is not None
        ready, _, _ = select.select([self.proc.stdout], [], [], timeout)
        line = self.proc.stdout.readline() if ready else b""
        if not line:
            why = f"no answer in {timeout:g} s" if not ready else "exited"
            raise WorkerError(f"worker {why}; its stderr ends: {self.tail()}")
        reply: dict[str, Any] = json.loads(line)
        if "error" in reply:
            raise WorkerError(reply["error"].strip().splitlines()[-1] + f" ({self.log})")
        return reply

    def request(self, case: dict[str, Any], rounds: int) -> dict[str, Any]:
        """Send one request and wait for its reply."""
        assert self.proc.stdin is not None
        try:
            self.proc.stdin.write((json.dumps({"case": case, "rounds": rounds}) + "\n").encode())
            self.proc.stdin.flush()
        except BrokenPipeError:
            raise WorkerError(f"worker exited; its stderr ends: {self.tail()}") from None
        return self._read(TIMEOUT)

    def tail(self, n: int = 400) -> str:
        """The end of the worker's stderr."""
        try:
            return self.log.read_text(errors="replace")[-n:].strip()
        except OSError:
            return ""

    def close(self) -> None:
        """Ask the worker to quit; kill its process group if it does not within 5 s."""
        if self._err.closed:
            return
        if self.proc.poll() is None:
            try:
                assert self.proc.stdin is not None
                self.proc.stdin.write(b'{"quit": true}\n')
                self.proc.stdin.close()
                self.proc.wait(5.0)
            except (OSError, subprocess.TimeoutExpired):
                pass
        if self.proc.poll() is None:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(self.proc.pid, signal.SIGKILL)
            self.proc.wait()
        self._err.close()


def python_of(venv: str, venvs: Path) -> Path | None:
    """The interpreter of a venv (None: not installed)."""
    if venv == "project":
        return Path(sys.executable)
    exe = venvs / venv / "bin" / "python"
    return exe if exe.exists() else None


def _stats(times: Sequence[float], row: Row) -> dict[str, Any]:
    scale = UNITS[row.unit] / row.per
    med, lo, hi = statistics.median(times), min(times), max(times)
    return {
        "times_s": list(times),
        "median_s": med,
        "min_s": lo,
        "max_s": hi,
        f"median_{row.unit}_per_op": med * scale,
        f"range_{row.unit}_per_op": [lo * scale, hi * scale],
    }


def _ratios(row: Row, out: dict[str, dict[str, Any]]) -> list[dict[str, Any]]:
    ratios = []
    for a in (c for c in row.contenders if not c.peer):
        for b in (c for c in row.contenders if c.peer):
            ra, rb = out[a.label], out[b.label]
            entry: dict[str, Any] = {"measured": a.label, "baseline": b.label}
            if ra["status"] == rb["status"] == "ok":
                entry["ratio"] = ra["median_s"] / rb["median_s"]
                entry["range"] = [ra["min_s"] / rb["max_s"], ra["max_s"] / rb["min_s"]]
            else:
                entry["ratio"] = None
                entry["note"] = ra["status"] if ra["status"] != "ok" else rb["status"]
            ratios.append(entry)
    return ratios


def run_row(
    row: Row, rounds: int, warmup: int, venvs: Path, installs: dict[str, str], scratch: Path
) -> dict[str, Any]:
    """One row (module docstring)."""
    out: dict[str, dict[str, Any]] = {}
    doc: dict[str, Any] = {"title": row.title, "unit": row.unit, "per": row.per}
    if row.note:
        doc["note"] = row.note
    try:
        case = row.case(scratch) if callable(row.case) else dict(row.case)
    except Exception as exc:  # the row cannot be prepared: every contender fails alike
        case, doc["error"] = None, f"case preparation failed: {type(exc).__name__}: {exc}"
    workers: dict[str, Worker] = {}
    started: list[Worker] = []
    cases: dict[str, dict[str, Any]] = {}
    try:
        for c in row.contenders:
            info: dict[str, Any] = {"venv": c.venv, "module": c.module, "peer": c.peer}
            out[c.label] = info
            exe = python_of(c.venv, venvs)
            if exe is None:
                info["status"] = "peer not installed"
                cmd = installs.get(c.venv, f"make the venv {venvs / c.venv}")
                info["install"] = cmd.replace("$VENVS", str(venvs))
                continue
            if case is None:
                info["status"], info["error"] = "failed", doc["error"]
                continue
            cases[c.label] = {**case, **c.case}
            log = scratch / f"{row.key}.{len(workers)}.log"
            try:
                w = Worker(str(exe), c.module, log, c.venv == "project")
                started.append(w)
                info["python"] = w.hello.get("python")
                info["versions"] = w.hello.get("versions", {})
                first = w.request(cases[c.label], max(warmup, 1))
                info["setup_s"], info["warmup_s"] = first["setup_s"], first["times"]
                workers[c.label] = w
            except WorkerError as exc:
                info["status"], info["error"] = "failed", str(exc)
        times: dict[str, list[float]] = {label: [] for label in workers}
        stamps: dict[str, list[float]] = {label: [] for label in workers}
        for _ in range(rounds):
            for label, w in list(workers.items()):
                try:
                    reply = w.request(cases[label], 1)
                except WorkerError as exc:
                    out[label].update(status="failed", error=str(exc))
                    del workers[label]
                    continue
                times[label] += reply["times"]
                stamps[label] += reply["stamps"]
                out[label]["accuracy"] = reply["accuracy"]
        for label in workers:
            out[label].update(status="ok", stamps=stamps[label], **_stats(times[label], row))
    finally:
        for w in started:
            w.close()
    doc["contenders"] = out
    doc["ratios"] = _ratios(row, out)
    return doc


def run_rows(
    rows: Sequence[Row],
    rounds: int,
    warmup: int,
    venvs: Path,
    installs: dict[str, str],
    scratch: Path,
    progress: Callable[[str], None] | None = None,
) -> dict[str, Any]:
    """Every row in turn; the JSON document (module docstring)."""
    doc: dict[str, Any] = {
        "benchmark": "rcm-pin against its peers (benchmarks/peers)",
        "statistic": "median [min-max] over interleaved rounds (A, B, A, B, ...)",
        "ratio": "rcm-pin / peer, medians; range [min_a/max_b, max_a/min_b]",
        "rounds": rounds,
        "warmup": warmup,
        "venvs": str(venvs),
        "machine": {"cpus": os.cpu_count(), "loadavg_start": list(os.getloadavg())},
        "started": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "rows": {},
    }
    for row in rows:
        if progress is not None:
            progress(row.key)
        doc["rows"][row.key] = run_row(row, rounds, warmup, venvs, installs, scratch)
    doc["machine"]["loadavg_end"] = list(os.getloadavg())
    return doc


__all__ = ["Contender", "Row", "Worker", "WorkerError", "python_of", "run_row", "run_rows"]
