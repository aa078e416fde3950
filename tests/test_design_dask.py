"""Design sweeps on a real Dask cluster (distributed.LocalCluster on the loopback interface):
the same table as the local run, bit for bit, and no design lost when a worker dies."""

from __future__ import annotations

import os
import signal

import distributed
import pytest

from rcm_pin.design import Study, Vary, execute, run
from rcm_pin.errors import InvalidInputError

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
