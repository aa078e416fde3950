"""Crash consistency of ``rcm-pin reproduce`` (the runner on the slow fake sections of
tests/fake_slow.py, driven by tests/fake_reproduce.py): SIGKILL at seeded random points then
a rerun gives the files and the cache of an uninterrupted run, bit for bit; one run per
folder; a damaged cache entry is recomputed with a warning; no pool process outlives a
killed run.

Compared: every file of the output folder (the sections' files, ``.cache/*.json``) and
``report.md`` without its last part, "Run time per section", which holds run times and
whether each section came from the cache (what differs between a rerun and a first run by
design). Excluded: ``.lock`` (the lock file; empty between runs).
"""

from __future__ import annotations

import json
import os
import random
import subprocess
import sys
from pathlib import Path

import fake_reproduce
import fake_slow
import pytest
from crash import descendants, files, kill_when, survivors, wait_for

from rcm_pin.cli import main
from rcm_pin.errors import FolderBusyError
from rcm_pin.processes import lock_holder
from rcm_pin.report import writer
from rcm_pin.report.cache import CacheWarning

DRIVER = Path(fake_reproduce.__file__)
ROOT = Path(__file__).resolve().parents[1]


def driver(out: Path, jobs: int = 2, **env: str) -> subprocess.Popen:
    environ = {**os.environ, "PYTHONPATH": str(ROOT), **env}
    return subprocess.Popen(
        [sys.executable, str(DRIVER), str(out), str(jobs)],
        env=environ, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip


def content(out: Path) -> dict[str, bytes]:
    """The compared files (module docstring)."""
    found = files(out, skip=lambda name: name == ".lock")
    report = found.pop("report.md", b"")
    found["report.md"] = report.split(b"## Run time per section")[0]
    return found


def rerun(out: Path, monkeypatch: pytest.MonkeyPatch, jobs: int = 1) -> None:
    monkeypatch.setattr(writer, "SECTIONS", fake_reproduce.FAKE)
    writer.write_report(out, jobs=jobs, quiet=True)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """An uninterrupted run's files."""
    out = tmp_path_factory.mktemp("reference")
    proc = driver(out)
    assert proc.wait() == 0, proc.stderr.read() if proc.stderr else ""
    return content(out)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_killed_runs_then_a_rerun_give_the_uninterrupted_files(
    seed, tmp_path, monkeypatch, reference
):
    rng = random.Random(seed)
    killed = 0
    for _ in range(2):  # two kills at random points, then a rerun to the end
        entries = len(list((tmp_path / ".cache").glob("*.json"))) + rng.randrange(0, 3)
        proc = driver(tmp_path)
        family: set[int] = set()

        def ready(proc=proc, entries=entries, family=family) -> bool:
            family |= descendants(proc.pid)
            return len(list((tmp_path / ".cache").glob("*.json"))) >= entries

        killed += kill_when(proc, ready, rng.uniform(0.0, 0.4))
        assert not survivors(family), "pool processes outlived the killed run"
    assert killed  # at least one kill landed mid-run
    rerun(tmp_path, monkeypatch)
    assert content(tmp_path) == reference
    assert not (tmp_path / ".work").exists()


def test_a_second_run_on_the_folder_is_refused_naming_the_holder(tmp_path, monkeypatch, reference):
    first = driver(tmp_path)
    assert wait_for(first, lambda: lock_holder(tmp_path) == first.pid)
    with pytest.raises(FolderBusyError) as exc:
        rerun(tmp_path, monkeypatch)
    assert f"is in use by another run (PID {first.pid}); valid: wait until it ends" in str(
        exc.value
    )
    assert first.wait() == 0
    assert content(tmp_path) == reference  # the first run is whole: nothing of the second
    rerun(tmp_path, monkeypatch)  # the lock is free again
    assert content(tmp_path) == reference


@pytest.mark.parametrize("damage", ["truncated", "emptied", "byte-flipped"])
def test_a_damaged_cache_entry_is_recomputed_with_a_warning(
    damage, tmp_path, monkeypatch, reference
):
    rerun(tmp_path, monkeypatch)
    entry = tmp_path / ".cache" / "slow_c.json"
    data = entry.read_bytes()
    if damage == "truncated":
        data = data[: len(data) // 2]
    elif damage == "emptied":
        data = b""
    else:  # a published value of the markdown: "measured 6.0 mm" -> "measured 7.0 mm"
        at = data.index(b"measured 6.0") + len(b"measured ")
        data = data[:at] + b"7" + data[at + 1 :]
        assert json.loads(data)["section"]["body"].count("measured 7.0") == 1
    entry.write_bytes(data)
    fake_slow_calls = []
    monkeypatch.setattr(fake_slow.time, "sleep", lambda s: fake_slow_calls.append(s))
    with pytest.warns(CacheWarning, match=r"slow_c\.json: damaged"):
        rerun(tmp_path, monkeypatch)
    assert len(fake_slow_calls) == 3  # one section (three files) computed again
    assert content(tmp_path) == reference


def test_no_pool_process_outlives_a_killed_run(tmp_path):
    pids = tmp_path / "pids"
    pids.mkdir()
    proc = driver(tmp_path / "out", FAKE_SLOW_PIDS=str(pids))
    (tmp_path / "out").mkdir(exist_ok=True)
    family: set[int] = set()

    def ready() -> bool:
        family.update(descendants(proc.pid))
        return len(list(pids.glob("*.pid"))) == 2

    assert kill_when(proc, ready, 0.0)
    workers = {int(p.stem) for p in pids.glob("*.pid")}
    assert workers <= family and len(family) >= 3  # the fork server and two workers at least
    assert survivors(family) == set()


def test_the_cli_exits_2_naming_the_run_that_holds_the_folder(tmp_path, capsys):
    hold = "import sys, time; from rcm_pin.processes import folder_lock\n"
    hold += "with folder_lock(sys.argv[1]):\n    print('held', flush=True); time.sleep(60)"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    holder = subprocess.Popen(
        [sys.executable, "-c", hold, str(tmp_path)], env=env, stdout=subprocess.PIPE, text=True
    )
    try:
        assert holder.stdout is not None and holder.stdout.readline() == "held\n"
        code = main(["reproduce", "--out", str(tmp_path), "--only", "position", "--json"])
    finally:
        holder.kill()
        holder.wait()
    error = json.loads(capsys.readouterr().out)["error"]
    assert code == 2 and error == {
        "type": "FolderBusyError",
        "message": f"--out {tmp_path} is in use by another run (PID {holder.pid}); valid: wait "
        "until it ends, or another folder",
    }
    assert sorted(p.name for p in tmp_path.iterdir()) == [".lock"]  # nothing computed
