"""benchmarks/peers/run.py with fake contenders: the protocol, interleaved rounds, medians,
ratios, the JSON document written atomically, a missing venv and a failing worker."""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import pytest

PEERS = Path(__file__).resolve().parents[1] / "benchmarks" / "peers"
sys.path.insert(0, str(PEERS))

import harness  # noqa: E402
import run  # noqa: E402
from harness import Contender, Row  # noqa: E402

#: A fake worker module: sleeps ``case["sleep"]`` s per run and reports its call count.
FAKE = """
import time

def setup(case):
    return {"sleep": case["sleep"], "calls": 0, "pid": __import__("os").getpid()}

def run_once(state):
    state["calls"] += 1
    time.sleep(state["sleep"])
    print("noise on stdout must not break the protocol")
    return {"calls": state["calls"], "error_m": 1e-12, "pid": state["pid"]}
"""
BROKEN = "def setup(case):\n    return None\n\ndef run_once(state):\n    raise ValueError('boom')\n"


@pytest.fixture()
def modules(tmp_path: Path) -> dict[str, str]:
    (tmp_path / "fake.py").write_text(FAKE)
    (tmp_path / "broken.py").write_text(BROKEN)
    return {"fake": str(tmp_path / "fake.py"), "broken": str(tmp_path / "broken.py")}


def _rows(modules: dict[str, str]) -> list[Row]:
    return [
        Row(
            "fake",
            "a fake row",
            (
                Contender("ours", modules["fake"], case={"sleep": 0.02}),
                Contender("theirs", modules["fake"], peer=True, case={"sleep": 0.01}),
                Contender("absent", modules["fake"], venv="no_such_venv", peer=True),
                Contender("broken", modules["broken"], peer=True),
            ),
            case={"sleep": 1.0},
            per=2,
        )
    ]


def test_harness_runs_interleaved_rounds_and_writes_the_document(
    modules: dict[str, str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys
) -> None:
    written: list[Path] = []
    real = run.atomic_write

    def spy(path: Path, data: bytes) -> Path:
        written.append(Path(path))
        return real(path, data)

    monkeypatch.setattr(run, "atomic_write", spy)
    out = tmp_path / "out" / "peers.json"
    out.parent.mkdir()
    installs = {"no_such_venv": "python -m venv $VENVS/no_such_venv"}
    doc = run.main(
        ["--venvs", str(tmp_path / "venvs"), "--rounds", "4", "--json", str(out)],
        rows=_rows(modules),
        installs=installs,
    )
    assert written == [out] and json.loads(out.read_text()) == doc
    assert [p.name for p in out.parent.iterdir()] == ["peers.json"]  # no temporary left
    row = doc["rows"]["fake"]
    ours, theirs = row["contenders"]["ours"], row["contenders"]["theirs"]
    assert ours["status"] == theirs["status"] == "ok"
    assert len(ours["times_s"]) == len(theirs["times_s"]) == 4
    assert ours["accuracy"]["calls"] == 1 + 4  # one warm-up round, then the timed ones
    assert ours["accuracy"]["pid"] != theirs["accuracy"]["pid"] != os.getpid()
    # interleaved: ours, theirs, ours, theirs, ...
    merged = sorted([(t, "o") for t in ours["stamps"]] + [(t, "t") for t in theirs["stamps"]])
    assert "".join(k for _, k in merged) == "ot" * 4
    assert 0.02 <= ours["median_s"] < 0.5 and 0.01 <= theirs["median_s"] < 0.5
    assert ours["min_s"] <= ours["median_s"] <= ours["max_s"]
    assert ours["median_ms_per_op"] == pytest.approx(1e3 * ours["median_s"] / 2)
    absent = row["contenders"]["absent"]
    assert absent["status"] == "peer not installed"
    assert absent["install"] == f"python -m venv {tmp_path / 'venvs'}/no_such_venv"
    broken = row["contenders"]["broken"]
    assert broken["status"] == "failed" and "boom" in broken["error"]
    ratios = {r["baseline"]: r for r in row["ratios"]}
    assert set(ratios) == {"theirs", "absent", "broken"}
    r = ratios["theirs"]
    assert r["ratio"] == pytest.approx(ours["median_s"] / theirs["median_s"])
    assert r["range"][0] <= r["ratio"] <= r["range"][1]
    assert ratios["absent"]["ratio"] is None
    assert ratios["absent"]["note"] == "peer not installed"
    table = capsys.readouterr().out
    assert "| a fake row | ours |" in table and "peer not installed" in table
    assert absent["install"] in table


def test_a_worker_whose_module_does_not_import_fails_its_contender_only(
    modules: dict[str, str], tmp_path: Path
) -> None:
    (tmp_path / "bad_import.py").write_text("import no_such_module_anywhere\n")
    row = Row(
        "r",
        "r",
        (
            Contender("ours", modules["fake"]),
            Contender("theirs", str(tmp_path / "bad_import.py"), peer=True),
        ),
        case={"sleep": 0.0},
    )
    doc = harness.run_row(row, 2, 0, tmp_path, {}, tmp_path)
    assert doc["contenders"]["ours"]["status"] == "ok"
    theirs = doc["contenders"]["theirs"]
    assert theirs["status"] == "failed" and "no_such_module_anywhere" in theirs["error"]
    assert doc["ratios"][0]["ratio"] is None


def test_a_worker_exits_when_its_parent_is_not_the_harness(tmp_path: Path) -> None:
    import subprocess

    env = dict(os.environ, RCM_PIN_PEERS_PARENT="1")  # not our PID: the harness "died"
    proc = subprocess.run(
        [sys.executable, str(PEERS / "worker.py"), str(tmp_path / "x.py")],
        env=env, capture_output=True, timeout=30, check=False,
    )  # fmt: skip
    assert proc.returncode == 1 and proc.stdout == b""


def test_the_registry_lists_every_row_with_existing_modules() -> None:
    import rows

    assert rows.ROWS and len({r.key for r in rows.ROWS}) == len(rows.ROWS)
    for r in rows.ROWS:
        assert any(not c.peer for c in r.contenders)
        for c in r.contenders:
            assert (PEERS / c.module).is_file(), c.module
            assert c.venv == "project" or c.venv in rows.INSTALLS


SLOW = """
import os, time

def setup(case):
    with open(case["pid_file"], "w") as f:
        f.write(str(os.getpid()))
    return None

def run_once(state):
    time.sleep(60)
    return {}
"""


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    try:  # a zombie waiting for its new parent to reap it is dead too
        return Path(f"/proc/{pid}/status").read_text().split("State:")[1].split()[0] != "Z"
    except (OSError, IndexError):
        return False


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="PR_SET_PDEATHSIG")
def test_workers_die_when_the_harness_is_killed(tmp_path: Path) -> None:
    import signal
    import subprocess
    import time

    (tmp_path / "slow.py").write_text(SLOW)
    pid_file = tmp_path / "worker.pid"
    driver = (
        f"import sys; sys.path.insert(0, {str(PEERS)!r}); import run; "
        "from harness import Contender, Row; "
        f"run.main(['--rounds', '1'], rows=[Row('slow', 'slow', (Contender('a', "
        f"{str(tmp_path / 'slow.py')!r}),), case={{'pid_file': {str(pid_file)!r}}})], "
        "installs={})"
    )
    harness_proc = subprocess.Popen([sys.executable, "-c", driver])
    try:
        deadline = time.monotonic() + 60
        while not pid_file.exists() or not pid_file.read_text():
            assert time.monotonic() < deadline and harness_proc.poll() is None
            time.sleep(0.05)
        worker = int(pid_file.read_text())
        assert _alive(worker)
    finally:
        harness_proc.send_signal(signal.SIGKILL)
        harness_proc.wait()
    deadline = time.monotonic() + 10
    while _alive(worker) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not _alive(worker)


def test_a_standalone_script_runs_through_the_adapter(tmp_path: Path) -> None:
    (tmp_path / "standalone.py").write_text(
        "def run(rounds):\n    return {'median_s': 0.5, 'accuracy': {'err': 1e-9}, 'x': [1]}\n"
    )
    row = Row(
        "s", "s", (Contender("theirs", "script_adapter.py", peer=True,
                             case={"script": str(tmp_path / "standalone.py")}),
                   Contender("ours", "script_adapter.py",
                             case={"script": str(tmp_path / "standalone.py")})),
    )  # fmt: skip
    doc = harness.run_row(row, 2, 1, tmp_path, {}, tmp_path)
    assert doc["contenders"]["theirs"]["accuracy"] == {"median_s": 0.5, "err": 1e-9}
    assert doc["ratios"][0]["ratio"] > 0
