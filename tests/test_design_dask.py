"""Design sweeps on a real Dask cluster (distributed.LocalCluster on the loopback interface):
the same table as the local run, bit for bit, no design lost when a worker dies, every
finished chunk kept when the scheduler dies (exit 3), workers of other code refused."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import threading
from pathlib import Path

import distributed
import pandas as pd
import pytest

from rcm_pin.cli import main
from rcm_pin.design import Study, Vary, execute, run, store
from rcm_pin.errors import CodeMismatchError, InvalidInputError

STUDY = Study(
    "rcm_bevel",
    (Vary("q2_limit", 0.8, 1.3, 4), Vary("q3_upper", 0.1, 0.2, 3)),
    ("cone_coverage", "worst_conditioning", "cone_margin"),
)


@pytest.fixture(scope="module")
def cluster():
    with distributed.LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=None,
        silence_logs=40,
    ) as c:
        yield c


@pytest.fixture(scope="module")
def local():
    return run(STUDY, workers=1, progress=False).frame


def test_cluster_table_equals_the_local_table_bit_for_bit(cluster, local):
    remote = run(STUDY, scheduler=cluster.scheduler_address, chunk=2, progress=False)
    assert remote.computed == 12
    assert remote.frame.equals(local)


def test_a_killed_worker_loses_no_design(cluster, local):
    with distributed.Client(cluster.scheduler_address, set_as_default=False) as client:
        pids = client.run(os.getpid)
    killed: list[int] = []

    def kill_one(done: int, total: int) -> None:
        if not killed:  # after the first finished chunk, SIGKILL one worker mid-run
            pid = sorted(pids.values())[0]
            os.kill(pid, signal.SIGKILL)
            killed.append(pid)

    result = run(
        STUDY, scheduler=cluster.scheduler_address, chunk=1, progress=False, on_chunk=kill_one
    )
    assert killed
    assert result.frame["key"].is_unique and len(result.frame) == 12
    assert result.frame.equals(local)
    with distributed.Client(cluster.scheduler_address, set_as_default=False) as client:
        client.wait_for_workers(2, timeout=60)  # the nanny restarted the killed worker
        assert killed[0] not in client.run(os.getpid).values()


def test_no_scheduler_at_the_address_is_a_typed_error(monkeypatch):
    monkeypatch.setattr(execute, "CONNECT_TIMEOUT", 1.0)
    with pytest.raises(InvalidInputError) as exc:
        run(STUDY, scheduler="tcp://127.0.0.1:1", progress=False)
    assert str(exc.value).startswith("--scheduler 'tcp://127.0.0.1:1': no Dask scheduler answered")


def test_a_worker_running_other_code_is_refused_and_writes_nothing(cluster, tmp_path):
    patch = "import rcm_pin.design.evaluate as e; e._real = e.model_hash; e.model_hash = {}"
    with distributed.Client(cluster.scheduler_address, set_as_default=False) as client:
        client.run(exec, patch.format("lambda m: 'f' * 16"))  # as if its sources differed
        try:
            with pytest.raises(CodeMismatchError, match=r"runs code hash f{16} for rcm_bevel"):
                run(STUDY, tmp_path, scheduler=cluster.scheduler_address, chunk=4, progress=False)
        finally:
            client.run(exec, "import rcm_pin.design.evaluate as e; e.model_hash = e._real")
    assert store.parts(tmp_path) == []


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def test_a_lost_scheduler_keeps_every_finished_chunk_and_exits_3(tmp_path, capsys, local):
    """A scheduler and a worker of their own (processes), the scheduler SIGKILLed once the
    first chunk is in the store; a local rerun computes only the missing designs."""
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    quiet = {"env": env, "stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    scheduler = subprocess.Popen(
        [sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
         "--port", str(port), "--no-dashboard"], **quiet,
    )  # fmt: skip
    worker = subprocess.Popen(
        [sys.executable, "-m", "distributed.cli.dask_worker", address, "--nthreads", "1",
         "--no-nanny", "--no-dashboard"], **quiet,
    )  # fmt: skip
    try:
        with distributed.Client(address, timeout=60, set_as_default=False) as client:
            client.wait_for_workers(1, timeout=60)

        def kill_the_scheduler() -> None:
            while not store.parts(tmp_path) and scheduler.poll() is None:
                threading.Event().wait(0.02)
            scheduler.kill()

        killer = threading.Thread(target=kill_the_scheduler)
        killer.start()
        argv = ["sweep", "rcm_bevel", "--vary", "q2_limit=0.8:1.3:4", "--vary",
                "q3_upper=0.1:0.2:3", "--metric", "cone_coverage", "--metric",
                "worst_conditioning", "--metric", "cone_margin", "--scheduler", address,
                "--chunk", "1", "--out", str(tmp_path), "--json"]  # fmt: skip
        code = main(argv)
        killer.join()
    finally:
        scheduler.kill()
        worker.kill()
        scheduler.wait()
        worker.wait()
    error = json.loads(capsys.readouterr().out)["error"]
    assert code == 3 and error["type"] == "ComputationLostError"
    assert error["message"].startswith(f"the Dask scheduler {address} or its workers were lost")
    kept = sum(len(pd.read_parquet(p)) for p in store.parts(tmp_path))
    assert 1 <= kept < 12
    again = run(STUDY, tmp_path, workers=1, progress=False)
    assert (again.computed, again.reused) == (12 - kept, kept)
    assert again.frame.equals(local)
